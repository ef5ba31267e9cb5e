// Program execution: per-thread state, module slots, exceptions, printing, transforms and the
// TesseraRuntime table handed to modules. Every entry checks that the calling program kind may
// make that call ("Which OptiX calls are supported where?"). Tracing lives in trace.cc.
#include "runtime.h"

#include <pthread.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "batch_block.h"
#include "interrupt.h"
#include "packet_trace.h"
#include "tessera/rt.h"
#include "tessera/scheduler/log.h"
#include "texture_views.h"
#include "thread_state.h"

namespace tessera::worker {
namespace {

thread_local std::unique_ptr<ThreadState> t_owner;  // frees the state when the thread ends

constexpr unsigned kAllKinds = 0x1FFu;  // every ProgramKind

std::string IndexText(const Index3& i) {
  return absl::StrCat("(", i[0], ", ", i[1], ", ", i[2], ")");
}

}  // namespace

// A suspended program needs back only its per-call values (ray, payload, distance, attributes);
// launch index and dim do not change within a launch index, invariants never change, and its
// binding's own values are re-applied from the binding.
void SavePerCall(SuspendedSlots& s) {
  const ModuleState& ms = *s.module;
  const auto& vars = ms.module->variables();
  s.bytes.resize(ms.module->per_call_bytes());
  unsigned char* at = s.bytes.data();
  for (unsigned var : ms.module->per_call()) {
    CopyWords(at, ms.slots[var], vars[var].size);
    at += vars[var].size;
  }
}

void RestoreSaved(const SuspendedSlots& s) {
  ModuleState& ms = *s.module;
  const auto& vars = ms.module->variables();
  const unsigned char* at = s.bytes.data();
  for (unsigned var : ms.module->per_call()) {
    CopyWords(ms.slots[var], at, vars[var].size);
    at += vars[var].size;
  }
  if (ms.loaded != s.loaded && s.loaded != nullptr) Apply(ms, *s.loaded);
}

__thread ThreadState* t_state __attribute__((tls_model("initial-exec"))) = nullptr;
__thread const TesseraBufferView* t_buffer_table __attribute__((tls_model("initial-exec"))) =
    nullptr;

ThreadState& CreateThreadState() {
  t_owner = std::make_unique<ThreadState>();
  t_state = t_owner.get();
  // Nested rtTrace runs on the native stack (TBB workers have 4 MiB, others 8 MiB): programs with
  // large locals reach its end long before 1024 levels, so rtTrace also checks the stack itself
  // (LimitStack).
  pthread_attr_t attr;
  if (pthread_getattr_np(pthread_self(), &attr) == 0) {
    void* base = nullptr;
    size_t size = 0;
    if (pthread_attr_getstack(&attr, &base, &size) == 0 && base != nullptr) {
      constexpr size_t kReserve = 256 * 1024;
      t_state->stack_floor = static_cast<const char*>(base) + std::min(size / 2, kReserve);
      t_state->stack_limit = t_state->stack_floor;
    }
    pthread_attr_destroy(&attr);
  }
  return *t_state;
}

void UsePlan(ThreadState& ts, const LaunchPlan& plan) {
  ts.plan = &plan;
  t_buffer_ids = &plan.bindless.fast;
  t_texture_ids = &plan.textures.fast;
  if (ts.plan_serial == plan.serial) return;
  ts.plan_serial = plan.serial;
  ts.frames.resize(plan.max_depth + 1);
  ts.suspended.resize(plan.max_depth + 2);
  ts.modules.resize(std::max(ts.modules.size(), plan.invariants.size()));
  for (ModuleState& ms : ts.modules) {
    ms.loaded = nullptr;
    ms.suspended = nullptr;
  }
  ts.last_node = nullptr;
  ts.last_node_id = 0;
}

void InitModuleState(ModuleState& ms, const Module* m) {
  ms.module = m;
  ms.slots = m->Slots();
}

void LoadInvariants(const ThreadState& ts, ModuleState& ms, unsigned module_index) {
  const LaunchPlan& plan = *ts.plan;
  for (const auto& c : plan.invariants[module_index].copies) {
    std::memcpy(ms.slots[c.var], c.src, c.size);
  }
  ms.invariants_plan = plan.serial;
  ms.loaded = nullptr;
}

namespace {
constexpr uint32_t kUntouched = 0x7fc0a5a5u;  // a quiet NaN no bounding box program computes
}  // namespace

void CallProgramChecked(ThreadState& ts, const BoundProgram& p, int primitive) {
  for (float& f : ts.scratch_result) std::memcpy(&f, &kUntouched, sizeof(f));
  reinterpret_cast<void (*)(int, float*)>(p.function)(primitive, ts.scratch_result);
  VerifyScratch(ts, p);
}

void VerifyScratch(ThreadState& ts, const BoundProgram& p) {
  for (const float& f : ts.scratch_result) {
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof(bits));
    if (bits != kUntouched) {
      throw FatalError{absl::FailedPreconditionError(absl::StrCat(
          p.name, " is set as a ", KindName(p.kind),
          " program but wrote through a bounding box result pointer: it looks like a bounding box "
          "program (void f(int, float result[6])), which only rtGeometrySetBoundingBoxProgram "
          "takes"))};
    }
  }
  __atomic_store_n(&p.arguments_checked, true, __ATOMIC_RELAXED);
}

