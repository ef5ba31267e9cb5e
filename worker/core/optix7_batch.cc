#include "optix7_batch.h"

#include "packet16.h"

namespace tessera::worker {
namespace {

// A lane's stack: the native stack budget a launch index may use (optixTrace and callables raise
// STACK_OVERFLOW past it, as on a thread's own stack) and a reserve below it for the engine,
// Embree and a program that is still running when it is crossed.
constexpr size_t kLaneStackBytes = kOptix7StackBudget + 768 * 1024;

}  // namespace

Optix7Batch::Optix7Batch() {
  for (Optix7Lane& lane : lanes_) lane.batch = this;
}

void Optix7Batch::LaneMain(void* arg) {
  auto& lane = *static_cast<Optix7Lane*>(arg);
  Optix7Batch& batch = *lane.batch;
  // One launch index per resumption once the last one ended: the lane's stack stays laid out for
  // the tile.
  lane.sanitizer.AfterIntoLane();
  for (;;) {
    try {
      batch.run_(lane.ts);
    } catch (...) {
      lane.error = std::current_exception();
    }
    lane.sanitizer.BeforeBack();
    tessera_lane_switch(&lane.sp, batch.scheduler_sp_);
    lane.sanitizer.AfterIntoLane();
  }
}

void Optix7Batch::BeginTile(Optix7Thread& thread, void (*run)(Optix7Thread&)) {
  run_ = run;
  thread_ = &thread;
  for (unsigned k = 0; k < kLanes; ++k) {
    Optix7Lane& lane = lanes_[k];
    if (stacks_[k] == nullptr) stacks_[k] = std::make_unique<LaneStack>(kLaneStackBytes, k);
    Optix7Thread& ts = lane.ts;
    ts.launch = thread.launch;
    ts.dims = thread.dims;
    ts.out = thread.out;
    ts.tile = &thread;
    ts.lane = &lane;
    ts.stack_limit = stacks_[k]->base() + (stacks_[k]->size() - kOptix7StackBudget);
    ts.stack_floor = stacks_[k]->base();
    // Afresh each tile: a tile that was interrupted or failed left its lanes anywhere.
    lane.sp = stacks_[k]->Start(&LaneMain, &lane);
    lane.waiting = false;
    lane.error = nullptr;
  }
}

inline void Optix7Batch::Resume(Optix7Lane& lane) {
  t_optix7 = &lane.ts;
  const LaneStack& stack = *stacks_[&lane - lanes_.data()];
  sanitizer_.Before(stack.base(), stack.size());
  tessera_lane_switch(&scheduler_sp_, lane.sp);
  sanitizer_.AfterBackFromLane();
  t_optix7 = thread_;
  if (lane.error) {
    std::exception_ptr e = lane.error;
    lane.error = nullptr;
    std::rethrow_exception(e);  // the other lanes of the block are abandoned with it
  }
}

void Optix7Batch::TraceWaiting() {
  // One packet per scene among the waiting lanes, scenes in the order of their first lane.
  static_assert(kLanes == 16, "one rtcIntersect16 per scene");
  RTCRayHit* rays[kLanes];
  for (unsigned k = 0; k < kLanes; ++k) rays[k] = lanes_[k].ray;
  ForEachSceneGroup(
      static_cast<int>(kLanes),
      [&](int k) { return lanes_[k].waiting ? lanes_[k].scene : nullptr; },
      [&](const Optix7Scene* scene, int, const int* valid, int) {
        IntersectPacket16(scene->scene, valid, rays);
      });
}

void Optix7Batch::RunBlock(const Index3& origin, const Index3& size) {
  unsigned n = 0;
  for (uint32_t z = origin[2]; z < origin[2] + size[2]; ++z) {
    for (uint32_t y = origin[1]; y < origin[1] + size[1]; ++y) {
      for (uint32_t x = origin[0]; x < origin[0] + size[0]; ++x) {
        Optix7Lane& lane = lanes_[n++];
        lane.ts.index = {x, y, z};
        lane.waiting = false;
      }
    }
  }
  for (unsigned k = n; k < kLanes; ++k) lanes_[k].waiting = false;
  for (unsigned k = 0; k < n; ++k) Resume(lanes_[k]);
  for (;;) {
    bool any = false;
    for (unsigned k = 0; k < n; ++k) any = any || lanes_[k].waiting;
    if (!any) break;
    TraceWaiting();
    for (unsigned k = 0; k < n; ++k) {
      Optix7Lane& lane = lanes_[k];
      if (!lane.waiting) continue;
      lane.waiting = false;
      Resume(lane);
    }
  }
}

}  // namespace tessera::worker
