#include "optix7_device_call.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "absl/strings/str_cat.h"
#include "call_progress.h"
#include "device_arena.h"
#include "float_mode.h"
#include "optix7_atomics.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"
#include "tessera/scheduler/launch_timing.h"
#include "tessera/scheduler/log.h"
#include "tile_pieces.h"
#include "write_tracker.h"

namespace tessera::worker {
namespace {

// Written bytes per region message: well under the wire's 64 MiB, and small enough that the
// host applies one while the next arrives.
constexpr size_t kRegionBytes = size_t{4} << 20;

// The process's write tracker over its device memory range, made at the first call that reports
// writes and kept (one tracker may be armed in a process; calls hold Optix7CallMutex).
absl::StatusOr<memory::WriteTracker*> ProcessTracker() {
  static std::unique_ptr<memory::WriteTracker> tracker;
  if (tracker != nullptr) return tracker.get();
  absl::StatusOr<memory::DeviceArena*> arena = memory::ProcessArena();
  if (!arena.ok()) return arena.status();
  absl::StatusOr<std::unique_ptr<memory::WriteTracker>> made =
      memory::WriteTracker::Create((*arena)->base(), (*arena)->size());
  if (!made.ok()) return made.status();
  tracker = *std::move(made);
  return tracker.get();
}

// How the writes to each allocation are found, chosen from what the last calls saw (per process:
// calls hold Optix7CallMutex): write-protection costs a fault per page programs write (tens of
// microseconds with several threads, whose TLBs each change of protection flushes) and nothing
// for memory they only read; a copy before the call costs a copy and a compare of every page
// however few are written. An allocation whose pages the last call wrote more than one in 16 of
// is copied next time; a copied one goes back to protection after kCalmCalls calls that changed
// fewer than one page in 64 of it.
struct TrackingMode {
  bool copy = false;
  int calm = 0;  // calls in a row that changed few of its pages, while copied
};
constexpr int kCalmCalls = 3;
std::map<uint64_t, TrackingMode>& TrackingModes() {
  static auto* const modes = new std::map<uint64_t, TrackingMode>;
  return *modes;
}

// Packs `runs` into region results (device_memory), with their bytes unless `with_data` is off.
void SendRuns(const std::vector<memory::WriteTracker::Run>& runs, bool with_data,
              const v1::LaunchRequest& request, uint64_t sequence,
              const std::function<void(v1::TileResult&&)>& on_result) {
  v1::TileResult result;
  v1::BufferRegion* region = nullptr;
  auto flush = [&] {
    if (region == nullptr) return;
    result.set_launch_id(request.launch_id());
    result.set_tile_index(kFinalTileIndex);
    result.set_call_sequence(sequence);
    on_result(std::move(result));
    result = v1::TileResult();
    region = nullptr;
  };
  for (const auto& [address, size] : runs) {
    uintptr_t at = address;
    size_t left = size;
    while (left > 0) {
      if (region != nullptr && with_data && region->data().size() >= kRegionBytes) flush();
      if (region == nullptr) {
        region = result.add_regions();
        region->set_device_memory(true);
      }
      const size_t take = with_data ? std::min(left, kRegionBytes) : left;
      region->add_run_offsets(at);
      region->add_run_sizes(take);
      if (with_data) region->mutable_data()->append(reinterpret_cast<const char*>(at), take);
      at += take;
      left -= take;
    }
  }
  flush();
}

// Combined atomics per region message: 24 bytes each on the wire, well under its limit.
constexpr size_t kAtomicsPerRegion = size_t{1} << 16;

// Sends `atomics` (AtomicsToSend) as device-memory regions without runs.
void SendAtomics(const std::vector<CombinedAtomic>& atomics, const v1::LaunchRequest& request,
                 uint64_t sequence, const std::function<void(v1::TileResult&&)>& on_result) {
  for (size_t first = 0; first < atomics.size(); first += kAtomicsPerRegion) {
    v1::TileResult result;
    result.set_launch_id(request.launch_id());
    result.set_tile_index(kFinalTileIndex);
    result.set_call_sequence(sequence);
    v1::BufferRegion* region = result.add_regions();
    region->set_device_memory(true);
    const size_t last = std::min(atomics.size(), first + kAtomicsPerRegion);
    region->mutable_atomics()->Reserve(static_cast<int>(last - first));
    for (size_t i = first; i < last; ++i) {
      v1::DeviceMemoryAtomic* a = region->add_atomics();
      a->set_address(atomics[i].address);
      a->set_op(atomics[i].op);
      a->set_operand(atomics[i].operand);
      a->set_limit(atomics[i].limit);
    }
    on_result(std::move(result));
  }
}

// Chooses each allocation's tracking for the next call (TrackingMode).
void UpdateTrackingModes(const std::map<uint64_t, uint64_t>& allocations,
                         const std::vector<std::pair<uintptr_t, size_t>>& faulted,
                         const std::vector<memory::WriteTracker::Run>& runs) {
  const size_t page = memory::DeviceArena::PageSize();
  auto& modes = TrackingModes();
  // Forget allocations that are gone.
  for (auto it = modes.begin(); it != modes.end();) {
    it = allocations.count(it->first) != 0 ? std::next(it) : modes.erase(it);
  }
  auto pages_of = [page](uint64_t size) { return std::max<uint64_t>(1, (size + page - 1) / page); };
  for (const auto& [address, written] : faulted) {
    auto it = allocations.find(address);  // protected ranges are whole allocations
    if (it == allocations.end()) continue;
    const uint64_t pages = pages_of(it->second);
    if (written > 16 && written * 16 > pages) modes[it->first] = TrackingMode{true, 0};
  }
  // Pages with changed bytes per copied allocation.
  std::map<uint64_t, uint64_t> changed;
  uintptr_t last_page = 0;
  for (const auto& [address, size] : runs) {
    for (uintptr_t p = address / page * page; p < address + size; p += page) {
      if (p == last_page) continue;
      last_page = p;
      auto it = allocations.upper_bound(p + page - 1);
      if (it == allocations.begin()) continue;
      --it;
      ++changed[it->first];
    }
  }
  for (auto& [address, mode] : modes) {
    if (!mode.copy) continue;
    auto size = allocations.find(address);
    if (size == allocations.end()) continue;
    const uint64_t pages = pages_of(size->second);
    mode.calm = changed[address] * 64 < pages ? mode.calm + 1 : 0;
    if (mode.calm >= kCalmCalls) mode = TrackingMode{};
  }
}

}  // namespace

absl::Status RunOptix7Call(Optix7Engine& engine, const Optix7Session& session,
                           const v1::LaunchRequest& request, tbb::task_arena& arena, int threads,
                           uint64_t sequence, const std::atomic<bool>& cancel,
                           const std::function<void(v1::TileResult&&)>& on_result) {
  const auto started = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> call_lock(Optix7CallMutex());
  if (absl::Status s = engine.Prepare(session.state(), request.optix7(), &cancel); !s.ok()) {
    return s;
  }
  const auto prepared = std::chrono::steady_clock::now();
  Index3 dims{1, 1, 1};
  bool empty = false;
  for (int i = 0; i < request.dims_size(); ++i) {
    dims[i] = static_cast<uint32_t>(request.dims(i));
    empty = empty || request.dims(i) == 0;
  }
  memory::WriteTracker* tracker = nullptr;
  if (request.optix7().report_writes() && !empty) {
    absl::StatusOr<memory::WriteTracker*> made = ProcessTracker();
    if (!made.ok()) {
      return absl::Status(
          made.status().code(),
          absl::StrCat("cannot track writes to device memory: ", made.status().message()));
    }
    tracker = *made;
    // Copies first: a page shared with a protected allocation must end up protected.
    auto& modes = TrackingModes();
    for (int pass = 0; pass < 2; ++pass) {
      for (const auto& [address, size] : session.state().allocations) {
        const bool copy = modes[address].copy;
        if (copy != (pass == 0)) continue;
        absl::Status s = copy ? tracker->Snapshot(address, size) : tracker->Protect(address, size);
        if (!s.ok()) {
          (void)tracker->Collect();
          return s;
        }
      }
    }
  }

  // A device with its own copy of device memory notes its programs' atomics, for the host to
  // apply to its copy; one that shares the host's memory (in-process) operates on the host's
  // copy itself, atomically, and notes nothing.
  const bool note_atomics = tracker != nullptr && !session.shares_host_memory();
  if (note_atomics) BeginAtomicNotes();

  const auto armed = std::chrono::steady_clock::now();
  std::mutex failure_mu;  // failure, from a piece that failed
  std::atomic<bool> stop{false};
  absl::Status failure;
  const std::vector<TilePiece> pieces =
      SplitTiles(request.tiles(), dims, threads, request.optix7().batched());
  CallTiles tiles(request, pieces, started, on_result);
  auto run_piece = [&](const TilePiece& piece) {
    v1::TileResult part;
    bool done = false;
    try {
      done = engine.RunTile(piece.origin, piece.size, dims, cancel, stop, part);
    } catch (const FatalError& e) {
      std::lock_guard<std::mutex> lock(failure_mu);
      if (failure.ok()) failure = e.status;
      stop = true;
      part.set_error(std::string(e.status.message()));
      part.set_error_code(RT_ERROR_LAUNCH_FAILED);
      done = true;
    }
    tiles.PieceEnded(piece.tile, done, part);
  };
  if (!empty) {
    const bool flush_denormals = engine.FlushDenormals();
    arena.execute([&] {
      tbb::parallel_for(size_t{0}, pieces.size(), size_t{1}, [&](size_t i) {
        // Each piece sets its thread's mode and puts it back: arena threads are shared.
        ScopedFloatMode float_mode(flush_denormals);
        run_piece(pieces[i]);
      });
    });
  }
  const auto traced = std::chrono::steady_clock::now();
  // Collected whatever happened, so that the next call starts with nothing protected.
  std::vector<memory::WriteTracker::Run> runs;
  std::vector<CombinedAtomic> atomics;
  if (note_atomics) atomics = AtomicsToSend(EndAtomicNotes(), session.state().allocations);
  if (tracker != nullptr) {
    std::vector<std::pair<uintptr_t, size_t>> faulted;
    runs = tracker->Collect(&faulted);
    UpdateTrackingModes(session.state().allocations, faulted, runs);
    runs = RunsWithoutAtomics(runs, atomics);
  }
  const auto collected = std::chrono::steady_clock::now();
  if (!failure.ok()) return failure;
  if (cancel.load()) return absl::CancelledError("launch cancelled");
  SendRuns(runs, !session.shares_host_memory(), request, sequence, on_result);
  SendAtomics(atomics, request, sequence, on_result);
  if (scheduler::LaunchTimingEnabled()) {
    auto ms = [](auto a, auto b) {
      return std::chrono::duration<double, std::milli>(b - a).count();
    };
    log::Info(log::Component::kWorker,
              "OptiX 7 device call of launch %llu: prepare %.1fms, write tracking set up %.1fms, "
              "tiles %.1fms, writes collected %.1fms (%zu runs, %zu atomics), sent %.1fms",
              static_cast<unsigned long long>(request.launch_id()), ms(started, prepared),
              ms(prepared, armed), ms(armed, traced), ms(traced, collected), runs.size(),
              atomics.size(), ms(collected, std::chrono::steady_clock::now()));
  }
  // The call's end, also when nothing was written: the host counts the call's tiles by it.
  v1::TileResult end;
  end.set_launch_id(request.launch_id());
  end.set_tile_index(kFinalTileIndex);
  end.set_call_sequence(sequence);
  on_result(std::move(end));
  return absl::OkStatus();
}

}  // namespace tessera::worker