void Raise(unsigned code, std::string details) {
  if (TS().plan->ExceptionEnabled(code)) throw ExceptionSignal{code, std::move(details)};
}

void CallNotAllowed(const ThreadState& ts, const char* call) {
  throw FatalError{absl::FailedPreconditionError(absl::StrCat(
      call, " called from ", ts.current ? ts.current->name : "a program", ": not allowed in ",
      std::strchr("aeiou", KindName(ts.kind)[0]) != nullptr ? "an " : "a ", KindName(ts.kind),
      " program (OptiX 3 guide, \"Which OptiX calls are supported where?\")"))};
}

namespace {

void RtThrow(unsigned code) {
  InterruptPoint();
  CheckCall(TS(), kAllKinds & ~Bit(ProgramKind::kException), "rtThrow");
  if (code < RT_EXCEPTION_USER || code > 0xFFFF) {
    throw FatalError{absl::InvalidArgumentError(
        absl::StrFormat("rtThrow(0x%X) from %s: user exception codes run from 0x400 to 0xFFFF",
                        code, TS().current->name))};
  }
  Raise(code, absl::StrFormat("user exception 0x%X", code));
}

unsigned RtExceptionCode() {
  InterruptPoint();
  CheckCall(TS(), Bit(ProgramKind::kException), "rtGetExceptionCode");
  return TS().exception_code;
}

bool PrintActive() {
  const ThreadState& ts = TS();
  if (!ts.plan->print_enabled) return false;
  for (int i = 0; i < 3; ++i) {
    if (ts.plan->print_index[i] >= 0 &&
        static_cast<uint32_t>(ts.plan->print_index[i]) != ts.index[i]) {
      return false;
    }
  }
  return true;
}

// Whether `bytes` of output at the current launch index (print `sequence` there) fall past this
// tile's share of the print buffer, where the host would drop them: then they are counted in the
// tile's record of dropped prints instead of sent.
bool CountIfPastPrintBuffer(ThreadState& ts, uint64_t bytes, uint64_t sequence) {
  v1::PrintRecord* dropped = ts.out_dropped_prints;
  if (dropped == nullptr) {
    if (bytes <= ts.plan->print_buffer_size - ts.out_print_bytes) {
      ts.out_print_bytes += bytes;
      return false;
    }
    dropped = ts.out_dropped_prints = ts.out->add_prints();
    for (uint32_t i : ts.index) dropped->add_launch_index(i);
    dropped->set_sequence(sequence);
  }
  dropped->set_dropped_bytes(dropped->dropped_bytes() + bytes);
  dropped->set_dropped_prints(dropped->dropped_prints() + 1);
  return true;
}

void Emit(const std::string& text) {
  ThreadState& ts = TS();
  if (ts.out == nullptr) {
    // Bounding box programs run while accelerations are built, outside any launch index: their
    // prints have no place in the launch's output. Say so once instead of dropping them silently.
    static std::atomic<bool> said{false};
    if (ts.kind == ProgramKind::kBoundingBox && !said.exchange(true)) {
      log::Warn(log::Component::kWorker,
                "rtPrintf from %s is not printed: bounding box programs run while accelerations "
                "are built, outside any launch index",
                ts.current ? ts.current->name.c_str() : "a bounding box program");
    }
    return;
  }
  // The host keeps a launch's prints in launch-index order while they fit the print buffer.
  // This tile's prints come in that order, so once one does not fit beside the tile's earlier
  // ones, the host would drop it and every later one: they are counted in one record instead of
  // sent (a 100 MB print would not even fit in a message).
  const uint64_t sequence = ts.print_sequence++;
  if (CountIfPastPrintBuffer(ts, text.size(), sequence)) return;
  v1::PrintRecord* r = ts.out->add_prints();
  for (uint32_t i : ts.index) r->add_launch_index(i);
  r->set_sequence(sequence);
  r->set_text(text);
}

int RtPrintActive() {
  InterruptPoint();
  EndCollectingIfAny(TS());  // an effect: the collecting lane traces alone
  return PrintActive() ? 1 : 0;
}
void RtPrint(const char* text) {
  InterruptPoint();
  EndCollectingIfAny(TS());
  if (PrintActive() && text != nullptr) Emit(text);
}

const char* ExceptionName(unsigned code) {
  switch (code) {
    case RT_EXCEPTION_PROGRAM_ID_INVALID:
      return "RT_EXCEPTION_PROGRAM_ID_INVALID";
    case RT_EXCEPTION_TEXTURE_ID_INVALID:
      return "RT_EXCEPTION_TEXTURE_ID_INVALID";
    case RT_EXCEPTION_BUFFER_ID_INVALID:
      return "RT_EXCEPTION_BUFFER_ID_INVALID";
    case RT_EXCEPTION_INDEX_OUT_OF_BOUNDS:
      return "RT_EXCEPTION_INDEX_OUT_OF_BOUNDS";
    case RT_EXCEPTION_STACK_OVERFLOW:
      return "RT_EXCEPTION_STACK_OVERFLOW";
    case RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS:
      return "RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS";
    case RT_EXCEPTION_INVALID_RAY:
      return "RT_EXCEPTION_INVALID_RAY";
    case RT_EXCEPTION_INTERNAL_ERROR:
      return "RT_EXCEPTION_INTERNAL_ERROR";
    default:
      return code >= RT_EXCEPTION_USER ? "RT_EXCEPTION_USER" : "unknown exception";
  }
}

std::string ExceptionText() {
  const ThreadState& ts = TS();
  return absl::StrFormat("Caught %s (0x%X) at launch index %s: %s\n",
                         ExceptionName(ts.exception_code), ts.exception_code, IndexText(ts.index),
                         ts.exception_details);
}

void RtPrintExceptionDetails() {
  InterruptPoint();
  CheckCall(TS(), Bit(ProgramKind::kException), "rtPrintExceptionDetails");
  if (PrintActive()) Emit(ExceptionText());
}

// The running program's transform between object and world space; null where there is none
// (the two spaces are one).
const Mat* CurrentTransform(bool to_world) {
  ThreadState& ts = TS();
  if (ts.depth == 0 || ts.kind == ProgramKind::kMiss) return nullptr;
  const Frame& f = ts.top();
  // An intersection program run after traversal (kDeferred: native triangles) sees the
  // transforms above its hit, kept with the hit, as it would have during traversal.
  const bool hit_space =
      ts.kind == ProgramKind::kClosestHit ||
      (ts.kind == ProgramKind::kIntersection && ts.is.mode == IntersectMode::kDeferred);
  const Xform& x = hit_space                            ? f.hit.xform
                   : ts.kind == ProgramKind::kAttribute ? ts.attribute_hit->xform
                                                        : f.xform;
  if (!x.active) return nullptr;
  return to_world ? &x.to_world : &x.to_object;
}

void RtTransform(unsigned kind, unsigned what, const float* in, float* out) {
  InterruptPoint();
  CheckCall(TS(),
            Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss) |
                Bit(ProgramKind::kIntersection) | Bit(ProgramKind::kBoundingBox) |
                Bit(ProgramKind::kVisit) | Bit(ProgramKind::kAttribute),
            "rtTransform*");
  bool to_world = kind == RT_OBJECT_TO_WORLD;
  if (!to_world && kind != RT_WORLD_TO_OBJECT) {
    throw FatalError{absl::InvalidArgumentError(
        absl::StrCat("rtTransform* with unknown transform kind ", kind))};
  }
  float v[3] = {in[0], in[1], in[2]};
  // Normals go through the inverse transpose of the matrix that moves points.
  const bool normal = what == TESSERA_TRANSFORM_NORMAL;
  const Mat* transform = CurrentTransform(normal ? !to_world : to_world);
  if (transform == nullptr) {
    // No transform above the geometry: object space is world space, and the value is returned as
    // it is (a multiplication by the identity would turn -0 into +0 and an infinity into NaN).
    std::memcpy(out, v, sizeof(v));
    return;
  }
  if (normal) {
    const Mat& inv = *transform;
    for (int i = 0; i < 3; ++i) out[i] = inv[i] * v[0] + inv[4 + i] * v[1] + inv[8 + i] * v[2];
    return;
  }
  const Mat& m = *transform;
  float w = what == TESSERA_TRANSFORM_POINT ? 1.f : 0.f;
  float r[4];
  for (int i = 0; i < 4; ++i)
    r[i] = m[i * 4] * v[0] + m[i * 4 + 1] * v[1] + m[i * 4 + 2] * v[2] + m[i * 4 + 3] * w;
  float d = (what == TESSERA_TRANSFORM_POINT && r[3] != 0.f) ? r[3] : 1.f;
  for (int i = 0; i < 3; ++i) out[i] = r[i] / d;
}

