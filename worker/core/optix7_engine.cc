// Optix7Engine's tiles: the launch indices of a tile, each running the raygen program; exceptions
// raised at an index go to the exception program, or without one to the tile's reports; and the
// helpers every part of the engine raises and fails through.
#include "optix7_engine.h"

#include <pthread.h>

#include <algorithm>
#include <csetjmp>
#include <cstring>
#include <memory>
#include <mutex>
#include <vector>

#include "absl/strings/str_cat.h"
#include "batch_block.h"
#include "interrupt.h"
#include "optix7_batch.h"
#include "optix7_launch.h"
#include "optix7_thread.h"
#include "optix_types.h"
#include "tessera/worker/crash_report.h"

namespace tessera::worker {

__thread Optix7Thread* t_optix7 __attribute__((tls_model("initial-exec"))) = nullptr;

namespace {

thread_local std::unique_ptr<Optix7Thread> t_optix7_owner;  // frees the state at thread end

// The native stack a launch index may use for nested optixTrace and callable calls is measured
// from where its tile began (kOptix7StackBudget), so that where deep recursion runs out does not
// depend on the thread (TBB's have 4 MiB of stack, others 8 MiB). As the OptiX 3 engine's
// (thread_state.h).

std::string IndexText(const Index3& i) {
  return absl::StrCat("(", i[0], ", ", i[1], ", ", i[2], ")");
}

const char* KindName(Optix7Kind k) {
  switch (k) {
    case Optix7Kind::kRaygen:
      return "raygen";
    case Optix7Kind::kMiss:
      return "miss";
    case Optix7Kind::kClosestHit:
      return "closest-hit";
    case Optix7Kind::kAnyHit:
      return "any-hit";
    case Optix7Kind::kIntersection:
      return "intersection";
    case Optix7Kind::kException:
      return "exception";
    case Optix7Kind::kDirectCallable:
      return "direct-callable";
    case Optix7Kind::kContinuationCallable:
      return "continuation-callable";
  }
  return "unknown";
}

}  // namespace

Optix7Thread& CreateOptix7Thread() {
  t_optix7_owner = std::make_unique<Optix7Thread>();
  t_optix7 = t_optix7_owner.get();
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) == 0) {
    void* base = nullptr;
    size_t size = 0;
    if (pthread_attr_getstack(&attr, &base, &size) == 0 && base != nullptr) {
      constexpr size_t kReserve = 256 * 1024;  // one more level of engine, Embree and program
      t_optix7->stack_floor = static_cast<const char*>(base) + std::min(size / 2, kReserve);
    }
    pthread_attr_destroy(&attr);
  }
  return *t_optix7;
}

namespace {

// The crash line's query (crash_report.h): the program the thread's context names. Reads only
// the thread's initial-exec state pointer and what it points to: async-signal-safe.
bool RunningOptix7Program(const char** kind, const char** name) {
  const Optix7Thread* ts = t_optix7;
  if (ts == nullptr || ts->ctx.record == nullptr || ts->ctx.record->group == nullptr) return false;
  const Optix7Group& g = *ts->ctx.record->group;
  const Optix7Entry* entry = &g.entry;
  switch (ts->ctx.kind) {
    case Optix7Kind::kClosestHit:
      entry = &g.closest_hit;
      break;
    case Optix7Kind::kAnyHit:
      entry = &g.any_hit;
      break;
    case Optix7Kind::kIntersection:
      entry = &g.intersection;
      break;
    case Optix7Kind::kContinuationCallable:
      entry = &g.continuation;
      break;
    default:
      break;
  }
  *kind = KindName(ts->ctx.kind);
  *name = entry->name.c_str();
  return true;
}

[[maybe_unused]] const bool kCrashQueryInstalled = [] {
  SetOptix7ProgramQuery(&RunningOptix7Program);
  return true;
}();

}  // namespace

std::mutex& Optix7CallMutex() {
  static std::mutex mu;
  return mu;
}

