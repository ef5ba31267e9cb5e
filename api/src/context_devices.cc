// Context device selection: which devices of the context's list a launch uses.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"
#include "context.h"
#include "status.h"

namespace tessera::api {

void Context::ResetDeviceSlots() {
  // New devices start from nothing: the next delta carries the whole state.
  slots_.clear();
  for (int ordinal : selected_) {
    DeviceSlot slot;
    slot.desc = device_list_[ordinal];
    slot.sync.ordinal = ordinal;
    slot.sync.session_id = session_id_ + sessions_++;
    slots_.push_back(std::move(slot));
  }
  injected_devices_ = false;
  last_stable_layout_ = {};  // new devices hold no GPU_LOCAL state yet
}

absl::Status Context::SetDevices(const std::vector<int>& ordinals) {
  // Devices are in use until the launch returns (only the timeout callback can get here).
  if (running()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "cannot change devices while a launch runs");
  }
  if (ordinals.empty()) return RtError(RT_ERROR_INVALID_VALUE, "device count must not be 0");
  absl::flat_hash_set<int> seen;
  for (int ordinal : ordinals) {
    if (ordinal < 0 || ordinal >= static_cast<int>(device_list_.size())) {
      return RtError(RT_ERROR_INVALID_DEVICE,
                     absl::StrCat("device ordinal ", ordinal, " is out of range (",
                                  device_list_.size(), " devices)"));
    }
    if (!seen.insert(ordinal).second) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("device ordinal ", ordinal, " is listed twice"));
    }
    TS_RETURN_IF_ERROR(CheckInstantiable(device_list_[ordinal]));
  }
  // The set the context already runs on: its devices, their GPU_LOCAL copies and what the host
  // knows they hold stay as they are (re-creating them would restart every worker and silently
  // reset per-device accumulation).
  if (ordinals == selected_ && !injected_devices_) return absl::OkStatus();
  selected_ = ordinals;
  ResetDeviceSlots();
  return absl::OkStatus();
}

absl::Status Context::SetDeviceSpec(const std::string& spec) {
  if (running()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "cannot change devices while a launch runs");
  }
  auto entries = ParseDeviceSpec(spec);
  if (!entries.ok()) return entries.status();
  std::vector<DeviceDesc> devices = ExpandDevices(*entries);
  for (const DeviceDesc& d : devices) TS_RETURN_IF_ERROR(CheckInstantiable(d));
  device_list_ = std::move(devices);
  selected_.clear();
  for (size_t i = 0; i < device_list_.size(); ++i) selected_.push_back(static_cast<int>(i));
  ResetDeviceSlots();
  return absl::OkStatus();
}

void Context::UseDevicesForTesting(std::vector<std::unique_ptr<Device>> devices) {
  slots_.clear();
  for (auto& device : devices) {
    DeviceSlot slot;
    DeviceInfo info = device->Info();
    slot.desc = DeviceDesc{DeviceSpecEntry::Type::kInproc, info.name, info.address};
    slot.device = std::move(device);
    slot.sync.ordinal = static_cast<int>(slots_.size());
    slot.sync.session_id = session_id_ + sessions_++;
    slots_.push_back(std::move(slot));
  }
  injected_devices_ = true;
}

absl::Status Context::EnsureDevices() {
  if (slots_.empty()) return RtError(RT_ERROR_NO_DEVICE, "the context has no devices");
  size_t available = 0;
  std::string failures;
  for (DeviceSlot& slot : slots_) {
    if (slot.device != nullptr) {
      ++available;
      continue;
    }
    if (injected_devices_) continue;  // a lost test device stays lost
    auto device = CreateDevice(slot.desc, num_threads_);
    if (!device.ok()) {
      // A device that never worked is a configuration error; one that was lost is left out.
      if (!slot.lost) {
        return RtError(ToRtResult(device.status()),
                       absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address,
                                    ") could not be started: ", device.status().message()));
      }
      std::fprintf(stderr, "tessera: device '%s' (%s) could not be started again: %s\n",
                   slot.desc.name.c_str(), slot.desc.address.c_str(),
                   std::string(device.status().message()).c_str());
      absl::StrAppend(&failures, failures.empty() ? "" : "; ", slot.desc.name, ": ",
                      device.status().message());
      continue;
    }
    slot.device = *std::move(device);
    slot.lost = false;
    ++available;
  }
  if (available == 0) {
    return RtError(
        RT_ERROR_CONNECTION_FAILED,
        absl::StrCat("every device was lost and none could be started again",
                     failures.empty() ? "" : " (", failures, failures.empty() ? "" : ")"));
  }
  return absl::OkStatus();
}

void Context::LoseDevice(DeviceSlot& slot) {
  slot.device.reset();
  slot.lost = true;
  // A new session: the replacement starts from nothing, and a worker that comes back must not
  // mistake the new deltas for the continuation of the old ones.
  const int ordinal = slot.sync.ordinal;
  slot.sync = DeviceSync();
  slot.sync.ordinal = ordinal;
  slot.sync.session_id = session_id_ + sessions_++;
}

bool Context::race_check() const {
  if (race_check_) return true;
  const char* env = std::getenv("TESSERA_RACE_CHECK");
  return env != nullptr && *env != '\0' && std::string(env) != "0";
}

absl::Status Context::SetTileSize(std::vector<uint64_t> size) {
  if (running()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "cannot change the tile size while a launch runs");
  }
  tile_size_ = std::move(size);
  return absl::OkStatus();
}

}  // namespace tessera::api