void RtGetTransform(unsigned kind, float* m) {
  InterruptPoint();
  CheckCall(TS(),
            Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss) |
                Bit(ProgramKind::kIntersection) | Bit(ProgramKind::kBoundingBox) |
                Bit(ProgramKind::kVisit) | Bit(ProgramKind::kAttribute),
            "rtGetTransform");
  const Mat* src = CurrentTransform(kind == RT_OBJECT_TO_WORLD);
  std::memcpy(m, src != nullptr ? src->data() : kIdentity.data(), sizeof(float) * 16);
}

void* RtBufferIndexError(unsigned slot, unsigned long long x, unsigned long long y,
                         unsigned long long z) {
  InterruptPoint();
  ThreadState& ts = TS();
  EndCollectingIfAny(ts);  // an effect: the collecting lane traces alone
  const Module* m = ts.current->module;
  const TesseraBufferView& v = ts.current->table[slot];
  std::string name = slot < m->buffers().size() ? m->buffers()[slot].name : "?";
  Raise(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS,
        absl::StrCat("buffer '", name, "' index (", x, ", ", y, ", ", z, ") outside size (",
                     v.size[0], ", ", v.size[1], ", ", v.size[2], ") in ", ts.current->name));
  // Disabled: reads see zeros and writes land in scratch memory.
  ts.scratch.assign(std::max<size_t>(v.element_size, 64), 0);
  return ts.scratch.data();
}

