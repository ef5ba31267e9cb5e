// The devices a device spec names (one per in-process device, worker process or worker address),
// what rtDeviceGetAttribute reports for them, and how they are instantiated. libtessera installs
// the factories: worker/core's in-process device, and worker processes over gRPC
// (scheduler/transport); tessera::api_core alone has neither and is tested with fake devices.
#ifndef TESSERA_API_SRC_DEVICE_TABLE_H_
#define TESSERA_API_SRC_DEVICE_TABLE_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "device_spec.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"

namespace tessera::api {

struct DeviceDesc {
  DeviceSpecEntry::Type type = DeviceSpecEntry::Type::kInproc;
  std::string name;     // "Tessera inproc (CPU)"
  std::string address;  // "inproc", "local:2/0", "10.0.0.2:5000", "unix:/tmp/w.sock"
  int local_index = 0;  // kLocal: which of the entry's N workers
  int local_count = 0;  // kLocal: N, which shares the machine's cores among them
};

// One device per entry; local:N gives N devices.
std::vector<DeviceDesc> ExpandDevices(const std::vector<DeviceSpecEntry>& entries);

// With nothing configured: one local worker process per core ("local:<cores>"), or "inproc"
// when no worker transport is installed or this process cannot use it (said once on stderr).
std::string DefaultDeviceSpec();

// Parses TESSERA_DEVICES (or the default) and expands it.
absl::StatusOr<std::vector<DeviceDesc>> DevicesFromEnvironment();

// The device list rtDevice* functions describe, independent of any context: TESSERA_DEVICES or
// the default (RT_ERROR_NO_DEVICE when the spec is bad), and one of them by ordinal
// (RT_ERROR_INVALID_VALUE when out of range).
absl::StatusOr<std::vector<DeviceDesc>> GlobalDevices();
absl::StatusOr<DeviceDesc> GlobalDevice(int ordinal);

// Copies at most `size` bytes of `s` (size > 0) into `out`, always NUL-terminated, as OptiX
// returns strings such as RT_DEVICE_ATTRIBUTE_NAME.
void CopyString(const std::string& s, size_t size, char* out);

// rtDeviceGetAttribute for one device; `size` must match the attribute's type.
absl::Status GetDeviceAttribute(const DeviceDesc& device, RTdeviceattribute attribute, RTsize size,
                                void* out);

// RT_ERROR_NOT_SUPPORTED for worker devices when no worker factory is installed or this process
// cannot use it.
absl::Status CheckInstantiable(const DeviceDesc& device);

// Creates an in-process device. libtessera installs the real one (worker/core) at load time;
// without it, creating a device fails with RT_ERROR_NO_DEVICE.
using InprocDeviceFactory = std::unique_ptr<Device> (*)(int num_threads);
void SetInprocDeviceFactory(InprocDeviceFactory factory);

// Creates a worker device: spawns a worker process for `local:N` entries, connects to HOST:PORT
// and unix:PATH ones. libtessera installs it at load time (api/src/worker_factory.cc).
using WorkerDeviceFactory = absl::StatusOr<std::unique_ptr<Device>> (*)(const DeviceDesc& device);
void SetWorkerDeviceFactory(WorkerDeviceFactory factory);

// Whether this process can use worker devices at all (libtessera installs it with the worker
// transport): not in a child forked without exec from a process that had used them.
using WorkerTransportCheck = absl::Status (*)();
void SetWorkerTransportCheck(WorkerTransportCheck check);

// What a running worker (HOST:PORT, unix:PATH) says about itself when asked.
struct WorkerFacts {
  int threads = 0;
  uint64_t total_memory = 0;  // bytes; 0 when it did not say
  int clock_khz = 0;          // 0 when it did not say
};
// Asks a running worker (libtessera installs it with the worker transport): UNAVAILABLE, naming
// the address, when it cannot be reached.
using WorkerProbe = absl::StatusOr<WorkerFacts> (*)(const DeviceDesc& device);
void SetWorkerProbe(WorkerProbe probe);

// `num_threads` sizes in-process devices; a worker sizes its own pool (DeviceDesc::local_count).
absl::StatusOr<std::unique_ptr<Device>> CreateDevice(const DeviceDesc& device, int num_threads);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_DEVICE_TABLE_H_