const char* ExceptionCodeName(int code) {
  switch (code) {
    case OPTIX_EXCEPTION_CODE_STACK_OVERFLOW:
      return "OPTIX_EXCEPTION_CODE_STACK_OVERFLOW";
    case OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED:
      return "OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED";
    case OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_MISS_SBT:
      return "OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_MISS_SBT";
    case OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_HIT_SBT:
      return "OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_HIT_SBT";
    case OPTIX_EXCEPTION_CODE_INVALID_RAY:
      return "OPTIX_EXCEPTION_CODE_INVALID_RAY";
    case OPTIX_EXCEPTION_CODE_CALLABLE_INVALID_SBT:
      return "OPTIX_EXCEPTION_CODE_CALLABLE_INVALID_SBT";
    case OPTIX_EXCEPTION_CODE_CALLABLE_NO_DC_SBT_RECORD:
      return "OPTIX_EXCEPTION_CODE_CALLABLE_NO_DC_SBT_RECORD";
    case OPTIX_EXCEPTION_CODE_CALLABLE_NO_CC_SBT_RECORD:
      return "OPTIX_EXCEPTION_CODE_CALLABLE_NO_CC_SBT_RECORD";
    case OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_0:
      return "OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_0";
    case OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_1:
      return "OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_1";
    case OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_2:
      return "OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_2";
    default:
      return code >= 0 ? "user exception" : "exception";
  }
}

std::string ProgramName(const Optix7Context& ctx) {
  const Optix7Group* g = ctx.record != nullptr ? ctx.record->group : nullptr;
  if (g == nullptr) return absl::StrCat("a ", KindName(ctx.kind), " program");
  const Optix7Entry* e = &g->entry;
  switch (ctx.kind) {
    case Optix7Kind::kClosestHit:
      e = &g->closest_hit;
      break;
    case Optix7Kind::kAnyHit:
      e = &g->any_hit;
      break;
    case Optix7Kind::kIntersection:
      e = &g->intersection;
      break;
    case Optix7Kind::kContinuationCallable:
      e = &g->continuation;
      break;
    default:
      break;
  }
  return absl::StrCat(KindName(ctx.kind), " program ", e->name, " (program group ", g->id, ")");
}

void Raise(Optix7Thread& ts, Optix7Exception e, const std::string& what) {
  e.text = absl::StrCat("Caught ", ExceptionCodeName(e.code), " (", e.code, ") at launch index ",
                        IndexText(ts.index), ": ", what, " (in ", ProgramName(ts.ctx), ")");
  throw e;
}

void Fail(const Optix7Thread& ts, const char* call, const std::string& what) {
  throw FatalError{absl::FailedPreconditionError(absl::StrCat(
      call, " from ", ProgramName(ts.ctx), " at launch index ", IndexText(ts.index), ": ", what))};
}

void CheckKind(const Optix7Thread& ts, unsigned kinds, const char* call) {
  if (__builtin_expect(!(kinds & KindBit(ts.ctx.kind)), 0)) {
    Fail(ts, call, absl::StrCat("not allowed in a ", KindName(ts.ctx.kind), " program"));
  }
}

namespace {

// A scene a pipeline's compile options do not allow for: what OptiX leaves undefined (its
// programs were specialized without it), reported with what the options said.
void CheckCompileOptions(const Optix7Thread& ts, const Optix7Scene& s, uint64_t handle,
                         const char* call) {
  const Optix7Launch& l = *ts.launch;
  // Made only for a message: a program alternating between two roots comes here per trace.
  auto scene = [handle] { return absl::StrCat("traversable 0x", absl::Hex(handle)); };
  const unsigned graph = l.graph_flags;
  const bool instances = s.kind == memory::AccelKind::kInstances;
  if (graph == OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS && instances) {
    Fail(ts, call,
         absl::StrCat(scene(),
                      " is an instance acceleration, but the pipeline's "
                      "traversableGraphFlags allow a single GAS only"));
  }
  if ((graph & OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING) != 0 && instances &&
      !s.single_level) {
    Fail(ts, call,
         absl::StrCat(scene(),
                      " has transforms or instance accelerations below its instances, but "
                      "the pipeline's traversableGraphFlags allow single-level instancing "
                      "(use OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY)"));
  }
  const unsigned primitives = l.primitive_flags != 0
                                  ? l.primitive_flags
                                  : OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM |
                                        static_cast<unsigned>(OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE);
  if ((s.primitive_types & ~primitives) != 0) {
    Fail(ts, call,
         absl::StrCat(scene(), " holds primitives of types 0x", absl::Hex(s.primitive_types),
                      " (OptixPrimitiveTypeFlags), but the pipeline's usesPrimitiveTypeFlags "
                      "are 0x",
                      absl::Hex(primitives)));
  }
  if (s.any_motion && !l.motion_blur) {
    Fail(ts, call,
         absl::StrCat(scene(),
                      " has motion (an acceleration or transform with motion keys), but "
                      "the pipeline was compiled with usesMotionBlur 0"));
  }
}

}  // namespace