TesseraRuntime MakeRuntime() {
  TesseraRuntime r = {
      TESSERA_MODULE_ABI_VERSION,
      &RtTrace,
      &RtPotentialIntersection,
      &RtReportIntersection,
      &RtIgnoreIntersection,
      &RtTerminateRay,
      &RtThrow,
      &RtExceptionCode,
      &RtPrintExceptionDetails,
      &RtPrintActive,
      &RtPrint,
      &RtTransform,
      &RtGetTransform,
      &RtBufferIndexError,
      &RtIntersectChild,
      0,
      &RtGetPrimitiveIndex,
      &RtTriangleHit,
      &RtTriangleBarycentrics,
      &RtCallableEnter,
      &RtCallableLeave,
      &RtTextureById,
      &RtBufferById,
      &RtBufferIdIndexError,
      &RtCallableIdEnter,
      0,  // buffer_id_table_offset, below
      &RtTraceWithFlags,
      0,  // texture_table_offset, below
      0,  // texture_id_table_offset, below
      &RtSpawnPoint,
  };
  // Static TLS (initial-exec) sits at the same offset from the thread pointer on every thread.
  r.buffer_table_offset = reinterpret_cast<const char*>(&t_buffer_table) -
                          static_cast<const char*>(__builtin_thread_pointer());
  r.buffer_id_table_offset = reinterpret_cast<const char*>(&t_buffer_ids) -
                             static_cast<const char*>(__builtin_thread_pointer());
  r.texture_table_offset = reinterpret_cast<const char*>(&t_texture_table) -
                           static_cast<const char*>(__builtin_thread_pointer());
  r.texture_id_table_offset = reinterpret_cast<const char*>(&t_texture_ids) -
                              static_cast<const char*>(__builtin_thread_pointer());
  return r;
}

}  // namespace

