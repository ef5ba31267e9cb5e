#include "device_table.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "status.h"
#include "system_info.h"
#include "tessera/scheduler/log.h"

namespace tessera::api {
namespace {

std::atomic<InprocDeviceFactory> g_inproc_factory{nullptr};
std::atomic<WorkerDeviceFactory> g_worker_factory{nullptr};
std::atomic<WorkerProbe> g_worker_probe{nullptr};
std::atomic<WorkerTransportCheck> g_worker_check{nullptr};

absl::Status WorkerTransportUsable() {
  WorkerTransportCheck check = g_worker_check.load();
  return check == nullptr ? absl::OkStatus() : check();
}

absl::Status SizeError(const char* attribute, RTsize size, size_t expected) {
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat(attribute, " needs size ", expected, ", got ", size));
}

template <typename T>
absl::Status Write(const char* attribute, RTsize size, void* out, T value) {
  if (size != sizeof(T)) return SizeError(attribute, size, sizeof(T));
  std::memcpy(out, &value, sizeof(T));
  return absl::OkStatus();
}

bool OnThisMachine(const DeviceDesc& device) {
  return device.type == DeviceSpecEntry::Type::kInproc ||
         device.type == DeviceSpecEntry::Type::kLocal;
}

// A running worker's facts, asked for when an attribute needs them; without the transport (the
// core library alone) nothing can be asked and the facts are zero.
absl::StatusOr<WorkerFacts> AskWorker(const DeviceDesc& device) {
  WorkerProbe probe = g_worker_probe.load();
  if (probe == nullptr) return WorkerFacts{};
  absl::StatusOr<WorkerFacts> facts = probe(device);
  if (!facts.ok()) {
    // The transport's message names the worker's address and why it did not answer. A worker
    // that answered with a refusal of the token is an authentication failure, as in a launch.
    const absl::StatusCode code = facts.status().code();
    return RtError(
        code == absl::StatusCode::kUnauthenticated || code == absl::StatusCode::kPermissionDenied
            ? RT_ERROR_AUTHENTICATION_FAILED
            : RT_ERROR_CONNECTION_FAILED,
        facts.status().message());
  }
  return facts;
}

// An attribute that describes the device's machine: this one's for in-process and local:N
// devices (`local()`), what a running worker says of its own (`fact`) for the others.
template <typename T, typename Local>
absl::Status MachineFact(const char* attribute, const DeviceDesc& device, RTsize size, void* out,
                         T WorkerFacts::*fact, Local local) {
  if (size != sizeof(T)) return SizeError(attribute, size, sizeof(T));
  if (OnThisMachine(device)) return Write<T>(attribute, size, out, local());
  TS_ASSIGN_OR_RETURN(WorkerFacts facts, AskWorker(device));
  return Write<T>(attribute, size, out, facts.*fact);
}

}  // namespace

std::vector<DeviceDesc> ExpandDevices(const std::vector<DeviceSpecEntry>& entries) {
  std::vector<DeviceDesc> devices;
  for (const DeviceSpecEntry& e : entries) {
    switch (e.type) {
      case DeviceSpecEntry::Type::kInproc:
        devices.push_back({e.type, "Tessera inproc (CPU)", "inproc"});
        break;
      case DeviceSpecEntry::Type::kLocal:
        for (int i = 0; i < e.count; ++i) {
          devices.push_back({e.type, absl::StrCat("Tessera local worker ", i),
                             absl::StrCat(e.ToString(), "/", i), i, e.count});
        }
        break;
      case DeviceSpecEntry::Type::kTcp:
      case DeviceSpecEntry::Type::kUnix:
        devices.push_back({e.type, absl::StrCat("Tessera worker ", e.ToString()), e.ToString()});
        break;
    }
  }
  return devices;
}

std::string DefaultDeviceSpec() {
  if (g_worker_factory.load() == nullptr) return kDefaultDeviceSpec;
  if (absl::Status usable = WorkerTransportUsable(); !usable.ok()) {
    // Defaults work with no configuration: a forked child still renders, on its own cores.
    static std::atomic<bool> said{false};
    if (!said.exchange(true)) {
      log::Warn(log::Component::kApi, "the default devices are '%s' here: %s", kDefaultDeviceSpec,
                usable.message());
    }
    return kDefaultDeviceSpec;
  }
  return absl::StrCat("local:", HardwareThreads());
}

absl::StatusOr<std::vector<DeviceDesc>> DevicesFromEnvironment() {
  std::string spec = DeviceSpecFromEnvironment(DefaultDeviceSpec());
  auto entries = ParseDeviceSpec(spec);
  if (!entries.ok()) {
    return RtError(ToRtResult(entries.status()),
                   absl::StrCat("TESSERA_DEVICES: ", entries.status().message()));
  }
  return ExpandDevices(*entries);
}

absl::StatusOr<std::vector<DeviceDesc>> GlobalDevices() {
  auto devices = DevicesFromEnvironment();
  if (!devices.ok()) return RtError(RT_ERROR_NO_DEVICE, devices.status().message());
  return devices;
}

