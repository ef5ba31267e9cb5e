#include "tessera/worker/inproc_device.h"

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <system_error>
#include <thread>

#include "absl/strings/str_cat.h"
#include "call_arena.h"
#include "call_progress.h"
#include "float_mode.h"
#include "optix7_device_call.h"
#include "optix7_session.h"
#include "plan.h"
#include "replica.h"
#include "runtime.h"
#include "tessera/accuracy.h"
#include "tessera/rt.h"
#include "tessera/scheduler/launch_timing.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/result_pool.h"
#include "tessera/scheduler/tiling.h"
#include "tile_pieces.h"
#include "write_epochs.h"

namespace tessera {
namespace {

using worker::CallTiles;
using worker::FatalError;
using worker::Index3;
using worker::WriteEpochs;

// Launch indices per thread in a write epoch of a call whose results go out while it traces:
// small enough that a call of the dispatcher's usual size (16384 per thread) makes several.
constexpr uint64_t kEpochIndicesPerThread = 4096;
// The most threads a call runs on, whatever the context asks for.
constexpr uint32_t kMaxThreads = 256;

// Runs `f` on a long-lived thread of the process and waits for it. The in-process device builds
// its plans (and so commits Embree scenes) there: Embree keeps some memory for every thread that
// ever committed a scene, and a launch's calls come from dispatch threads started afresh for it,
// which cost ~0.25 KB a launch for good (docs/devices.md, "Memory over long use"). A few such
// threads serve all devices of the process: another starts when all are busy, so that one
// context's bounding box program that never returns cannot hold up another context's builds.
// `f` runs inline where no thread can be started (a process limit), and a child forked from the
// process starts its own (the parent's threads did not come along).
void RunOnPlanThread(const std::function<void()>& f) {
  constexpr int kMaxPlanThreads = 4;
  struct Job {
    const std::function<void()>* f;
    bool done = false;
    std::exception_ptr error;
  };
  struct State {
    pid_t pid = getpid();
    std::mutex mu;
    std::condition_variable work, finished;
    std::deque<Job*> queue;
    int threads = 0, idle = 0;  // under mu

    // Starts a plan thread (under mu); false where the process allows no more threads.
    bool Start() {
      try {
        std::thread([this] {
          std::unique_lock<std::mutex> lock(mu);
          for (;;) {
            ++idle;
            work.wait(lock, [this] { return !queue.empty(); });
            --idle;
            Job* job = queue.front();
            queue.pop_front();
            lock.unlock();
            try {
              (*job->f)();
            } catch (...) {
              job->error = std::current_exception();
            }
            lock.lock();
            job->done = true;
            finished.notify_all();
          }
        }).detach();
      } catch (const std::system_error&) {
        return false;
      }
      ++threads;
      return true;
    }
  };
  static std::atomic<State*> current{nullptr};
  State* state = current.load();
  if (state == nullptr || state->pid != getpid()) {
    auto* fresh = new State;  // never freed: its threads outlive every device
    // Install it unless another thread of this process installed one meanwhile (then that one
    // serves); a forked child replaces its parent's.
    while (!current.compare_exchange_weak(state, fresh)) {
      if (state != nullptr && state->pid == getpid()) break;
    }
    if (state == nullptr || state->pid != getpid()) state = fresh;
  }
  Job job{&f, false, nullptr};
  {
    std::unique_lock<std::mutex> lock(state->mu);
    // A thread counts as idle until it takes a job: jobs queued ahead of this one use them up.
    const bool busy = state->idle <= static_cast<int>(state->queue.size());
    if (busy && state->threads < kMaxPlanThreads && !state->Start() && state->threads == 0) {
      lock.unlock();
      f();
      return;
    }
    state->queue.push_back(&job);
    state->work.notify_one();
    state->finished.wait(lock, [&job] { return job.done; });
  }
  if (job.error) std::rethrow_exception(job.error);
}

// Runs `build` (making or refreshing a launch plan) on a plan thread; what it throws becomes its
// status.
template <typename F>
absl::Status OnPlanThread(F&& build) {
  absl::Status status;
  RunOnPlanThread([&] {
    try {
      status = build();
    } catch (const FatalError& e) {
      status = e.status;
    } catch (const std::bad_alloc&) {
      status = absl::ResourceExhaustedError(
          "the device ran out of memory building the launch's programs and accelerations");
    }
  });
  return status;
}

class InprocDevice : public Device {
 public:
  InprocDevice(int num_threads, bool results_in_rounds, bool shares_host_memory)
      : results_in_rounds_(results_in_rounds),
        shares_host_memory_(shares_host_memory),
        forced_epochs_(ForcedEpochs()),
        num_threads_(num_threads > 0 ? num_threads
                                     : static_cast<int>(std::thread::hardware_concurrency())),
        embree_(rtcNewDevice(nullptr)),
        scenes_(embree_) {}
  ~InprocDevice() override {
    optix7_engine_.reset();
    plan_.reset();
    scenes_ = worker::SceneCache(embree_);
    rtcReleaseDevice(embree_);
  }

