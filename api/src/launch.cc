// Context::Launch: validate, ship state deltas, dispatch tiles to devices (scheduler/), gather
// results, and deal with devices lost on the way.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>

#include "absl/functional/function_ref.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "acceleration.h"
#include "acceleration_data.h"
#include "buffer.h"
#include "context.h"
#include "gather.h"
#include "geometry.h"
#include "lowering.h"
#include "status.h"
#include "tessera/scheduler/dispatcher.h"
#include "tessera/scheduler/launch_timing.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/result_pool.h"
#include "tessera/scheduler/tiling.h"
#include "validate.h"

namespace tessera::api {
namespace {

// A device error as the application sees it: the RTresult from the table (or the status's own)
// and a message naming the device.
absl::Status DeviceError(const DeviceSlot& slot, const char* what, const absl::Status& status) {
  RTresult code = ToRtResult(status);
  if (code == RT_ERROR_INVALID_VALUE || code == RT_ERROR_INVALID_CONTEXT) {
    code = RT_ERROR_LAUNCH_FAILED;  // a device rejecting our own messages is a launch failure
  }
  if (status.code() == absl::StatusCode::kAborted) code = RT_ERROR_LAUNCH_FAILED;
  return RtError(code, absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address, ") ",
                                    what, ": ", status.message()));
}

// Whether `status` says the device itself is gone rather than that it refused our request.
bool IsDeviceLoss(const absl::Status& status) {
  return status.code() == absl::StatusCode::kUnavailable ||
         status.code() == absl::StatusCode::kDeadlineExceeded;
}

// The context's buffers that `pick` accepts, named and comma-separated, for a lost device's line.
std::string BufferNames(Context& context, absl::FunctionRef<bool(const Buffer&)> pick) {
  std::string names;
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() != Kind::kBuffer) continue;
    const auto& b = static_cast<const Buffer&>(*object);
    if (pick(b)) absl::StrAppend(&names, names.empty() ? "" : ", ", b.DescribeNamed());
  }
  return names;
}

// Buffers whose devices each run on their own data (device pointers for every device of the
// context): launch indices of a lost device that run elsewhere read another device's data.
std::string PerDeviceDataBuffers(Context& context) {
  const size_t devices = context.device_slots().size();
  if (devices < 2) return "";
  return BufferNames(context, [&](const Buffer& b) {
    return b.ships_content() && b.device_pointer_count() == devices;
  });
}

// What became of a lost device's tiles.
enum class LostTiles {
  kRanElsewhere,  // other devices ran (or will run) them
  kNoDeviceLeft,  // the launch fails for want of any device
  kLaunchEnded,   // the launch failed for another reason (a crash) or was cancelled
  kStartedAgain,  // every device was lost taking the state: the launch starts them again once
};

// Only local:N workers are started again; others are reached again in the background
// (DeviceJoiner).
void WarnLost(Context& context, const DeviceSlot& slot, uint64_t launch_id,
              const absl::Status& reason, LostTiles tiles) {
  const bool others_took_over = tiles == LostTiles::kRanElsewhere;
  const bool spawned = slot.desc.type == DeviceSpecEntry::Type::kLocal;
  const std::string per_device = others_took_over ? PerDeviceDataBuffers(context) : "";
  const std::string moved =
      per_device.empty()
          ? std::string()
          : absl::StrCat(" Its launch indices read another device's data of ", per_device,
                         " (device pointers for every device): this launch's output is not what "
                         "it would have been without the loss.");
  // A lost device's copies of GPU_LOCAL buffers are gone.
  const std::string gpu_local = BufferNames(context, [](const Buffer& b) { return b.gpu_local(); });
  const std::string gone = gpu_local.empty() ? std::string()
                                             : absl::StrCat("; its copies of GPU_LOCAL buffers (",
                                                            gpu_local, ") are gone");
  log::Warn(log::Component::kApi, "device '%s' (%s) was lost during launch %llu: %s. %s%s.%s %s",
            slot.desc.name, slot.desc.address, static_cast<unsigned long long>(launch_id),
            reason.message(),
            others_took_over                    ? "Its tiles ran on the other devices"
            : tiles == LostTiles::kNoDeviceLeft ? "No other device was left to run its tiles"
            : tiles == LostTiles::kStartedAgain
                ? "No device was left: the launch starts its devices again once"
                : "The launch ended without its tiles",
            gone, moved,
            tiles == LostTiles::kStartedAgain ? ""
            : spawned                         ? "It is started again for the next launch."
                                              : "It is reached again in the background and joins "
                                                "the launch after it answers.");
}