const Optix7Scene* SceneOf(Optix7Thread& ts, uint64_t handle, const char* call) {
  if (ts.scene_serial == ts.launch->serial && ts.scene_handle == handle) return ts.scene;
  absl::StatusOr<const Optix7Scene*> s = ts.launch->engine->Scene(handle);
  if (!s.ok()) Fail(ts, call, std::string(s.status().message()));
  CheckCompileOptions(ts, **s, handle, call);
  ts.scene_serial = ts.launch->serial;
  ts.scene_handle = handle;
  ts.scene = *s;
  return *s;
}

void ResetOptix7Nesting(Optix7Thread& ts) {
  for (unsigned i = 0; i < ts.depth; ++i) {
    ts.frames[i].pending = nullptr;
    ts.frames[i].embree = nullptr;
  }
  ts.depth = 0;
  ts.callers.clear();
  ts.any_hit_end = nullptr;
}

namespace {

// Without an exception program, an exception ends its launch index with a report, as OptiX's
// default exception program prints one. A tile sends its first report and counts the rest, as
// OptiX 3 launches do (runtime.cc), so a launch that throws everywhere costs no memory per index.
void Report(Optix7Thread& ts, const Optix7Exception& e) {
  Optix7Thread& tile = *ts.tile;
  if (!tile.report_sent) {
    tile.report_sent = true;
    v1::ExceptionReport* r = tile.out->add_exceptions();
    for (uint32_t i : ts.index) r->add_launch_index(i);
    r->set_code(static_cast<uint32_t>(e.code));
    r->set_details(e.text);
    return;
  }
  v1::ExceptionReport*& rest = tile.reports_not_sent;
  if (rest == nullptr) rest = tile.out->add_exceptions();
  rest->set_not_sent(rest->not_sent() + 1);
  rest->set_not_sent_unshown(rest->not_sent_unshown() + 1);
}

__attribute__((noinline)) void HandleException(Optix7Thread& ts, Optix7Exception& e) {
  ResetOptix7Nesting(ts);
  const Optix7Record& ex = ts.launch->exception;
  if (ex.group == nullptr || ex.group->entry.function == nullptr) {
    Report(ts, e);
    return;
  }
  ts.exception = std::move(e);
  ts.ctx = Optix7Context{Optix7Kind::kException, &ex, nullptr, nullptr};
  try {
    ex.group->entry.function();
  } catch (Optix7Exception& inner) {
    // An exception inside the exception program ends the launch index with a report instead of
    // vanishing.
    ResetOptix7Nesting(ts);
    Report(ts, inner);
  }
}

// The thread's lanes, taken when its first batched tile runs and given back when it ends. Lanes
// outlive their threads: a launch's dispatch threads are new (scheduler/dispatcher.cc) and take
// pieces too, and mapping sixteen stacks for each, faulting their pages in and unmapping them as
// it ended (every unmap flushes the TLBs of all the process's cores) cost more with every thread.
class BatchPool {
 public:
  static BatchPool& Get() {
    static auto* pool = new BatchPool;  // never destroyed: threads may end after static exit
    return *pool;
  }
  std::unique_ptr<Optix7Batch> Take() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (!free_.empty()) {
        std::unique_ptr<Optix7Batch> batch = std::move(free_.back());
        free_.pop_back();
        return batch;
      }
    }
    return std::make_unique<Optix7Batch>();
  }
  void Give(std::unique_ptr<Optix7Batch> batch) {
    std::lock_guard<std::mutex> lock(mu_);
    free_.push_back(std::move(batch));
  }

 private:
  std::mutex mu_;
  std::vector<std::unique_ptr<Optix7Batch>> free_;  // at most as many as threads ever ran at once
};

Optix7Batch& ThreadBatch() {
  struct Holder {
    std::unique_ptr<Optix7Batch> batch;
    ~Holder() {
      if (batch != nullptr) BatchPool::Get().Give(std::move(batch));
    }
  };
  thread_local Holder holder;
  if (holder.batch == nullptr) holder.batch = BatchPool::Get().Take();
  return *holder.batch;
}