  DeviceInfo Info() const override { return DeviceInfo{"inproc", "inproc", num_threads_}; }

  absl::Status Apply(const v1::StateDelta& delta) override {
    std::lock_guard<std::mutex> call_lock(call_mu_);
    // OptiX 7 state is checked first and applied once the replica took the delta: a delta is
    // applied whole or not at all.
    const bool optix7 = worker::Optix7Session::Carries(delta);
    if (optix7) {
      if (optix7_ == nullptr)
        optix7_ = std::make_unique<worker::Optix7Session>(shares_host_memory_);
      if (absl::Status s = optix7_->Check(delta); !s.ok()) return s;
    }
    absl::Status applied = replica_.Apply(delta);
    if (applied.ok() && optix7) applied = optix7_->Apply(delta);
    // Bound programs point into the replica: a plan outlives only deltas of values and of the
    // graph, which leave them valid (replica_values.cc).
    if (plan_ && plan_->bindings_generation != replica_.bindings_generation()) plan_.reset();
    return applied;
  }

  absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                      const std::function<void(v1::TileResult&&)>& on_result) override {
    // Calls run one after the other: each call's written regions are the marks it collects.
    std::lock_guard<std::mutex> call_lock(call_mu_);
    const auto started = std::chrono::steady_clock::now();
    if (cancel.load()) return absl::CancelledError("launch cancelled");
    if (request.dims_size() < 1 || request.dims_size() > 3) {
      return absl::InvalidArgumentError(
          absl::StrCat("launch with ", request.dims_size(), " dimensions"));
    }
    for (uint64_t d : request.dims()) {
      if (d > std::numeric_limits<uint32_t>::max()) {
        return absl::InvalidArgumentError(
            absl::StrCat("launch dimension ", d, " exceeds launch indices (unsigned int)"));
      }
    }
    for (const v1::Tile& t : request.tiles()) {
      if (t.origin_size() != request.dims_size() || t.size_size() != request.dims_size()) {
        return absl::InvalidArgumentError(absl::StrCat(
            "tile ", t.index(), " has ", t.origin_size(), " origin and ", t.size_size(),
            " size entries in a launch of ", request.dims_size(), " dimensions"));
      }
    }
    if (request.has_optix7()) return LaunchOptix7(request, cancel, on_result);
    // Before the plan: building accelerations runs bounding-box programs, which may write.
    if (request.launch_id() != snapshot_launch_id_) {
      replica_.SnapshotForLaunch();
      snapshot_launch_id_ = request.launch_id();
      calls_ = 0;
    }
    const uint64_t sequence = ++calls_;  // calls run one at a time: this is the order they ran
    if (plan_ && plan_->generation != replica_.generation() &&
        !worker::RefreshValues(*plan_, scenes_)) {
      plan_.reset();
    }
    if (plan_ && plan_->structure_generation != replica_.structure_generation()) {
      absl::Status refreshed =
          OnPlanThread([&] { return worker::RefreshGraph(*plan_, scenes_, &cancel); });
      if (!refreshed.ok()) {
        plan_.reset();
        return refreshed;
      }
    }
    if (!plan_ || plan_->generation != replica_.generation()) {
      absl::Status made = OnPlanThread([&] {
        absl::StatusOr<std::unique_ptr<worker::LaunchPlan>> plan =
            worker::MakePlan(replica_, scenes_, &cancel);
        if (!plan.ok()) return plan.status();
        plan_ = std::move(*plan);
        return absl::OkStatus();
      });
      if (!made.ok()) return made;
    }
    Index3 dims{1, 1, 1};
    bool empty = false;
    for (int i = 0; i < request.dims_size(); ++i) {
      dims[i] = static_cast<uint32_t>(request.dims(i));
      empty = empty || request.dims(i) == 0;
    }
    if (!empty && request.entry_point() >= plan_->ray_generation.size()) {
      return absl::InvalidArgumentError(
          absl::StrCat("entry point ", request.entry_point(), " out of range"));
    }

    // CPU_NUM_THREADS comes from the host as any 32-bit count; more threads than kMaxThreads
    // only cost memory (TBB itself warns past 1024).
    int threads =
        replica_.context().num_threads > 0
            ? static_cast<int>(std::min<uint32_t>(replica_.context().num_threads, kMaxThreads))
            : num_threads_;
    std::mutex failure_mu;  // failure, from a piece that failed
    std::atomic<bool> stop{false};
    std::atomic<int64_t> piece_ns{0};
    absl::Status failure;
    // A tile is reported when its last piece ends: not at all when a piece was cancelled, with
    // the error when a piece failed.
    const std::vector<worker::TilePiece> pieces =
        worker::SplitTiles(request.tiles(), dims, threads, request.batched());
    CallTiles tiles(request, pieces, started, on_result);
    // The call's rtTrace calls and packet answers, sent with its last result (TileResult).
    std::atomic<uint64_t> traces{0}, packet_answers{0};
    auto run_piece = [&](const worker::TilePiece& piece) {
      v1::TileResult part;
      bool done = false;
      const auto piece_start =
          timing_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
      try {
        done = worker::RunTile(*plan_, request.entry_point(), piece.origin, piece.size, dims,
                               cancel, stop, part, request.batched());
      } catch (const FatalError& e) {
        std::lock_guard<std::mutex> lock(failure_mu);
        if (failure.ok()) failure = e.status;
        stop = true;
        part.set_error(std::string(e.status.message()));
        part.set_error_code(RT_ERROR_LAUNCH_FAILED);
        done = true;
      }
      // How much of the call's thread time went into pieces, not waiting (TESSERA_LAUNCH_TIMING).
      if (timing_) piece_ns += (std::chrono::steady_clock::now() - piece_start).count();
      traces.fetch_add(part.traces(), std::memory_order_relaxed);
      packet_answers.fetch_add(part.packet_answers(), std::memory_order_relaxed);
      part.clear_traces();  // the call's figures go with its last result, not with each tile's
      part.clear_packet_answers();
      tiles.PieceEnded(piece.tile, done, part);
    };
    // Results go out in write epochs while later pieces trace (no barrier: nobody waits for a
    // round's last piece).
    WriteEpochs epochs(replica_, pieces.size(), Epochs(request, threads, pieces.size()));
    // A message for written regions, packed into one that held results before when there is
    // one (result_pool.h).
    auto regions_result = [&] {
      v1::TileResult r = scheduler::TakeTileResult();
      r.set_launch_id(request.launch_id());
      r.set_tile_index(kFinalTileIndex);
      r.set_call_sequence(sequence);
      return r;
    };
    auto send_closed = [&](unsigned char after, unsigned char upto) {
      while (upto != 0) {
        if (!stop.load() && !cancel.load()) {
          v1::TileResult partial = regions_result();
          replica_.TakeWrittenRegions(&partial, after, upto, /*last=*/false);
          if (partial.regions_size() > 0) {
            on_result(std::move(partial));
          } else {
            scheduler::RecycleTileResult(std::move(partial));
          }
        }
        upto = epochs.Sent(upto, &after);
      }
    };
    // Everything parallel in this call runs in an arena of the device's threads: a worker
    // process started with --threads 1 must not wake TBB threads for the other cores.
    tbb::task_arena& arena = arena_.Of(threads);
    if (!empty) {  // the all-zero launch only builds accelerations
      const bool flush_denormals = FlushDenormals();
      arena.execute([&] {
        tbb::parallel_for(size_t{0}, pieces.size(), size_t{1}, [&](size_t i) {
          const unsigned char epoch = epochs.Started();
          {
            // Each piece sets its thread's mode and puts it back: arena threads are shared, and
            // the calling thread (the host's own, in process) takes pieces too.
            worker::ScopedFloatMode float_mode(flush_denormals);
            run_piece(pieces[i]);
          }
          unsigned char after = 0;
          const unsigned char upto = epochs.Finished(epoch, &after);
          send_closed(after, upto);
        });
      });
    }
    const auto traced = std::chrono::steady_clock::now();
    v1::TileResult final_result = regions_result();
    // Taken even when the call failed, so that marks of unfinished tiles do not leak into the
    // next call's regions.
    arena.execute(
        [&] { replica_.TakeWrittenRegions(&final_result, epochs.sent(), 0, /*last=*/true); });
    replica_.SetWriteEpoch(1);  // bounding-box programs of the next call's builds mark with it
    if (timing_) {
      auto ms = [](std::chrono::steady_clock::duration d) {
        return std::chrono::duration<double, std::milli>(d).count();
      };
      const auto ended = std::chrono::steady_clock::now();
      log::Info(log::Component::kWorker,
                "device call of launch %llu: %d tiles %.1fms (%d threads ran pieces for %.1fms in "
                "all), regions %.1fms; monotonic clock %.1f to %.1fms",
                static_cast<unsigned long long>(request.launch_id()), request.tiles_size(),
                ms(traced - started), threads,
                ms(std::chrono::steady_clock::duration(piece_ns.load())), ms(ended - traced),
                ms(started.time_since_epoch()), ms(ended.time_since_epoch()));
    }
    if (!failure.ok()) return failure;
    if (cancel.load()) return absl::CancelledError("launch cancelled");
    final_result.set_traces(traces.load());
    final_result.set_packet_answers(packet_answers.load());
    on_result(std::move(final_result));
    return absl::OkStatus();
  }

