// Context device selection: which devices of the context's list a launch uses.
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

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

namespace {

// Creates the devices of `slots` at once, each on a thread of its own: a worker that is slow to
// start (or stopped while starting, which costs its start deadline) then delays the launch by its
// own start only, not by the sum of all. Exceptions become statuses, as at the C boundary.
std::vector<absl::StatusOr<std::unique_ptr<Device>>> CreateDevices(
    const std::vector<DeviceSlot*>& slots, int num_threads) {
  std::vector<absl::StatusOr<std::unique_ptr<Device>>> created(slots.size());
  auto create = [&](size_t i) {
    try {
      created[i] = CreateDevice(slots[i]->desc, num_threads);
    } catch (const std::bad_alloc&) {
      created[i] = RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED, "out of memory");
    } catch (const std::system_error& e) {
      created[i] = RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED,
                           absl::StrCat("could not start a thread: ", e.what()));
    } catch (const std::exception& e) {
      created[i] = absl::InternalError(absl::StrCat("threw: ", e.what()));
    }
  };
  if (slots.size() == 1) {
    create(0);
    return created;
  }
  std::vector<std::thread> threads;
  for (size_t i = 0; i < slots.size(); ++i) {
    try {
      threads.emplace_back(create, i);
    } catch (const std::system_error&) {
      create(i);  // no thread to be had: this one starts here
    }
  }
  for (std::thread& t : threads) t.join();
  return created;
}

}  // namespace

absl::Status Context::EnsureDevices() {
  if (slots_.empty()) return RtError(RT_ERROR_NO_DEVICE, "the context has no devices");
  std::vector<DeviceSlot*> missing;
  for (DeviceSlot& slot : slots_) {
    // A lost test device stays lost.
    if (slot.device == nullptr && !injected_devices_) missing.push_back(&slot);
  }
  std::vector<absl::StatusOr<std::unique_ptr<Device>>> created =
      CreateDevices(missing, num_threads_);
  for (size_t i = 0; i < missing.size(); ++i) {
    if (!created[i].ok()) continue;
    missing[i]->device = *std::move(created[i]);
    missing[i]->lost = false;
    missing[i]->start_failure_said = false;
  }
  size_t available = 0;
  for (const DeviceSlot& slot : slots_) available += slot.device != nullptr ? 1 : 0;
  // A device that cannot be started (a worker killed or stopped while starting, a remote worker
  // not up yet) is a lost device: while another is left the launch runs without it, said once
  // until it starts again, and every launch tries it again. Only with no device left does the
  // launch fail: a device that never worked names why (a configuration error keeps its code).
  std::string failures;
  absl::Status first_never_started;
  for (size_t i = 0; i < missing.size(); ++i) {
    if (created[i].ok()) continue;
    DeviceSlot& slot = *missing[i];
    const absl::Status& why = created[i].status();
    absl::StrAppend(&failures, failures.empty() ? "" : "; ", slot.desc.name, ": ", why.message());
    if (!slot.lost && first_never_started.ok()) {
      first_never_started = RtError(
          ToRtResult(why), absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address,
                                        ") could not be started: ", why.message()));
    }
    if (available > 0 && !slot.start_failure_said) {
      std::fprintf(stderr,
                   "tessera: device '%s' (%s) could not be started%s: %s. Launches run on the "
                   "other devices and try it again each time (said once until it starts).\n",
                   slot.desc.name.c_str(), slot.desc.address.c_str(), slot.lost ? " again" : "",
                   std::string(why.message()).c_str());
      slot.start_failure_said = true;
    }
    slot.lost = true;
  }
  if (available > 0) return absl::OkStatus();
  if (!first_never_started.ok()) return first_never_started;
  return RtError(RT_ERROR_CONNECTION_FAILED,
                 absl::StrCat("every device was lost and none could be started again",
                              failures.empty() ? "" : " (", failures, failures.empty() ? "" : ")"));
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