const TesseraRuntime* EngineRuntime() {
  static const TesseraRuntime runtime = MakeRuntime();
  return &runtime;
}

namespace {

// Forgets the nested calls a launch index left behind when an exception unwound them.
void ResetNesting(ThreadState& ts) {
  ts.depth = 0;
  ts.visits.clear();
  ts.calls.clear();
  for (ModuleState& ms : ts.modules) ms.suspended = nullptr;
}

// Forgets what a launch index left behind when it was jumped out of (InterruptibleTile): nested
// calls, and the any-hit program it may have been in, whose state lived in the frames skipped.
void ForgetInterruptedIndex(ThreadState& ts) {
  ResetNesting(ts);
  ts.packet.collecting = nullptr;
  ts.packet.replay = nullptr;
  ts.pending = nullptr;
  ts.ah_end = nullptr;
  ts.ah_calls = 0;
}

// The report of the exception at the current launch index (ts.exception_code and _details),
// which reached no exception program, for the host: printed there among the prints when printing
// shows this launch index, else counted on stderr naming the launch's first. What the host would
// not use (past the print buffer; all but a tile's first of those printing does not show) is
// only counted, so a launch that throws at every index costs no memory per index.
void Report(ThreadState& ts) {
  const bool shown = PrintActive();
  std::string text = ExceptionText();
  // Printed after the launch index's prints (the host gives it the last sequence number).
  const bool send =
      shown ? !CountIfPastPrintBuffer(ts, text.size(), std::numeric_limits<uint64_t>::max())
            : !ts.out_unshown_report_sent;
  if (send) {
    if (!shown) ts.out_unshown_report_sent = true;
    v1::ExceptionReport* r = ts.out->add_exceptions();
    for (uint32_t i : ts.index) r->add_launch_index(i);
    r->set_code(ts.exception_code);
    r->set_details(std::move(text));
    return;
  }
  v1::ExceptionReport*& not_sent = ts.out_reports_not_sent;
  if (not_sent == nullptr) not_sent = ts.out->add_exceptions();
  not_sent->set_not_sent(not_sent->not_sent() + 1);
  if (!shown) not_sent->set_not_sent_unshown(not_sent->not_sent_unshown() + 1);
}

// An exception raised at the current launch index: the entry's exception program runs, or the
// report goes to the host.
__attribute__((noinline)) void HandleException(ThreadState& ts, const LaunchPlan& plan,
                                               unsigned entry, ExceptionSignal& e) {
  ResetNesting(ts);
  ts.exception_code = e.code;
  ts.exception_details = std::move(e.details);
  const BoundProgram* ex = entry < plan.exception.size() ? plan.exception[entry] : nullptr;
  if (ex != nullptr) {
    try {
      Enter(ts, *ex);
      CallProgram(ts, *ex);
    } catch (ExceptionSignal& inner) {
      // An exception inside the exception program ends this launch index; it reaches the host as
      // a report (printed in order, or counted on stderr) instead of vanishing.
      ResetNesting(ts);
      ts.exception_code = inner.code;
      // ex->name says "exception program 'f' in m.so"; details of a failed call name it already.
      ts.exception_details = absl::StrContains(inner.details, ex->name)
                                 ? std::move(inner.details)
                                 : absl::StrCat(inner.details, " (raised in ", ex->name, ")");
      Report(ts);
    }
  } else {
    Report(ts);
  }
}

// Runs the ray generation program at ts.index on a thread set up for the launch (RunTile).
inline void RunIndex(ThreadState& ts, const LaunchPlan& plan, unsigned entry,
                     const BoundProgram& rg) {
  ++ts.index_serial;
  ts.print_sequence = 0;
  if (__builtin_expect(ts.depth != 0, 0)) ResetNesting(ts);  // the last index failed mid-trace
  if (__builtin_expect(static_cast<bool>(ts.pending), 0)) ts.pending = nullptr;
  try {
    Enter(ts, rg);
    CallProgram(ts, rg);
  } catch (ExceptionSignal& e) {
    HandleException(ts, plan, entry, e);
  }
}

}  // namespace

