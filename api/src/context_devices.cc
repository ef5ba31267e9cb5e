// Context device selection: which devices of the context's list a launch uses.
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
    slot.sync.session_id = session_id_ + slots_.size();
    slots_.push_back(std::move(slot));
  }
  injected_devices_ = false;
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
    slot.sync.session_id = session_id_ + slots_.size();
    slots_.push_back(std::move(slot));
  }
  injected_devices_ = true;
}

absl::Status Context::EnsureDevices() {
  if (slots_.empty()) return RtError(RT_ERROR_NO_DEVICE, "the context has no devices");
  for (DeviceSlot& slot : slots_) {
    if (slot.device != nullptr) continue;
    auto device = CreateDevice(slot.desc, num_threads_);
    if (!device.ok()) return device.status();
    slot.device = *std::move(device);
  }
  return absl::OkStatus();
}

}  // namespace tessera::api
