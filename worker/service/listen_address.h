// The address a worker listens on: "HOST:PORT", "[IPV6]:PORT" or "unix:PATH" (the device-spec
// spellings, DESIGN.md "Devices").
#ifndef TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_
#define TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_

#include <string>

#include "absl/strings/string_view.h"

namespace tessera::worker {

// True when only this machine can connect: unix sockets, localhost, 127.0.0.0/8 and ::1. A worker
// runs the code its host sends, so anything else needs TLS and a token (docs/security.md).
bool IsLoopbackAddress(absl::string_view listen);

// `listen` with `bound_port` in place of its port (port 0 asks for an ephemeral one); unix
// addresses are returned unchanged.
std::string ResolvedListenAddress(absl::string_view listen, int bound_port);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_
