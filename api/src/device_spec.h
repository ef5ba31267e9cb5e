// Device specs (docs/devices.md "Device specs"): a comma-separated list, the same in --devices and
// TESSERA_DEVICES. `inproc` is a device inside the host process, `local:N` N worker processes the
// host spawns, `HOST:PORT` a running worker, `unix:PATH` a worker on a Unix socket.
#ifndef TESSERA_API_SRC_DEVICE_SPEC_H_
#define TESSERA_API_SRC_DEVICE_SPEC_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::api {

struct DeviceSpecEntry {
  enum class Type { kInproc, kLocal, kTcp, kUnix };
  Type type = Type::kInproc;
  int count = 1;     // kLocal: worker processes
  std::string host;  // kTcp, without IPv6 brackets
  int port = 0;      // kTcp
  std::string path;  // kUnix

  // Canonical spelling: "inproc", "local:4", "10.0.0.2:5000", "[::1]:5000", "unix:/tmp/w.sock".
  std::string ToString() const;
};

// The spec used when TESSERA_DEVICES is unset or empty and worker processes cannot be made
// (tessera::api_core without libtessera's transport); otherwise the default is one local worker
// process per core (DefaultDeviceSpec in device_table.h).
inline constexpr char kDefaultDeviceSpec[] = "inproc";

// Parses a whole spec; the error message quotes the offending entry and says what was expected.
absl::StatusOr<std::vector<DeviceSpecEntry>> ParseDeviceSpec(absl::string_view spec);

// TESSERA_DEVICES, or `fallback` when it is unset or blank.
std::string DeviceSpecFromEnvironment(const std::string& fallback = kDefaultDeviceSpec);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_DEVICE_SPEC_H_