namespace {

// The launch indices of a tile, each until it returns; false when a cancel or a failure elsewhere
// ended the launch first. Out of RunTile, whose sigsetjmp would keep this loop's values out of
// registers.
__attribute__((noinline)) bool RunIndices(ThreadState& ts, const LaunchPlan& plan, unsigned entry,
                                          const BoundProgram& rg, const Index3& origin,
                                          const Index3& size, const Index3& dims,
                                          const std::atomic<bool>& cancel,
                                          const std::atomic<bool>& stop) {
  const Index3 end{std::min(origin[0] + size[0], dims[0]), std::min(origin[1] + size[1], dims[1]),
                   std::min(origin[2] + size[2], dims[2])};
  for (uint32_t z = origin[2]; z < end[2]; ++z) {
    for (uint32_t y = origin[1]; y < end[1]; ++y) {
      for (uint32_t x = origin[0]; x < end[0]; ++x) {
        // Checked per launch index so a cancel stops even long-running programs promptly.
        if (cancel.load(std::memory_order_relaxed) || stop.load(std::memory_order_relaxed)) {
          return false;
        }
        StoreIndex(ts.index, x, y, z);
        RunIndex(ts, plan, entry, rg);
      }
    }
  }
  return true;
}

// The launch indices of a tile in blocks of the launch grid (batch_block.h): each block's first
// rays are kept and traced as packets, then its indices run, row by row (packet_trace.h).
__attribute__((noinline)) bool RunBlocks(ThreadState& ts, const LaunchPlan& plan, unsigned entry,
                                         const BoundProgram& rg, const Index3& origin,
                                         const Index3& size, const Index3& dims,
                                         const std::atomic<bool>& cancel,
                                         const std::atomic<bool>& stop) {
  std::array<PacketLane, 16> lanes;
  return ForEachBlock(origin, size, dims, cancel, stop, [&](const Index3& from, const Index3& to) {
    int n = 0;
    for (uint32_t y = from[1]; y < to[1]; ++y) {
      for (uint32_t x = from[0]; x < to[0]; ++x) {
        StoreIndex(ts.index, x, y, from[2]);
        CollectLane(ts, rg, lanes[n++]);
      }
    }
    TracePackets(lanes.data(), n);
    n = 0;
    for (uint32_t y = from[1]; y < to[1]; ++y) {
      for (uint32_t x = from[0]; x < to[0]; ++x) {
        StoreIndex(ts.index, x, y, from[2]);
        const PacketLane& lane = lanes[n++];
        ts.packet.replay = lane.scene != nullptr ? &lane : nullptr;
        RunIndex(ts, plan, entry, rg);
        ts.packet.replay = nullptr;
      }
    }
  });
}

}  // namespace