// TESSERA_LAUNCH_TIMING=1: one line per launch on stderr with where the host's time went, to tell
// device work from host work when a launch scales worse than expected.
class LaunchTiming {
 public:
  LaunchTiming()
      : enabled_(scheduler::LaunchTimingEnabled()),
        start_(std::chrono::steady_clock::now()),
        last_(start_) {
    if (enabled_) getrusage(RUSAGE_SELF, &start_usage_);
  }
  void Mark(const char* phase) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    absl::StrAppend(&line_, " ", phase, "=", Ms(now - last_), "ms");
    last_ = now;
  }
  void Report(uint64_t launch_id) {
    if (!enabled_) return;
    rusage now{};
    getrusage(RUSAGE_SELF, &now);
    // The monotonic clock is the machine's: it places the launch among local workers' calls.
    log::Info(log::Component::kApi,
              "launch %llu:%s (of which applying results %sms); host cpu user %.1fms sys %.1fms; "
              "monotonic clock %s to %sms",
              static_cast<unsigned long long>(launch_id), line_, Ms(apply),
              scheduler::Milliseconds(now.ru_utime, start_usage_.ru_utime),
              scheduler::Milliseconds(now.ru_stime, start_usage_.ru_stime),
              Ms(start_.time_since_epoch()), Ms(last_.time_since_epoch()));
  }
  std::chrono::steady_clock::duration apply{};

 private:
  static std::string Ms(std::chrono::steady_clock::duration d) {
    return absl::StrFormat("%.1f", std::chrono::duration<double, std::milli>(d).count());
  }
  const bool enabled_;
  rusage start_usage_{};
  std::chrono::steady_clock::time_point start_, last_;
  std::string line_;
};

// Clears the running flag (claimed with TryStartRunning) when the launch returns.
class RunningScope {
 public:
  explicit RunningScope(Context& c) : c_(c) {}
  ~RunningScope() { c_.set_running(false); }

 private:
  Context& c_;
};

// Polls the timeout callback on the launching thread (OptiX semantics: the callback runs on the
// application's thread and may ask to stop), while state ships and while tiles run. The callback
// and its interval are read at every poll, so removing or changing it (from the callback) takes
// effect at once.
class TimeoutPoller {
 public:
  using TimePoint = std::chrono::steady_clock::time_point;
  explicit TimeoutPoller(Context& c) : c_(c) { Reset(); }
  bool cancelled() const { return cancelled_; }
  // When Poll next has something to do (max: never).
  TimePoint deadline() const {
    return !cancelled_ && c_.timeout_callback() != nullptr ? next_ : TimePoint::max();
  }
  // Calls the callback if its time came; returns whether the launch is to stop.
  bool Poll() {
    RTtimeoutcallback callback = c_.timeout_callback();
    if (cancelled_ || callback == nullptr || std::chrono::steady_clock::now() < next_) {
      return cancelled_;
    }
    if (callback() != 0) cancelled_ = true;
    Reset();
    return cancelled_;
  }

 private:
  void Reset() {
    // At least a millisecond; at most about 30 years, beyond which the clock's nanoseconds
    // overflow (an infinite interval means never).
    const double seconds = std::clamp(c_.timeout_polling_seconds(), 0.001, 1e9);
    next_ = std::chrono::steady_clock::now() +
            std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                std::chrono::duration<double>(seconds));
  }
  Context& c_;
  TimePoint next_;
  bool cancelled_ = false;
};

absl::Status CheckNothingMapped(Context& context) {
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kBuffer && static_cast<Buffer*>(object)->mapped()) {
      return RtError(RT_ERROR_ALREADY_MAPPED,
                     absl::StrCat(object->Describe(), " is mapped; unmap it before launching"));
    }
  }
  return absl::OkStatus();
}

