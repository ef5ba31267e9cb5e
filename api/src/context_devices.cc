// Context device selection: which devices of the context's list a launch uses.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "absl/container/flat_hash_set.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "context.h"
#include "device_joiner.h"
#include "status.h"
#include "tessera/scheduler/log.h"

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

namespace {

// A worker someone else runs: one that does not answer is tried again in the background instead
// of at every launch (a host that cannot be reached costs each try the connection timeout).
bool IsRunningWorker(const DeviceDesc& desc) {
  return desc.type == DeviceSpecEntry::Type::kTcp || desc.type == DeviceSpecEntry::Type::kUnix;
}

// The longest one try to reach a running worker takes: TESSERA_WORKER_TIMEOUT (read as the
// transport reads it, which says once when it is unusable), and a second for the connection.
// How long a launch that has a device waits for running workers' first tries: connecting to a
// worker that is up takes milliseconds, one that is not may take the whole connection timeout.
constexpr absl::Duration kFirstAnswerGrace = absl::Seconds(1);

absl::Duration OneTryAtMost() {
  double seconds = 10;
  const char* env = std::getenv("TESSERA_WORKER_TIMEOUT");
  double parsed = 0;
  if (env != nullptr && absl::SimpleAtod(env, &parsed) && std::isfinite(parsed) && parsed >= 1) {
    seconds = parsed;
  }
  return absl::Seconds(seconds + 1);
}

}  // namespace

void Context::StartJoining(DeviceSlot& slot, bool try_at_once) {
  if (slot.joiner != nullptr || injected_devices_) return;
  const DeviceDesc desc = slot.desc;
  const int threads = num_threads_;
  slot.joiner = std::make_shared<DeviceJoiner>(
      desc.address, [desc, threads] { return CreateDevice(desc, threads); }, try_at_once,
      slot.lost);
}

