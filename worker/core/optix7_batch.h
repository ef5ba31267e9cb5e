// Batched tracing for the OptiX 7 engine (docs/programs.md, "Batched tracing"): the launch indices
// of one block of the launch grid run as lanes (lanes.h) until each waits at an optixTrace or is
// done; the waiting rays go to Embree together as one 16-wide packet per scene, and the lanes
// resume with their answers, so closest-hit and miss programs of a batch run back to back and
// their own traces batch again. Blocks are aligned to the launch grid (4x4 in 2D and 3D, 16 in
// 1D) and tiles and pieces are made of whole blocks, so the lanes a ray shares its packet with
// depend on its launch index alone, not on tiling or devices. Internal to worker/core.
#ifndef TESSERA_WORKER_CORE_OPTIX7_BATCH_H_
#define TESSERA_WORKER_CORE_OPTIX7_BATCH_H_

#include <embree3/rtcore.h>

#include <array>
#include <exception>
#include <memory>

#include "lanes.h"
#include "optix7_thread.h"

namespace tessera::worker {

class Optix7Batch;

struct Optix7Lane {
  Optix7Thread ts;  // the launch index's state, Optix7TS() while the lane runs
  Optix7Batch* batch = nullptr;
  void* sp = nullptr;  // where its stack resumes
  bool waiting = false;
  LaneSanitizer sanitizer;  // the lane's side of its switches
  // While waiting: the ray (answered in place) and the scene it is traced in.
  RTCRayHit* ray = nullptr;
  const Optix7Scene* scene = nullptr;
  // What left the launch index other than an OptiX exception (a FatalError): rethrown by RunBlock.
  std::exception_ptr error;
};

class Optix7Batch {
 public:
  static constexpr unsigned kLanes = 16;

  Optix7Batch();
  Optix7Batch(const Optix7Batch&) = delete;
  Optix7Batch& operator=(const Optix7Batch&) = delete;

  // Prepares the lanes for a tile of `thread` (its launch, results and reports); `run` runs one
  // launch index (RunIndex).
  void BeginTile(Optix7Thread& thread, void (*run)(Optix7Thread&));
  // Runs every launch index of the block [origin, origin + size) (at most kLanes of them) as a
  // lane. Rethrows what a lane threw past `run`; the tile ends with it.
  void RunBlock(const Index3& origin, const Index3& size);

  // From a lane's optixTrace: suspends the lane until its ray has been traced in `scene` with
  // the other waiting lanes', its answer in `ray`.
  static void Wait(Optix7Thread& ts, const Optix7Scene& scene, RTCRayHit& ray) {
    Optix7Lane& lane = *ts.lane;
    lane.ray = &ray;
    lane.scene = &scene;
    lane.waiting = true;
    lane.sanitizer.BeforeBack();
    tessera_lane_switch(&lane.sp, lane.batch->scheduler_sp_);
    lane.sanitizer.AfterIntoLane();
  }

 private:
  static void LaneMain(void* lane);
  // Inlined into RunBlock: after a switch back from a lane, a return would be predicted from the
  // lane's calls (the return stack buffer is the CPU's, not the stack's) and mispredicted.
  __attribute__((always_inline)) inline void Resume(Optix7Lane& lane);
  void TraceWaiting();

  std::array<Optix7Lane, kLanes> lanes_;
  std::array<std::unique_ptr<LaneStack>, kLanes> stacks_;
  void (*run_)(Optix7Thread&) = nullptr;
  Optix7Thread* thread_ = nullptr;
  void* scheduler_sp_ = nullptr;
  LaneSanitizer sanitizer_;  // the scheduler's side
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_BATCH_H_