absl::StatusOr<DeviceDesc> GlobalDevice(int ordinal) {
  TS_ASSIGN_OR_RETURN(std::vector<DeviceDesc> devices, GlobalDevices());
  if (ordinal < 0 || ordinal >= static_cast<int>(devices.size())) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("device ordinal ", ordinal, " is out of range (", devices.size(),
                                " devices)"));
  }
  return std::move(devices[ordinal]);
}

void CopyString(const std::string& s, size_t size, char* out) {
  const size_t n = std::min(s.size(), size - 1);
  std::memcpy(out, s.data(), n);
  out[n] = '\0';
}

absl::Status GetDeviceAttribute(const DeviceDesc& device, RTdeviceattribute attribute, RTsize size,
                                void* out) {
  switch (attribute) {
    case RT_DEVICE_ATTRIBUTE_NAME: {
      if (size == 0)
        return RtError(RT_ERROR_INVALID_VALUE, "RT_DEVICE_ATTRIBUTE_NAME needs size > 0");
      CopyString(device.name, size, static_cast<char*>(out));
      return absl::OkStatus();
    }
    case RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT:
      // A local:N worker gets its share of the cores (api/src/worker_factory.cc).
      return MachineFact("RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT", device, size, out,
                         &WorkerFacts::threads, [&] {
                           return device.type == DeviceSpecEntry::Type::kLocal
                                      ? std::max(
                                            1, HardwareThreads() / std::max(1, device.local_count))
                                      : HardwareThreads();
                         });
    case RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY:
      return MachineFact("RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY", device, size, out,
                         &WorkerFacts::total_memory, [] { return TotalSystemMemory(); });
    case RT_DEVICE_ATTRIBUTE_CLOCK_RATE:
      return MachineFact("RT_DEVICE_ATTRIBUTE_CLOCK_RATE", device, size, out,
                         &WorkerFacts::clock_khz, [] { return CpuClockKHz(); });
    case RT_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY: {
      const int cc[2] = {0, 0};
      if (size != sizeof(cc)) {
        return SizeError("RT_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY", size, sizeof(cc));
      }
      std::memcpy(out, cc, sizeof(cc));
      return absl::OkStatus();
    }
    case RT_DEVICE_ATTRIBUTE_CUDA_DEVICE_ORDINAL:
      return Write<int>("RT_DEVICE_ATTRIBUTE_CUDA_DEVICE_ORDINAL", size, out, -1);
    case RT_DEVICE_ATTRIBUTE_MAX_THREADS_PER_BLOCK:
    case RT_DEVICE_ATTRIBUTE_EXECUTION_TIMEOUT_ENABLED:
    case RT_DEVICE_ATTRIBUTE_MAX_HARDWARE_TEXTURE_COUNT:
    case RT_DEVICE_ATTRIBUTE_TCC_DRIVER:
      return Write<int>("device attribute", size, out, 0);
  }
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat("unknown device attribute ", static_cast<int>(attribute)));
}

absl::Status CheckInstantiable(const DeviceDesc& device) {
  if (device.type == DeviceSpecEntry::Type::kInproc) return absl::OkStatus();
  if (g_worker_factory.load() != nullptr) {
    absl::Status usable = WorkerTransportUsable();
    if (usable.ok()) return absl::OkStatus();
    return RtError(
        RT_ERROR_NOT_SUPPORTED,
        absl::StrCat("device '", device.address, "' is a worker process, and ", usable.message()));
  }
  return RtError(RT_ERROR_NOT_SUPPORTED,
                 absl::StrCat("device '", device.address,
                              "' is a worker process, and this build of Tessera has no worker "
                              "transport (use TESSERA_DEVICES=inproc)"));
}

void SetInprocDeviceFactory(InprocDeviceFactory factory) { g_inproc_factory.store(factory); }

void SetWorkerDeviceFactory(WorkerDeviceFactory factory) { g_worker_factory.store(factory); }

void SetWorkerProbe(WorkerProbe probe) { g_worker_probe.store(probe); }

void SetWorkerTransportCheck(WorkerTransportCheck check) { g_worker_check.store(check); }

absl::StatusOr<std::unique_ptr<Device>> CreateDevice(const DeviceDesc& device, int num_threads) {
  TS_RETURN_IF_ERROR(CheckInstantiable(device));
  if (device.type != DeviceSpecEntry::Type::kInproc) {
    WorkerDeviceFactory factory = g_worker_factory.load();  // set: CheckInstantiable passed
    absl::StatusOr<std::unique_ptr<Device>> created = factory(device);
    if (!created.ok()) return created.status();
    if (*created == nullptr) {
      return RtError(RT_ERROR_NO_DEVICE,
                     absl::StrCat("the worker device '", device.address, "' could not be created"));
    }
    return created;
  }
  InprocDeviceFactory factory = g_inproc_factory.load();
  if (factory == nullptr) {
    return RtError(RT_ERROR_NO_DEVICE,
                   "this build of Tessera has no in-process device (worker/core was not built)");
  }
  std::unique_ptr<Device> created = factory(num_threads);
  if (created == nullptr) {
    return RtError(RT_ERROR_NO_DEVICE, "the in-process device could not be created");
  }
  return created;
}

}  // namespace tessera::api