  absl::StatusOr<v1::AccelerationBoundsReply> AccelerationBounds(
      const v1::AccelerationBoundsRequest& request) override {
    std::lock_guard<std::mutex> call_lock(call_mu_);  // builds happen inside Launch calls
    return scenes_.AccelerationBounds(request);
  }

 private:
  absl::Status LaunchOptix7(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                            const std::function<void(v1::TileResult&&)>& on_result) {
    if (optix7_ == nullptr) {
      return absl::FailedPreconditionError("an OptiX 7 launch before any OptiX 7 state arrived");
    }
    if (request.launch_id() != snapshot_launch_id_) {
      snapshot_launch_id_ = request.launch_id();
      calls_ = 0;
    }
    const uint64_t sequence = ++calls_;
    if (optix7_engine_ == nullptr) optix7_engine_ = std::make_unique<worker::Optix7Engine>(embree_);
    const int threads =
        replica_.context().num_threads > 0
            ? static_cast<int>(std::min<uint32_t>(replica_.context().num_threads, kMaxThreads))
            : num_threads_;
    return worker::RunOptix7Call(*optix7_engine_, *optix7_, request, arena_.Of(threads), threads,
                                 sequence, cancel, on_result);
  }

  // Whether this call's pieces flush denormals to zero (docs/fast_math.md): the plan binds a
  // program of a fast-math module, or the context asks for fast math. Looked up once per plan.
  bool FlushDenormals() {
    if (plan_->serial != fast_math_serial_) {
      fast_math_serial_ = plan_->serial;
      plan_fast_math_ = std::any_of(plan_->programs.begin(), plan_->programs.end(),
                                    [](const worker::BoundProgram& b) {
                                      return b.module != nullptr && b.module->fast_math();
                                    });
    }
    return plan_fast_math_ || (replica_.context().accuracy_flags & TESSERA_ACCURACY_FAST_MATH) != 0;
  }

