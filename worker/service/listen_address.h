// The address a worker listens on: "HOST:PORT", "[IPV6]:PORT" or "unix:PATH" (the device-spec
// spellings, docs/devices.md "Device specs").
#ifndef TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_
#define TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_

#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"

namespace tessera::worker {

// OK when `listen` is an address of one of those spellings: a port from 0 to 65535, a unix path of
// 1 to 107 bytes (what a socket address holds). INVALID_ARGUMENT naming it otherwise: gRPC would
// take a missing port for 443, wrap a port past 65535 and bind an empty path where no host can
// connect, so the worker would listen somewhere other than where it was told.
absl::Status CheckListenAddress(absl::string_view listen);

// OK unless `listen` is a unix socket that a live process listens on. gRPC replaces a socket file
// at the path it binds, which suits a stale socket left by a worker that was killed, but leaves a
// running worker unreachable while both report listening there. FAILED_PRECONDITION naming it.
absl::Status CheckUnixSocketNotInUse(absl::string_view listen);

// OK when the worker can bind `listen` (checked with a socket of its own, closed again): a unix
// socket's directory exists and can be written, a TCP address resolves and its port is free.
// FAILED_PRECONDITION naming the address and the system's reason otherwise, so that the worker
// exits 2 with one line instead of gRPC's log and a guess.
absl::Status CheckCanBind(absl::string_view listen);

// True when only this machine can connect: unix sockets, localhost, 127.0.0.0/8 and ::1. A worker
// runs the code its host sends, so anything else needs TLS and a token (docs/security.md).
bool IsLoopbackAddress(absl::string_view listen);

// `listen` with `bound_port` in place of its port (port 0 asks for an ephemeral one); unix
// addresses are returned unchanged.
std::string ResolvedListenAddress(absl::string_view listen, int bound_port);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_LISTEN_ADDRESS_H_