void RunIndex(Optix7Thread& ts) {
  const Optix7Record& rg = ts.launch->raygen;
  if (__builtin_expect(ts.depth != 0 || !ts.callers.empty(), 0)) ResetOptix7Nesting(ts);
  ts.ctx = Optix7Context{Optix7Kind::kRaygen, &rg, nullptr, nullptr};
  try {
    rg.group->entry.function();
  } catch (Optix7Exception& e) {
    HandleException(ts, e);
  }
}

// Out of RunTile, whose sigsetjmp would keep this loop's values out of registers.
__attribute__((noinline)) bool RunIndices(Optix7Thread& ts, const Index3& origin,
                                          const Index3& size, const Index3& dims,
                                          const std::atomic<bool>& cancel,
                                          const std::atomic<bool>& stop) {
  const Index3 end{std::min(origin[0] + size[0], dims[0]), std::min(origin[1] + size[1], dims[1]),
                   std::min(origin[2] + size[2], dims[2])};
  if (ts.launch->batched) {
    // Blocks of the launch grid (BatchBlock), clipped to the piece: whole blocks when pieces
    // are made of them (tile_pieces.h), as tiles are.
    Optix7Batch& batch = ThreadBatch();
    batch.BeginTile(ts, &RunIndex);
    return ForEachBlock(origin, size, dims, cancel, stop,
                        [&](const Index3& from, const Index3& to) {
                          batch.RunBlock(from, {to[0] - from[0], to[1] - from[1], 1});
                        });
  }
  for (uint32_t z = origin[2]; z < end[2]; ++z) {
    for (uint32_t y = origin[1]; y < end[1]; ++y) {
      for (uint32_t x = origin[0]; x < end[0]; ++x) {
        if (cancel.load(std::memory_order_relaxed) || stop.load(std::memory_order_relaxed)) {
          return false;
        }
        ts.index = {x, y, z};
        RunIndex(ts);
      }
    }
  }
  return true;
}

}  // namespace

Optix7Engine::Optix7Engine(RTCDevice device)
    : scenes_(device, Optix7IntersectFunction(), [this](uint64_t address) -> size_t {
        return launch_ != nullptr ? launch_->Readable(address) : 0;
      }) {
  scenes_.set_node_intersect(Optix7NodeIntersectFunction());
}

Optix7Engine::~Optix7Engine() = default;

bool Optix7Engine::FlushDenormals() const { return launch_ != nullptr && launch_->flush_denormals; }

absl::StatusOr<const Optix7Scene*> Optix7Engine::Scene(uint64_t handle) {
  std::lock_guard<std::mutex> lock(scenes_mu_);
  if (launch_ == nullptr) return scenes_.Get(handle, 0, 0);
  return scenes_.Get(handle, launch_->serial, launch_->accuracy);
}

bool Optix7Engine::RunTile(const Index3& origin, const Index3& size, const Index3& dims,
                           const std::atomic<bool>& cancel, const std::atomic<bool>& stop,
                           v1::TileResult& out) {
  if (launch_ == nullptr) {
    throw FatalError{absl::FailedPreconditionError("OptiX 7 tile run before Prepare")};
  }
  Optix7Thread& ts = Optix7TS();
  ts.launch = launch_.get();
  ts.dims = dims;
  ts.out = &out;
  ts.report_sent = false;
  ts.reports_not_sent = nullptr;
  const auto here = reinterpret_cast<uintptr_t>(__builtin_frame_address(0));
  ts.stack_limit = std::max(
      ts.stack_floor,
      reinterpret_cast<const char*>(here > kOptix7StackBudget ? here - kOptix7StackBudget : 0));
  struct Clear {  // nothing of the tile's outlives it
    Optix7Thread& ts;
    ~Clear() {
      ResetOptix7Nesting(ts);
      ts.out = nullptr;
      ts.reports_not_sent = nullptr;
      ts.ctx = Optix7Context{};
    }
  } clear{ts};
  // A program that never returns is jumped out of when the launch ends (interrupt.h); the index it
  // left half done is forgotten as an exception's would be, and the tile is abandoned.
  InterruptibleTile interruptible(cancel, stop);
  sigjmp_buf interrupted;
  if (sigsetjmp(interrupted, 0) != 0) {
    interruptible.Jumped();
    t_optix7 = &ts;  // the jump may have left a lane's stack: its lanes are never resumed
    ResetOptix7Nesting(ts);
    return false;
  }
  interruptible.Arm(&interrupted);
  return RunIndices(ts, origin, size, dims, cancel, stop);
}

}  // namespace tessera::worker