  // How many write epochs a call runs in: one unless results go out while the call traces and
  // several threads would otherwise wait while one sends (a single thread has no one to wait for
  // it). TESSERA_WRITE_EPOCHS sets the number (tests: many epochs in small launches).
  unsigned char Epochs(const v1::LaunchRequest& request, int threads, size_t pieces) const {
    if (!results_in_rounds_ || threads <= 1 || pieces <= 1) return 1;
    uint64_t epochs = forced_epochs_;
    if (epochs == 0) {
      uint64_t indices = 0;
      for (const v1::Tile& t : request.tiles()) indices += scheduler::TileIndices(t);
      epochs = indices / (kEpochIndicesPerThread * threads);
    }
    return static_cast<unsigned char>(std::clamp<uint64_t>(epochs, 1, WriteEpochs::kMaxEpochs));
  }

  static uint64_t ForcedEpochs() {
    const char* env = std::getenv("TESSERA_WRITE_EPOCHS");
    return env != nullptr ? std::strtoull(env, nullptr, 10) : 0;
  }

  const bool results_in_rounds_;
  const bool shares_host_memory_;  // in the host's process: OptiX 7 device memory is the host's
  const uint64_t forced_epochs_;   // 0: by launch size
  int num_threads_;
  RTCDevice embree_;
  worker::Replica replica_;
  worker::SceneCache scenes_;
  std::unique_ptr<worker::LaunchPlan> plan_;
  std::unique_ptr<worker::Optix7Session> optix7_;        // once OptiX 7 state arrived
  std::unique_ptr<worker::Optix7Engine> optix7_engine_;  // at the first OptiX 7 launch
  worker::CallArena arena_;                              // under call_mu_
  std::mutex call_mu_;                                   // Apply and Launch calls, one at a time
  // TESSERA_LAUNCH_TIMING: where a call's time went, on stderr (api/src/launch.cc).
  const bool timing_ = scheduler::LaunchTimingEnabled();
  uint64_t snapshot_launch_id_ = 0;  // the launch whose start the replica's snapshots record
  uint64_t calls_ = 0;               // calls of that launch run so far
  uint64_t fast_math_serial_ = 0;    // the plan serial plan_fast_math_ is for (0: none)
  bool plan_fast_math_ = false;      // a program of plan_ is of a fast-math module
};

}  // namespace

std::unique_ptr<Device> CreateInprocDevice(int num_threads, bool results_in_rounds,
                                           bool shares_host_memory) {
  return std::make_unique<InprocDevice>(num_threads, results_in_rounds, shares_host_memory);
}

}  // namespace tessera