// Ships each device what changed since it last synced. A device that is gone is dropped from
// this launch (and created again for the next); every device gone is RT_ERROR_CONNECTION_FAILED.
// Whether `delta` would tell the device nothing: no object, removal, chunk or module, and the
// context state it last applied. (A spuriously different serialization only costs a send.)
bool NothingNew(const v1::StateDelta& delta, const DeviceSync& sync,
                const std::string& context_bytes) {
  return sync.next_sequence > 1 && delta.objects_size() == 0 && delta.removed_size() == 0 &&
         delta.chunks_size() == 0 && delta.modules_size() == 0 && delta.memory_size() == 0 &&
         !delta.has_allocations() && context_bytes == sync.last_context;
}

// `retry`: when every device is lost taking its update, say so as the launch starting them again
// (the caller's second try) instead of failing.
absl::Status ApplyDeltas(Context& context, uint64_t launch_id, TimeoutPoller& poller,
                         bool retry = false) {
  size_t alive = 0;
  std::string lost;
  std::vector<std::pair<DeviceSlot*, absl::Status>> warn;  // said once it is known who is left
  struct Job {
    DeviceSlot* slot;
    PreparedDelta prepared;
    std::string context_bytes;
    absl::Status status;
  };
  std::vector<Job> jobs;
  for (DeviceSlot& slot : context.device_slots()) {
    if (slot.device == nullptr) continue;
    PreparedDelta prepared = BuildDelta(context, slot);
    std::string context_bytes = prepared.delta.context().SerializeAsString();
    if (NothingNew(prepared.delta, slot.sync, context_bytes)) {
      ++alive;  // an unchanged launch costs no round trip per device
      continue;
    }
    prepared.delta.set_launch_id(launch_id);
    jobs.push_back(Job{&slot, std::move(prepared), std::move(context_bytes), absl::OkStatus()});
  }
  // Devices take their deltas at once (hundreds of MB of INPUT buffers take seconds), each on a
  // thread of its own that touches only its delta and its device, while this thread polls the
  // timeout callback. An update cannot be interrupted: a cancel stops the launch once they end.
  if (!jobs.empty()) {
    std::mutex mu;
    std::condition_variable cv;
    size_t finished = 0;
    std::vector<std::thread> threads;
    threads.reserve(jobs.size());
    // On a thread of its own, an exception would end the process (std::terminate): it becomes
    // the job's status, as the C boundary made of it when devices took deltas on this thread.
    auto apply = [&mu, &cv, &finished](Job& job) {
      try {
        job.status = job.slot->device->Apply(job.prepared.delta);
      } catch (const std::bad_alloc&) {
        job.status = RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED, "out of memory");
      } catch (const std::system_error& e) {
        // Out of threads (a process limit): the device could not start what it needed.
        job.status = RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED,
                             absl::StrCat("could not start a thread: ", e.what()));
      } catch (const std::exception& e) {
        job.status = absl::InternalError(absl::StrCat("threw: ", e.what()));
      } catch (...) {
        job.status = absl::InternalError("threw a non-standard exception");
      }
      std::lock_guard<std::mutex> lock(mu);
      ++finished;
      cv.notify_all();
    };
    for (Job& job : jobs) {
      try {
        threads.emplace_back(apply, std::ref(job));
      } catch (const std::system_error&) {
        apply(job);  // no thread to be had: this device takes its delta here
      }
    }
    {
      std::unique_lock<std::mutex> lock(mu);
      while (finished < jobs.size()) {
        const auto deadline = poller.deadline();
        auto all_done = [&] { return finished == jobs.size(); };
        if (deadline == TimeoutPoller::TimePoint::max()) {
          cv.wait(lock, all_done);
        } else if (!cv.wait_until(lock, deadline, all_done)) {
          lock.unlock();
          poller.Poll();
          lock.lock();
        }
      }
    }
    for (std::thread& t : threads) t.join();
  }
  absl::Status rejected;
  for (Job& job : jobs) {
    DeviceSlot& slot = *job.slot;
    uint64_t bytes = 0;
    for (const v1::BufferChunk& chunk : job.prepared.delta.chunks()) bytes += chunk.data().size();
    for (const v1::DeviceMemoryChunk& c : job.prepared.delta.memory()) bytes += c.data().size();
    if (IsDeviceLoss(job.status)) {
      warn.emplace_back(&slot, job.status);
      absl::StrAppend(&lost, lost.empty() ? "" : "; ", slot.desc.name, ": ", job.status.message());
      context.LoseDevice(slot);
      continue;
    }
    if (!job.status.ok()) {
      // A worker that crashed taking the update (a module's constructor, say) is gone: the next
      // launch starts it again.
      const bool crashed = job.status.code() == absl::StatusCode::kAborted;
      if (rejected.ok()) {
        rejected = DeviceError(
            slot, crashed ? "crashed taking the state update" : "rejected the state update",
            job.status);
      }
      if (crashed) context.LoseDevice(slot);
      continue;
    }
    context.CountSent(bytes);
    CommitDelta(std::move(job.prepared), &slot.sync);
    slot.sync.last_context = std::move(job.context_bytes);
    ++alive;
  }
  if (!rejected.ok()) return rejected;
  const bool again = alive == 0 && retry;
  for (const auto& [slot, status] : warn) {
    WarnLost(context, *slot, launch_id, status,
             alive > 0 ? LostTiles::kRanElsewhere
             : again   ? LostTiles::kStartedAgain
                       : LostTiles::kNoDeviceLeft);
  }
  if (alive == 0) {
    return RtError(RT_ERROR_CONNECTION_FAILED, absl::StrCat("every device was lost (", lost, ")"));
  }
  // Every device now holds the current build epochs.
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kAcceleration) static_cast<Acceleration*>(object)->ClearDirty();
    if (Geometry::Is(object)) static_cast<Geometry*>(object)->ClearDirty();
  }
  return absl::OkStatus();
}