bool RunTile(const LaunchPlan& plan, unsigned entry, const Index3& origin, const Index3& size,
             const Index3& dims, const std::atomic<bool>& cancel, const std::atomic<bool>& stop,
             v1::TileResult& out, bool batched) {
  const BoundProgram* rg =
      entry < plan.ray_generation.size() ? plan.ray_generation[entry] : nullptr;
  if (rg == nullptr) {
    throw FatalError{absl::FailedPreconditionError(
        absl::StrCat("entry point ", entry, " has no ray generation program"))};
  }
  ThreadState& ts = TS();
  UsePlan(ts, plan);
  LimitStack(ts, __builtin_frame_address(0));
  ts.dims = dims;
  ts.out = &out;
  ts.traces = 0;
  ts.packet_answers = 0;
  ts.out_print_bytes = 0;
  ts.out_dropped_prints = nullptr;
  ts.out_unshown_report_sent = false;
  ts.out_reports_not_sent = nullptr;
  struct ClearOut {  // prints after the tile (say from a bounds program) have nowhere to go
    ThreadState& ts;
    ~ClearOut() {
      ts.out->set_traces(ts.out->traces() + ts.traces);
      ts.out->set_packet_answers(ts.out->packet_answers() + ts.packet_answers);
      // No program runs any more: a crash in the engine or Embree, or the worker's own exit, must
      // not be reported as the tile's last program's (crash_report.cc reads `current`).
      ts.current = nullptr;
      ts.out = nullptr;
      ts.out_dropped_prints = nullptr;
      ts.out_reports_not_sent = nullptr;
      // A tile that failed may have left a lane collecting or a packet's hit unused.
      ts.packet.collecting = nullptr;
      ts.packet.replay = nullptr;
    }
  } clear_out{ts};
  // A program that never returns is jumped out of when the launch ends (interrupt.h); the index
  // it left half done is forgotten as an exception's would be, and the tile is abandoned.
  InterruptibleTile interruptible(cancel, stop);
  sigjmp_buf interrupted;
  if (sigsetjmp(interrupted, 0) != 0) {
    interruptible.Jumped();
    ForgetInterruptedIndex(ts);
    return false;
  }
  interruptible.Arm(&interrupted);
  if (batched) return RunBlocks(ts, plan, entry, *rg, origin, size, dims, cancel, stop);
  return RunIndices(ts, plan, entry, *rg, origin, size, dims, cancel, stop);
}

void RunBoundsProgram(const LaunchPlan& plan, const BoundProgram& program, unsigned primitive,
                      float result[6]) {
  ThreadState& ts = TS();
  UsePlan(ts, plan);
  LimitStack(ts, __builtin_frame_address(0));
  ts.out = nullptr;
  ts.depth = 0;
  struct Left {  // as at a tile's end: no program runs once this one returned (or threw)
    ThreadState& ts;
    ~Left() { ts.current = nullptr; }
  } left{ts};
  try {
    Enter(ts, program);
    reinterpret_cast<void (*)(int, float*)>(program.function)(static_cast<int>(primitive), result);
  } catch (ExceptionSignal& e) {
    throw FatalError{absl::FailedPreconditionError(absl::StrCat(
        program.name, " raised an exception for primitive ", primitive, ": ", e.details))};
  }
}

}  // namespace tessera::worker