absl::Status Context::EnsureDevices() {
  if (slots_.empty()) return RtError(RT_ERROR_NO_DEVICE, "the context has no devices");
  // Running workers that answered in the background join now, with the whole state (their
  // sessions are new: LoseDevice, or never started).
  auto take_joined = [this] {
    for (DeviceSlot& slot : slots_) {
      if (slot.device != nullptr || slot.joiner == nullptr) continue;
      std::unique_ptr<Device> device = slot.joiner->Take();
      if (device == nullptr) continue;
      slot.joiner.reset();
      slot.device = std::move(device);
      slot.lost = false;
      slot.start_failure_said = false;
      slot.down_reason.clear();
    }
  };
  take_joined();
  auto count_available = [this] {
    size_t n = 0;
    for (const DeviceSlot& slot : slots_) n += slot.device != nullptr ? 1 : 0;
    return n;
  };
  // Waits until each of `waits` (a joiner's slot, and the tries it must have ended) ended its
  // try or answered, or `grace` after some device is ready (a worker that answers later joins a
  // later launch), or one try's longest time; takes those that answered.
  auto wait_for_tries = [&](const std::vector<std::pair<DeviceSlot*, uint64_t>>& waits,
                            absl::Duration grace) {
    const absl::Time start = absl::Now();
    const absl::Time deadline = start + OneTryAtMost();
    while (!waits.empty()) {
      bool all_tried = true;
      for (const auto& [slot, tries] : waits) {
        if (slot->joiner == nullptr) continue;  // taken
        const bool ready = slot->joiner->Wait(tries, absl::InfinitePast());
        all_tried = all_tried && (ready || slot->joiner->tries() >= tries);
      }
      take_joined();
      const absl::Time now = absl::Now();
      if (all_tried || now >= deadline || (count_available() > 0 && now >= start + grace)) break;
      absl::SleepFor(absl::Milliseconds(5));
    }
  };
  // Running workers not tried yet (at the context's first launch) are tried on joiners' threads
  // from the start, as those that stopped answering are; the others are created here, at once
  // and in parallel: in-process devices and spawned workers (local:N, started again at every
  // launch while they fail).
  std::vector<DeviceSlot*> missing;
  std::vector<std::pair<DeviceSlot*, uint64_t>> first_tries;
  for (DeviceSlot& slot : slots_) {
    // A lost test device stays lost.
    if (slot.device != nullptr || slot.joiner != nullptr || injected_devices_) continue;
    if (IsRunningWorker(slot.desc)) {
      StartJoining(slot, /*try_at_once=*/true);
      first_tries.emplace_back(&slot, 1);
    } else {
      missing.push_back(&slot);
    }
  }
  std::vector<absl::StatusOr<std::unique_ptr<Device>>> created =
      CreateDevices(missing, num_threads_);
  for (size_t i = 0; i < missing.size(); ++i) {
    if (!created[i].ok()) continue;
    DeviceSlot& slot = *missing[i];
    slot.device = *std::move(created[i]);
    slot.lost = false;
    slot.start_failure_said = false;
  }
  // The launch starts with the devices that answer: a worker that has not answered a second
  // after another device was ready is left to join a later launch.
  wait_for_tries(first_tries, kFirstAnswerGrace);
  // No device at all: the running workers get one more try each, at once and together, before
  // the launch fails (a bounded wait: each try ends within the connection timeout, and one
  // refused ends at once).
  if (count_available() == 0) {
    std::vector<std::pair<DeviceSlot*, uint64_t>> waits;
    for (DeviceSlot& slot : slots_) {
      if (slot.joiner == nullptr) continue;
      const bool first = std::any_of(first_tries.begin(), first_tries.end(),
                                     [&](const auto& w) { return w.first == &slot; });
      if (!first) waits.emplace_back(&slot, slot.joiner->Kick());
    }
    wait_for_tries(waits, absl::ZeroDuration());
  }
  const size_t available = count_available();
  // A device that cannot be started (a worker killed or stopped while starting, a remote worker
  // not up yet) is a lost device: while another is left the launch runs without it, said once
  // until it starts again. Only with no device left does the launch fail: a device that never
  // worked names why (a configuration error keeps its code).
  std::string failures;
  absl::Status first_never_started;
  for (size_t i = 0; i < missing.size(); ++i) {
    if (created[i].ok() || IsRunningWorker(missing[i]->desc)) continue;
    DeviceSlot& slot = *missing[i];
    const absl::Status& why = created[i].status();
    absl::StrAppend(&failures, failures.empty() ? "" : "; ", slot.desc.name, ": ", why.message());
    if (!slot.lost && first_never_started.ok()) {
      first_never_started = RtError(
          ToRtResult(why), absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address,
                                        ") could not be started: ", why.message()));
    }
    if (available > 0 && !slot.start_failure_said) {
      log::Warn(log::Component::kApi,
                "device '%s' (%s) could not be started%s: %s. Launches run on the other devices "
                "and try it again each time (said once until it starts).",
                slot.desc.name, slot.desc.address, slot.lost ? " again" : "", why.message());
      slot.start_failure_said = true;
    }
    slot.lost = true;
  }
  // Running workers that do not answer: one line each until they join.
  for (DeviceSlot& slot : slots_) {
    if (slot.device != nullptr || slot.joiner == nullptr) continue;
    const absl::Status last = slot.joiner->last_error();
    if (!last.ok()) slot.down_reason = std::string(last.message());
    if (slot.down_reason.empty()) slot.down_reason = "no answer yet";
    const std::string reason = slot.down_reason.empty() ? "" : " (" + slot.down_reason + ")";
    absl::StrAppend(&failures, failures.empty() ? "" : "; ", slot.desc.address, reason);
    if (!slot.lost && first_never_started.ok()) {
      const absl::Status why = last.ok() ? absl::UnavailableError(slot.down_reason) : last;
      first_never_started = RtError(
          ToRtResult(why), absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address,
                                        ") could not be started: ", slot.down_reason));
    }
    if (available > 0 && !slot.start_failure_said) {
      log::Warn(log::Component::kApi,
                "device %s not answering; continuing with %d devices, retrying in background%s",
                slot.desc.address, available, reason);
      slot.start_failure_said = true;
    }
  }
  if (available > 0) return absl::OkStatus();
  // Never answered: its own code (a refused token stays RT_ERROR_AUTHENTICATION_FAILED); with
  // running workers among several devices, every device named (any of them may come up).
  if (!first_never_started.ok()) {
    const bool running_workers = std::any_of(
        slots_.begin(), slots_.end(), [](const DeviceSlot& s) { return s.joiner != nullptr; });
    if (slots_.size() == 1 || !running_workers) return first_never_started;
    return RtError(ToRtResult(first_never_started),
                   absl::StrCat("no device could be started (", failures,
                                "); running workers are tried again in the background and join "
                                "when they answer"));
  }
  return RtError(RT_ERROR_CONNECTION_FAILED,
                 absl::StrCat("every device was lost and none could be started again",
                              failures.empty() ? "" : " (", failures, failures.empty() ? "" : ")",
                              "; running workers are tried again in the background and join when "
                              "they answer"));
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
  // A running worker is reached again in the background, from now: a launch never waits for it.
  if (IsRunningWorker(slot.desc)) {
    slot.start_failure_said = false;
    StartJoining(slot, /*try_at_once=*/true);
  }
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