// Device pointers (rtBufferGetDevicePointer/SetDevicePointer) into the host contents, or into
// per-device contents, before deltas are built.
absl::Status SyncDevicePointers(Context& context) {
  std::vector<int> ordinals;
  for (const DeviceSlot& slot : context.device_slots()) ordinals.push_back(slot.sync.ordinal);
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() != Kind::kBuffer) continue;
    TS_RETURN_IF_ERROR(static_cast<Buffer*>(object)->SyncDevicePointersBeforeLaunch(ordinals));
  }
  return absl::OkStatus();
}

// GPU_LOCAL buffers hold per-device state across launches (accumulation, RNG seeds): launches
// that can reach one keep every launch index on the same device (docs/devices.md "Buffers across
// devices"). Programs reach a buffer through a variable of an object the context reaches, or by
// id once the application took its id; a GPU_LOCAL buffer reached neither way leaves launches
// to dynamic assignment.
const Buffer* FirstGpuLocalBuffer(Context& context) {
  for (Object* object : context.Reachable()) {
    if (object->kind() == Kind::kBuffer && static_cast<Buffer*>(object)->gpu_local()) {
      return static_cast<Buffer*>(object);
    }
  }
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() != Kind::kBuffer) continue;
    const auto* buffer = static_cast<const Buffer*>(object);
    if (buffer->gpu_local() && buffer->id_taken()) return buffer;
  }
  return nullptr;
}
bool NeedsStableOwnership(Context& context) { return FirstGpuLocalBuffer(context) != nullptr; }

// Stable ownership keeps tile i on device i mod N; tiles of another size at the same launch size
// cover other launch indices, which then read another device's GPU_LOCAL copy. Said on stderr, as
// a lost device's GPU_LOCAL copies are.
void WarnIfTilesMoved(Context& context, uint64_t launch_id, const std::vector<uint64_t>& dims,
                      const std::vector<uint64_t>& tile_size) {
  Context::StableLayout& last = context.last_stable_layout();
  // Compared as cut: sizes past the launch's extent (or grown to bound the tile count) that give
  // the same tiles move nothing.
  const std::vector<uint64_t> effective = scheduler::EffectiveTileSize(dims, tile_size);
  if (last.dims == dims && !last.tile.empty() && last.tile != effective) {
    const Buffer* b = FirstGpuLocalBuffer(context);
    log::Warn(
        log::Component::kApi,
        "launch %llu: the tile size changed from %s to %s at the same launch size %s; launch "
        "indices move to other devices and see those devices' copies of GPU_LOCAL buffers (%s)",
        static_cast<unsigned long long>(launch_id), absl::StrJoin(last.tile, "x"),
        absl::StrJoin(effective, "x"), absl::StrJoin(dims, "x"),
        b != nullptr ? b->DescribeNamed().c_str() : "");
  }
  last.dims = dims;
  last.tile = effective;
}

// The context's tile size (tesseraContextSetTileSize), else TESSERA_TILE_SIZE, else chosen from
// the launch size, the devices' threads and how many devices share them; one entry per launch
// dimension.
absl::StatusOr<std::vector<uint64_t>> TileSizeFor(const Context& context,
                                                  const std::vector<uint64_t>& dims,
                                                  int total_threads, size_t devices) {
  std::vector<uint64_t> size = context.tile_size();
  if (size.empty()) {
    const char* env = std::getenv("TESSERA_TILE_SIZE");
    if (env != nullptr && *env != '\0') {
      auto parsed = scheduler::ParseTileSize(env);
      if (!parsed.ok()) {
        return RtError(RT_ERROR_INVALID_VALUE,
                       absl::StrCat("TESSERA_TILE_SIZE: ", parsed.status().message()));
      }
      size = *std::move(parsed);
    }
  }
  if (size.empty()) {
    return scheduler::ChooseTileSize(
        dims, total_threads,
        devices == 1 ? scheduler::kTilesPerThreadOneDevice : scheduler::kTilesPerThread);
  }
  size.resize(dims.size(), size.back());
  return size;
}

// Whether launches cut batches by the costs the last launch of the same tiles measured
// (TESSERA_COST_BATCHES=0 turns it off, to compare).
bool CostBatches() {
  static const bool on = [] {
    const char* e = std::getenv("TESSERA_COST_BATCHES");
    return e == nullptr || std::string(e) != "0";
  }();
  return on;
}

// TESSERA_BATCHING, read at every launch (tests and benchmarks change it between launches); a
// value it does not know is said once.
AutoBatching::Mode BatchingMode() {
  static std::atomic<bool> warned{false};
  std::string warning;
  const AutoBatching::Mode mode = AutoBatching::Parse(std::getenv("TESSERA_BATCHING"), &warning);
  if (!warning.empty() && !warned.exchange(true)) {
    log::Warn(log::Component::kApi, "%s", warning.c_str());
  }
  return mode;
}

// The fewest launch indices per device thread a call should carry (scheduler::Dispatcher):
// about two milliseconds of work at the cost per index the last launch of the entry point and
// size measured (with its calls' own overhead, which shrinks as they grow: a light launch settles
// on a call or two per device), or the dispatcher's default before any launch.
uint64_t MinIndicesPerCall(double ns_per_index) {
  constexpr double kCallWorkNs = 2e6;
  constexpr double kMost = 1 << 20;
  if (!(ns_per_index > 0)) return 0;
  return static_cast<uint64_t>(std::min(kCallWorkNs / ns_per_index, kMost));
}

}  // namespace

absl::Status Context::Launch(unsigned entry_point, const std::vector<uint64_t>& dims,
                             const v1::Optix7Launch* optix7) {
  // Claimed before anything else: checking the flag here and setting it after validation let a
  // second thread's launch start in between and gather into the same buffers.
  if (!TryStartRunning()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "a launch is already running on this context");
  }
  RunningScope running_scope(*this);
  set_last_launch_batched(false);  // until this launch's choice: one that ends before says 0
  if (optix7 != nullptr) entry_point = 0;  // tile costs are kept as for entry point 0
  if (optix7 == nullptr && entry_point >= entry_point_count()) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("entry point index ", entry_point, " is out of range (",
                                entry_point_count(), " entry points)"));
  }
  for (size_t d = 0; d < dims.size(); ++d) {
    // rtLaunchIndex and rtLaunchDim hold unsigned int components.
    if (dims[d] > std::numeric_limits<uint32_t>::max()) {
      return RtError(
          RT_ERROR_INVALID_VALUE,
          absl::StrCat("launch dimension ", d, " is ", dims[d], "; at most ",
                       std::numeric_limits<uint32_t>::max(), " (launch indices are unsigned int)"));
    }
  }
  TS_RETURN_IF_ERROR(ValidateOnce());  // walks every object only after a change it could see
  TS_RETURN_IF_ERROR(CheckNothingMapped(*this));
  TS_RETURN_IF_ERROR(EnsureDevices());
  TS_RETURN_IF_ERROR(SyncDevicePointers(*this));
  for (DeviceSlot& slot : device_slots()) {
    if (slot.device != nullptr) slot.threads = std::max(1, slot.device->Info().thread_count);
  }
  const uint64_t launch_id = NextLaunchId();
  LaunchTiming timing;
  TimeoutPoller poller(*this);
  StartProgress(0);  // while state ships: no tiles yet (not the last launch's figures)
  // What devices will hold is what ships now: buffer layouts and host writes are taken before the
  // timeout callback can change them.
  LaunchGather gather(*this);
  CheckRestoredAccelerations(*this);  // before lowering: decides which restored bounds ship
  {
    // Every device lost while taking its update (a worker's session dropped while the host was
    // idle, or all workers killed at that moment): the devices start again, with the whole state,
    // once, before the launch gives up. A device lost at any other moment is replaced at the next
    // launch, as before.
    absl::Status shipped = ApplyDeltas(*this, launch_id, poller, /*retry=*/true);
    if (shipped.ok() || ToRtResult(shipped) != RT_ERROR_CONNECTION_FAILED || poller.cancelled()) {
      TS_RETURN_IF_ERROR(shipped);
    } else {
      TS_RETURN_IF_ERROR(EnsureDevices());  // device pointers are in the host's copies already
      TS_RETURN_IF_ERROR(ApplyDeltas(*this, launch_id, poller));
    }
  }
  for (const auto& [id, object] : objects()) {
    if (object->kind() == Kind::kBuffer) static_cast<Buffer*>(object)->DevicePointersShipped();
  }
  timing.Mark("deltas");
  if (poller.cancelled()) {
    return RtError(RT_TIMEOUT_CALLBACK, "launch cancelled by the timeout callback");
  }

  v1::LaunchRequest common;
  common.set_launch_id(launch_id);
  common.set_entry_point(entry_point);
  for (uint64_t d : dims) common.add_dims(d);
  // Batched tracing (docs/programs.md, "Batched tracing"), chosen here so that every device of
  // the launch makes the same choice: TESSERA_BATCHING=1 for every launch, =auto per entry point
  // from what its earlier launches measured (OptiX 3 launches only), else never.
  const AutoBatching::Mode batching = BatchingMode();
  const bool choosing = batching == AutoBatching::Mode::kAuto && optix7 == nullptr;
  const bool batched =
      batching == AutoBatching::Mode::kAlways ||
      (choosing && auto_batching().Choose(entry_point, ray_generation(entry_point)));
  set_last_launch_batched(batched);
  if (optix7 == nullptr) {
    common.set_batched(batched);
  } else {
    *common.mutable_optix7() = *optix7;
    common.mutable_optix7()->set_batched(batched);
    // Devices send back what programs wrote to device memory, unless the only device writes the
    // host's own memory (in-process).
    size_t devices = 0;
    bool all_inproc = true;
    for (const DeviceSlot& slot : device_slots()) {
      if (slot.device == nullptr) continue;
      ++devices;
      all_inproc = all_inproc && slot.desc.type == DeviceSpecEntry::Type::kInproc;
    }
    common.mutable_optix7()->set_report_writes(devices > 1 || !all_inproc);
  }

  // The devices of this launch: slots whose device exists. With stable ownership, also those
  // lost since (while receiving this launch's state, or at an earlier launch and not back): tile
  // i belongs to device i mod N of the whole set, and only a lost device's tiles move.
  const bool stable = NeedsStableOwnership(*this);
  std::vector<DeviceSlot*> slots;
  std::vector<scheduler::DispatchDevice> devices;
  int total_threads = 0;
  for (DeviceSlot& slot : device_slots()) {
    if (slot.device == nullptr && !stable) continue;
    slots.push_back(&slot);
    scheduler::DispatchDevice device;
    device.device = slot.device.get();
    device.name = absl::StrCat("'", slot.desc.name, "' (", slot.desc.address, ")");
    device.threads = slot.device != nullptr ? std::max(1, slot.device->Info().thread_count)
                                            : std::max(1, slot.threads);
    device.header = common;
    device.header.set_session_id(slot.sync.session_id);
    total_threads += device.threads;
    devices.push_back(std::move(device));
  }
  auto tile_size = TileSizeFor(*this, dims, total_threads, slots.size());
  if (!tile_size.ok()) return tile_size.status();
  if (stable && slots.size() > 1) WarnIfTilesMoved(*this, launch_id, dims, *tile_size);
  // No tiles for the all-zero launch: each device then runs one empty call, which builds its
  // accelerations (bounding-box programs may write buffers: their regions are gathered too).
  std::vector<v1::Tile> tiles = scheduler::MakeTiles(dims, *tile_size);
  StartProgress(tiles.size());

  gather.SetDevices(slots);
  uint64_t indices = 1;
  for (uint64_t d : dims) indices *= d;
  const auto devices_began = std::chrono::steady_clock::now();
  TileCosts& costs = tile_costs(entry_point);
  const bool same_size = costs.dims == dims;
  const bool same_tiles = same_size && costs.tile_size == *tile_size;
  scheduler::Dispatcher dispatcher(
      std::move(devices), std::move(tiles), stable, progress_counter(),
      MinIndicesPerCall(same_size ? costs.ns_per_index : 0.0),
      same_tiles && CostBatches() ? costs.costs : std::vector<float>());

  // The launching thread applies results as they arrive and polls the timeout callback.
  std::vector<scheduler::FinishedBatch> batches;
  while (true) {
    const bool done = dispatcher.Wait(poller.deadline(), &batches);
    for (scheduler::FinishedBatch& batch : batches) {
      const auto start = std::chrono::steady_clock::now();
      gather.Apply(batch);
      for (v1::TileResult& r : batch.results) scheduler::RecycleTileResult(std::move(r));
      timing.apply += std::chrono::steady_clock::now() - start;
    }
    batches.clear();
    if (done) break;
    if (!poller.cancelled() && poller.Poll()) dispatcher.Cancel();
  }

  {
    const absl::Status outcome = dispatcher.status();
    const LostTiles tiles = poller.cancelled() ? LostTiles::kLaunchEnded
                            : outcome.ok()     ? LostTiles::kRanElsewhere
                            : outcome.code() == absl::StatusCode::kUnavailable
                                ? LostTiles::kNoDeviceLeft
                                : LostTiles::kLaunchEnded;
    for (const scheduler::LostDevice& lost : dispatcher.lost()) {
      WarnLost(*this, *slots[lost.device], launch_id, lost.reason, tiles);
    }
  }

  timing.Mark("devices");
  if (dispatcher.status().ok() && !poller.cancelled() && indices > 0) {
    const double ns =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - devices_began)
            .count();
    costs = TileCosts{dims, *tile_size, ns * total_threads / static_cast<double>(indices),
                      dispatcher.tile_costs()};
  }
  absl::Status tile_status = gather.Finish();
  const bool every_index_ran = dispatcher.status().ok() && !poller.cancelled() && tile_status.ok();
  if (choosing && every_index_ran &&
      auto_batching().Record(entry_point, indices, gather.traces(), gather.packet_answers())) {
    log::Debug(log::Component::kApi,
               "launch %llu: entry point %u now %s (its launch indices traced %.2f rays each, "
               "packets answered %.2f of their first rays; docs/programs.md, \"Batched tracing\")",
               static_cast<unsigned long long>(launch_id), entry_point,
               ToString(auto_batching().state(entry_point)),
               static_cast<double>(gather.traces()) / static_cast<double>(indices),
               static_cast<double>(gather.packet_answers()) / static_cast<double>(indices));
  }
  // Batches that did not finish left their writes in the devices' copies only.
  if (!every_index_ran) gather.ForgetDeviceCopies();
  timing.Mark("finish");
  timing.Report(launch_id);
  for (const scheduler::LostDevice& lost : dispatcher.lost()) LoseDevice(*slots[lost.device]);

  for (const auto& [id, object] : objects()) {
    if (object->kind() == Kind::kBuffer) {
      static_cast<Buffer*>(object)->SyncDevicePointersAfterLaunch();
    }
  }

  absl::Status status = dispatcher.status();
  if (poller.cancelled()) {
    return RtError(RT_TIMEOUT_CALLBACK, "launch cancelled by the timeout callback");
  }
  if (status.code() == absl::StatusCode::kUnavailable) {
    return RtError(RT_ERROR_CONNECTION_FAILED,
                   absl::StrCat("launch ", launch_id, " failed: ", status.message()));
  }
  if (!status.ok()) {
    const int d = dispatcher.failed_device();
    if (d >= 0) return DeviceError(*slots[d], "failed the launch", status);
    return RtError(RT_ERROR_LAUNCH_FAILED, std::string(status.message()));
  }
  return tile_status;
}

}  // namespace tessera::api
