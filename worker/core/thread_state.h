// Per-thread execution state of the engine and the helpers that move values in and out of a
// program module's slots. Internal to worker/core (runtime.cc, trace.cc).
#ifndef TESSERA_WORKER_CORE_THREAD_STATE_H_
#define TESSERA_WORKER_CORE_THREAD_STATE_H_

#include <algorithm>
#include <array>
#include <csetjmp>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "absl/status/status.h"
#include "plan.h"
#include "runtime.h"
#include "tessera/worker/crash_report.h"
#include "watertight.h"

namespace tessera::worker {

// optix::Ray's layout (internal/optix_datatypes.h).
struct RayData {
  float origin[3];
  float direction[3];
  unsigned ray_type;
  float tmin;
  float tmax;
};
static_assert(sizeof(RayData) == 36, "optix::Ray layout");

struct Hit {
  float t = 0;
  const InstancePlan* instance = nullptr;
  unsigned material = 0;
  unsigned primitive = 0;
  bool deferred = false;   // native triangle: attributes come from the intersection program later
  bool back_face = false;  // triangles: hit from the side their winding makes the back
  float barycentrics[2] = {0, 0};  // triangles: weights of the second and third vertex
  // Triangles (native or built-in): where their vertices are; null for intersection programs.
  const GeometryInfo* geometry = nullptr;
  RayData object_ray{};
  Xform xform;
  alignas(16) unsigned char attributes[AttributeLayout::kMaxBytes];
};

struct Frame {
  RayData ray{};  // world space
  void* payload = nullptr;
  size_t payload_size = 0;
  Hit hit;
  bool terminated = false;
  unsigned flags = 0;  // the RTrayflags the trace honours (RtTraceWithFlags)
  float time = 0.f;    // rtCurrentTime of the programs the ray runs
  Xform xform;         // the traversal's current transform
  // The payload before a program with several payload variables ran (ChoosePayload).
  std::vector<unsigned char> payload_before;
};

// What IntersectScene passes Embree as the intersect context, which Embree hands to every
// callback of the traversal (instanced scenes' included) as args->context.
struct TraceContext {
  RTCIntersectContext embree;  // first: callbacks cast args->context back
  const SceneEntry* scene = nullptr;
  // AnyHitBit of the traced ray: a filter callback on a geometry without an any-hit program for
  // this ray type returns at once.
  uint64_t any_hit_bit = 0;
  // Scenes with instances (flattened Groups): the instance whose composed transform the frame's
  // xform holds (RTC_INVALID_GEOMETRY_ID: *base, the transform above the scene), and that
  // transform, kept aside while an instance's is in the frame.
  unsigned current = RTC_INVALID_GEOMETRY_ID;
  const Xform* base = nullptr;
};
inline TraceContext& ContextOf(RTCIntersectContext* c) {
  return *reinterpret_cast<TraceContext*>(c);
}

// The any_hit_types bit of ray type `type`; none when the ray disables any-hit programs.
inline uint64_t AnyHitBit(unsigned type, bool disabled) {
  return disabled ? 0 : uint64_t{1} << std::min(type, 63u);
}

enum class IntersectMode { kSearch, kFiltered, kDeferred };

struct IntersectState {
  const InstancePlan* instance = nullptr;
  unsigned primitive = 0;
  RayData ray{};
  IntersectMode mode = IntersectMode::kSearch;
  float forced_t = 0;
  float candidate_t = 0;
  bool candidate_ok = false;
  bool committed = false;
  // Embree's hit (kDeferred, kFiltered): whether the program reported it, and how far from
  // Embree's t the kept report's own t was.
  bool reported = false;
  float reported_error = 0, candidate_error = 0;
  // kFiltered: the native triangle Embree found, and where.
  const GeometryInfo* geometry = nullptr;
  float barycentrics[2] = {0, 0};
};

// A selector whose visit program runs (rtIntersectChild traverses one of its children).
struct VisitState {
  uint64_t id = 0;
  const NodeInfo* node = nullptr;
  RayData ray{};  // in the selector's space
};

struct ExceptionSignal {
  unsigned code;
  std::string details;
};

struct ModuleState;

// The slots of a module whose program is suspended (it called rtTrace, or its intersection
// program is waiting for an any-hit program). They are saved only when another program of the
// same module is about to overwrite them, and restored when the suspended program resumes.
struct SuspendedSlots {
  ModuleState* module = nullptr;
  SuspendedSlots* outer = nullptr;  // the next suspended state of the same module
  bool saved = false;
  // Whether the suspended program can read per-call values: ray generation and exception
  // programs cannot (Table 4), so nothing but their binding needs restoring.
  bool reads_per_call = true;
  const BoundProgram* loaded = nullptr;
  std::vector<unsigned char> bytes;
};

// One module as seen by one thread.
struct ModuleState {
  const Module* module = nullptr;
  void* const* slots = nullptr;
  const BoundProgram* loaded = nullptr;  // whose copies the slots hold
  uint64_t invariants_plan = 0;          // serial of the plan whose invariants are loaded
  uint64_t index_written = 0;            // launch-index serial whose index/dim the slots hold
  SuspendedSlots* suspended = nullptr;   // innermost suspended state not yet restored
};

// A launch index of a batched block (packet_trace.h): its ray generation program's first ray,
// kept while that program ran only up to its rtTrace, and what Embree's packet found for it.
struct PacketLane {
  const SceneEntry* scene = nullptr;  // null: no ray kept; the index traces alone
  RayData ray;
  RTCRayHit hit;
};

struct PacketState {
  // Set while the ray generation program runs up to its first rtTrace for this lane, where
  // CollectTrace keeps the ray and jumps back to `jump` (__builtin_setjmp's buffer).
  PacketLane* collecting = nullptr;
  void* jump[5] = {};
  // The lane whose first rtTrace takes its packet's hit instead of tracing.
  const PacketLane* replay = nullptr;
  // The ray generation program's views with those of buffers it may write carrying
  // TESSERA_COLLECTING_EPOCH: an access while collecting ends the collection. Made once per
  // program and plan.
  const BoundProgram* table_program = nullptr;
  uint64_t table_plan = 0;
  std::vector<TesseraBufferView> table;
};

struct ThreadState {
  // A thread that runs programs gets an alternate signal stack: a program that overflows the
  // thread's stack still leaves its crash report (crash_report.h). A member rather than a
  // constructor of ThreadState: one without a user-provided constructor is zeroed by
  // value-initialization (make_unique), members without initializers included.
  struct AltSignalStackOfThread {
    AltSignalStackOfThread() { EnsureAltSignalStack(); }
  } alt_signal_stack;
  // Defined below t_state.
  ~ThreadState();

  const LaunchPlan* plan = nullptr;
  uint64_t plan_serial = 0;
  // The watertight test's ray, prepared once for every triangle it meets (IntersectWatertight):
  // `watertight_key` is the origin and direction it was prepared for.
  WatertightRay watertight_ray;
  float watertight_key[6];
  // Set while a ray is traced again with every native triangle candidate put to its intersection
  // program (TraverseVerified, trace.cc).
  bool verify_triangles = false;
  Index3 index{}, dims{};
  uint64_t index_serial = 0;  // bumps with every launch index this thread runs
  // The current tile's rtTrace calls and first rays a packet answered (TileResult.traces,
  // packet_answers): what the host chooses batching from (api/src/auto_batching.h).
  uint64_t traces = 0;
  uint64_t packet_answers = 0;
  std::vector<Frame> frames;  // frames[0 .. depth) are live; sized once per plan
  size_t depth = 0;
  std::vector<SuspendedSlots> suspended;  // one per depth, reused
  std::vector<ModuleState> modules;       // by module index
  ProgramKind kind = ProgramKind::kRayGeneration;
  const BoundProgram* current = nullptr;
  ModuleState* current_module = nullptr;
  IntersectState is;
  // Selectors being visited, innermost last, and a suspended state per level for their visit
  // programs while a child is traversed (a deque: linked states keep their addresses).
  std::vector<VisitState> visits;
  std::deque<SuspendedSlots> visit_suspended;
  // Callable program calls under way, innermost last, and a suspended state per level for
  // callers in another module than their callee's (callable.cc); calls an any-hit program made
  // begin at `ah_calls` (RunAnyHit).
  std::vector<TesseraCallFrame*> calls;
  std::deque<SuspendedSlots> call_suspended;
  size_t ah_calls = 0;
  Hit candidate;
  // The hit an attribute program computes the attributes of (ts.candidate or a frame's hit).
  Hit* attribute_hit = nullptr;
  // The ray of the running any-hit or attribute program, in its object space (callable.cc).
  const RayData* object_ray = nullptr;
  bool ah_ignore = false, ah_terminate = false;
  // Where rtIgnoreIntersection and rtTerminateRay end the running any-hit program (RunAnyHit).
  std::jmp_buf* ah_end = nullptr;
  unsigned exception_code = 0;
  std::string exception_details;
  std::exception_ptr pending;
  v1::TileResult* out = nullptr;
  uint64_t print_sequence = 0;
  // Text bytes printed into `out` by this RunTile, and the record that counts its prints past the
  // print buffer (the host could keep none of them).
  uint64_t out_print_bytes = 0;
  v1::PrintRecord* out_dropped_prints = nullptr;
  // Exception reports of this RunTile: whether the first that printing does not show was sent,
  // and the record that counts those not sent.
  bool out_unshown_report_sent = false;
  v1::ExceptionReport* out_reports_not_sent = nullptr;
  std::vector<unsigned char> scratch;
  // A traced payload kept across restoring its caller's values (RtTrace).
  std::vector<unsigned char> resume_payload;
  uint64_t last_node_id = 0;
  const NodeInfo* last_node = nullptr;
  PacketState packet;  // batched launches (packet_trace.h)
  // tesseraSpawnPoint's last hit on an untransformed triangle and what it prepared of it
  // (RtSpawnPoint): a path tracer's closest-hit program spawns two or three rays from one hit.
  // Keyed by the launch index too, so a hit of another launch, whose vertices may have changed,
  // never matches.
  struct SpawnCache {
    uint64_t index_serial = 0;
    const GeometryInfo* geometry = nullptr;
    unsigned primitive = 0;
    uint32_t barycentric_bits[2] = {0, 0};
    SpawnBase base;
  } spawn_cache;
  // Where a program's `result` argument points when its kind passes none (CallProgram).
  float scratch_result[6] = {};
  // rtTrace and callable program calls raise RT_EXCEPTION_STACK_OVERFLOW below this address:
  // kNativeStackBudget below where the running tile (or bounding box program) began, so the same
  // on every thread, or `stack_floor` if that is higher (LimitStack).
  const char* stack_limit = nullptr;
  // The thread's native stack minus a reserve for one more level of engine, Embree and program
  // frames (CreateThreadState).
  const char* stack_floor = nullptr;

  Frame& top() { return frames[depth - 1]; }
};

// The calling thread's state: a plain pointer in initial-exec TLS, so an access is one load.
// __thread, not thread_local: a thread_local declared extern gets a call to its (possible)
// dynamic initializer before every access.
extern __thread ThreadState* t_state __attribute__((tls_model("initial-exec")));
ThreadState& CreateThreadState();

// Keeps `program` (the calling thread's last) for the report of a program that calls exit(),
// which runs after exit() destroyed the thread's thread_local objects (crash_report.cc).
void KeepProgramForExitReport(const BoundProgram* program);

// exit() destroys the calling thread's thread_local objects, this state's owner among them,
// before its atexit handlers: the exit report must not read the state afterwards. So t_state
// forgets it (a crash report would read freed memory too), and the running program goes where
// that report finds it. Only the pointer is copied: at a thread's normal end `current` may name a
// program whose plan is gone.
inline ThreadState::~ThreadState() {
  if (t_state == this) t_state = nullptr;
  KeepProgramForExitReport(current);
}

// The running program's buffer views, which modules read at a fixed offset from the thread
// pointer (TesseraRuntime::buffer_table_offset): set whenever control passes to a program.
extern __thread const TesseraBufferView* t_buffer_table __attribute__((tls_model("initial-exec")));

// Makes `p` (of module state `ms`) the running program again after a nested program returned.
inline void ReturnTo(ThreadState& ts, const BoundProgram& p, ModuleState& ms) {
  ts.kind = p.kind;
  ts.current = &p;
  ts.current_module = &ms;
  t_buffer_table = p.table.data();
  t_texture_table = p.textures.data();
}
// The native stack a launch index may use for nested calls. Measured from where its tile began,
// not from the thread's end, so that where deep recursion runs out does not depend on the thread,
// device or process that ran the tile (TBB's threads have 4 MiB of stack, others 8 MiB). It
// leaves TBB's threads more than the reserve of CreateThreadState.
inline constexpr size_t kNativeStackBudget = 3 * 1024 * 1024 + 256 * 1024;
inline void LimitStack(ThreadState& ts, const void* start) {
  const auto here = reinterpret_cast<uintptr_t>(start);
  const uintptr_t limit = here > kNativeStackBudget ? here - kNativeStackBudget : 0;
  ts.stack_limit = std::max(ts.stack_floor, reinterpret_cast<const char*>(limit));
}

// The hit the running program sees: its own closest hit, the any-hit candidate, or the hit an
// attribute program computes attributes for; null for other kinds.
inline Hit* HitOf(ThreadState& ts) {
  switch (ts.kind) {
    case ProgramKind::kClosestHit:
      return &ts.top().hit;
    case ProgramKind::kAnyHit:
      return &ts.candidate;
    case ProgramKind::kAttribute:
      return ts.attribute_hit;
    default:
      return nullptr;
  }
}

inline ThreadState& TS() {
  if (__builtin_expect(t_state == nullptr, 0)) return CreateThreadState();
  return *t_state;
}

// Binds the calling thread to `plan`.
void UsePlan(ThreadState& ts, const LaunchPlan& plan);

// Cold paths of Enter (runtime.cc).
void InitModuleState(ModuleState& ms, const Module* m);
void SavePerCall(SuspendedSlots& s);

// Saves what a suspended program of `ms` needs back before another program of the module runs:
// its binding, and its per-call values if it can read any (runtime.cc).
inline void SaveSlots(SuspendedSlots& s, const ModuleState& ms) {
  s.loaded = ms.loaded;
  s.saved = true;
  if (s.reads_per_call) SavePerCall(s);
}
void LoadInvariants(const ThreadState& ts, ModuleState& ms, unsigned module_index);

// memcpy for the small, mostly fixed sizes of slot values, without a library call.
inline void CopyBytes(void* dst, const void* src, size_t n) {
  switch (n) {
    case 4:
      std::memcpy(dst, src, 4);
      return;
    case 8:
      std::memcpy(dst, src, 8);
      return;
    case 12:
      std::memcpy(dst, src, 12);
      return;
    case 16:
      std::memcpy(dst, src, 16);
      return;
    case 36:
      std::memcpy(dst, src, 36);
      return;
    default:
      std::memcpy(dst, src, n);
  }
}

// memset(dst, 0, n) for the small sizes of attributes, without a library call.
inline void ZeroBytes(void* dst, size_t n) {
  static constexpr unsigned char kZeros[16] = {};
  if (n <= sizeof(kZeros)) {
    CopyBytes(dst, kZeros, n);
  } else {
    std::memset(dst, 0, n);
  }
}

// Copies n bytes 4 at a time, for values a program (or the engine) has just written field by
// field: a wider load that spans two narrower stores still in the store buffer cannot take their
// data (store-to-load forwarding) and waits about a dozen cycles for them to reach the cache.
// Values of OptiX types are made of 4-byte fields; other sizes, and large ones, take CopyBytes.
// The empty asm keeps the compiler from merging the words back into vector moves.
inline void CopyWords(void* dst, const void* src, size_t n) {
  if (__builtin_expect(n % 4 != 0 || n > 128, 0)) {
    CopyBytes(dst, src, n);
    return;
  }
  auto* d = static_cast<unsigned char*>(dst);
  const auto* s = static_cast<const unsigned char*>(src);
  const auto word = [&](size_t i) {
    uint32_t w;
    std::memcpy(&w, s + i, 4);
    asm("" : "+r"(w));
    std::memcpy(d + i, &w, 4);
  };
  if (__builtin_constant_p(n)) {  // a ray: nine stores, not a loop the asm keeps GCC from unrolling
#pragma GCC unroll 32
    for (size_t i = 0; i < n; i += 4) word(i);
    return;
  }
  // Launch indices, attributes and small payloads: straight-line copies, no loop to set up.
  switch (n) {
    case 16:
      word(12);
      [[fallthrough]];
    case 12:
      word(8);
      [[fallthrough]];
    case 8:
      word(4);
      [[fallthrough]];
    case 4:
      word(0);
      [[fallthrough]];
    case 0:
      return;
    default:
      for (size_t i = 0; i < n; i += 4) word(i);
  }
}

// One 4-byte value read on its own (see CopyWords).
template <typename T>
inline T Word(const T& v) {
  static_assert(sizeof(T) == 4);
  T w = v;
#if defined(__x86_64__) || defined(__i386__)
  if constexpr (std::is_floating_point_v<T>) {
    asm("" : "+x"(w));  // stays in a vector register
  } else {
    asm("" : "+r"(w));
  }
#else
  asm("" : "+r"(w));
#endif
  return w;
}

// Stores four words as one 16-byte vector: a program's (or Embree's) wider loads of them then
// take the store's data, as they could not from four narrower stores.
using Vec4f = float __attribute__((vector_size(16)));
inline void StoreVec4(void* dst, float a, float b, float c, float d) {
  const Vec4f v = {a, b, c, d};
  std::memcpy(dst, &v, sizeof(v));
}

// Stores `ray`, which was just stored word by word, as the two vectors and a word that a block
// copy of it loads (a 16-byte load takes the data of one 16-byte store still in flight, not of four
// 4-byte ones): read word by word, stored in blocks.
inline void StoreRayBlocks(void* dst, const RayData& ray) {
  auto* d = static_cast<unsigned char*>(dst);
  float type;
  std::memcpy(&type, &ray.ray_type, sizeof(type));
  StoreVec4(d, Word(ray.origin[0]), Word(ray.origin[1]), Word(ray.origin[2]),
            Word(ray.direction[0]));
  StoreVec4(d + 16, Word(ray.direction[1]), Word(ray.direction[2]), Word(type), Word(ray.tmin));
  const float tmax = Word(ray.tmax);
  std::memcpy(d + 32, &tmax, sizeof(tmax));
}

// The ray of a program's rtCurrentRay slot: read word by word (it was stored that way) and
// stored as two vectors and a word.
// kSettled: the ray was stored long before (a frame's ray, stored before its traversal), so one
// block copy reads it without waiting on stores in flight.
template <bool kSettled = false>
inline void WriteRaySlots(const ModuleState& ms, const std::vector<BoundProgram::SlotRef>& refs,
                          const RayData& ray) {
  for (const BoundProgram::SlotRef& r : refs) {
    if (r.size != sizeof(RayData)) {
      CopyWords(ms.slots[r.var], &ray, r.size);
      continue;
    }
    if constexpr (kSettled) {
      std::memcpy(ms.slots[r.var], &ray, sizeof(RayData));
      continue;
    }
    StoreRayBlocks(ms.slots[r.var], ray);
  }
}

// Payloads: CopyWords also spares payloads of other sizes than CopyBytes's a library call.
inline void WriteSlots(const ModuleState& ms, const std::vector<BoundProgram::SlotRef>& refs,
                       const void* src, size_t size) {
  for (const BoundProgram::SlotRef& r : refs) {
    CopyWords(ms.slots[r.var], src, std::min<size_t>(size, r.size));
  }
}

// The same for values of a fixed size N (ray, distance, launch index), whose SlotRefs hold the
// bytes to copy: a constant-size copy when the declaration takes all N.
template <size_t N>
inline void WriteSlots(const ModuleState& ms, const std::vector<BoundProgram::SlotRef>& refs,
                       const void* src) {
  for (const BoundProgram::SlotRef& r : refs) {
    if (r.size == N) {
      std::memcpy(ms.slots[r.var], src, N);
    } else {
      CopyBytes(ms.slots[r.var], src, r.size);
    }
  }
}

inline ModuleState& StateOf(ThreadState& ts, const BoundProgram& p) {
  ModuleState& ms = ts.modules[p.module_index];
  if (__builtin_expect(ms.module == nullptr, 0)) InitModuleState(ms, p.module);
  return ms;
}

// Loads `p`'s own values into its module's slots (beyond the module's invariants).
inline void Apply(ModuleState& ms, const BoundProgram& p) {
  for (const BoundProgram::Copy& c : p.copies) CopyBytes(ms.slots[c.var], c.src, c.size);
  ms.loaded = &p;
}

// rtCurrentTime of `p`: the time of the ray being traced; a launch's own programs see 0.
inline void WriteTime(const ThreadState& ts, const ModuleState& ms, const BoundProgram& p) {
  static constexpr float kLaunchTime[4] = {};  // as wide as any slot CopySize allows
  const float* time = ts.depth > 0 ? &ts.frames[ts.depth - 1].time : kLaunchTime;
  WriteSlots<sizeof(float)>(ms, p.time, time);
}

// Sets a launch index as Enter copies it into programs' variables: x and y in one 8-byte store
// and z in a 4-byte one, so that each of the copy's loads (8 and 4 bytes, or fewer) takes its data
// from one store still in flight; three 4-byte stores would make the 8-byte load wait for them.
inline void StoreIndex(Index3& index, uint32_t x, uint32_t y, uint32_t z) {
  static_assert(sizeof(Index3) == 12 && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__);
  const uint64_t xy = uint64_t{x} | uint64_t{y} << 32;  // x at the lower address
  std::memcpy(index.data(), &xy, sizeof(xy));
  index[2] = z;
}

// Makes `p` the running program: saves a suspended caller's slots if `p` would overwrite them,
// loads `p`'s bindings and the launch index/dim semantics. Inline: it runs for every program.
__attribute__((always_inline)) inline void Enter(ThreadState& ts, const BoundProgram& p) {
  ModuleState& ms = StateOf(ts, p);
  if (ms.suspended != nullptr && !ms.suspended->saved) SaveSlots(*ms.suspended, ms);
  ReturnTo(ts, p, ms);
  if (__builtin_expect(ms.invariants_plan != ts.plan_serial, 0)) {
    LoadInvariants(ts, ms, p.module_index);
  }
  if (ms.loaded != &p) Apply(ms, p);
  if (ms.index_written != ts.index_serial && p.kind != ProgramKind::kBoundingBox) {
    // The tile loop has just stored the index as an 8-byte and a 4-byte word (StoreIndex), which
    // the copies load whole.
    WriteSlots<sizeof(ts.index)>(ms, p.launch_index, ts.index.data());
    WriteSlots<sizeof(ts.dims)>(ms, p.launch_dim, ts.dims.data());
    // Attributes a program leaves unwritten read zeros, not what the thread's last launch index
    // left: output must not depend on which launch indices shared a thread.
    for (const BoundProgram::Attribute& a : p.attributes) ZeroBytes(ms.slots[a.var], a.size);
    ms.index_written = ts.index_serial;
  }
  if (__builtin_expect(!p.time.empty(), 0)) WriteTime(ts, ms, p);
}

// Suspends the running program's module across a nested call, in `s`; Resume restores it if
// needed.
inline SuspendedSlots& SuspendInto(ThreadState& ts, SuspendedSlots& s) {
  s.module = ts.current_module;
  s.outer = s.module->suspended;
  s.saved = false;
  s.reads_per_call = ts.kind != ProgramKind::kRayGeneration && ts.kind != ProgramKind::kException;
  s.module->suspended = &s;
  return s;
}
inline SuspendedSlots& Suspend(ThreadState& ts, size_t level) {
  return SuspendInto(ts, ts.suspended[level]);
}
// Puts back a suspended program's per-call values and binding (runtime.cc): another program of its
// module ran while it was suspended.
void RestoreSaved(const SuspendedSlots& s);
inline void Resume(ThreadState& ts, SuspendedSlots& s) {
  if (s.saved) {
    if (s.reads_per_call) {
      RestoreSaved(s);
    } else if (s.module->loaded != s.loaded && s.loaded != nullptr) {
      Apply(*s.module, *s.loaded);  // a ray generation program needs back only its binding
    }
  }
  s.module->suspended = s.outer;
}

// Raises `code` if it is enabled (throws ExceptionSignal); otherwise returns so the caller skips
// the offending operation.
void Raise(unsigned code, std::string details);

// Which program kinds may make a call: bit per ProgramKind.
constexpr unsigned Bit(ProgramKind k) { return 1u << static_cast<unsigned>(k); }
[[noreturn]] void CallNotAllowed(const ThreadState& ts, const char* call);
inline void CheckCall(ThreadState& ts, unsigned allowed, const char* call) {
  if (__builtin_expect(!(allowed & Bit(ts.kind)), 0)) CallNotAllowed(ts, call);
}

// Calls `p`'s function. A module's symbols carry no signature, so a bounding box program
// (`void f(int primitive, float result[6])`) may be set as any kind; every kind is therefore
// called with a primitive (0 where the kind has none) and a result pointer to per-thread scratch,
// harmless for functions that take fewer arguments. The first calls of a program check the
// scratch and fail the launch, naming the program, when it wrote there (runtime.cc).
void CallProgramChecked(ThreadState& ts, const BoundProgram& p, int primitive);
// The check after the call; RunAnyHit makes it itself when rtIgnoreIntersection or rtTerminateRay
// ended the program (an any-hit program that always ends so would otherwise be checked forever).
void VerifyScratch(ThreadState& ts, const BoundProgram& p);
inline void CallProgram(ThreadState& ts, const BoundProgram& p, int primitive = 0) {
  if (__builtin_expect(__atomic_load_n(&p.arguments_checked, __ATOMIC_RELAXED), 1)) {
    reinterpret_cast<void (*)(int, float*)>(p.function)(primitive, ts.scratch_result);
  } else {
    CallProgramChecked(ts, p, primitive);
  }
}

// Traversal entry points (trace.cc).
void RtTrace(unsigned long long node, const void* ray, void* payload, size_t payload_size);
void RtTraceWithFlags(unsigned long long node, const void* ray, void* payload, size_t payload_size,
                      unsigned mask, unsigned flags, int has_time, float time);
int RtPotentialIntersection(float t);
int RtReportIntersection(unsigned material);
void RtIgnoreIntersection();
void RtTerminateRay();
void RtIntersectChild(unsigned index);
// rtCallableProgram calls (callable.cc).
void* RtCallableEnter(const void* variable, TesseraCallFrame* frame);
void RtCallableLeave(TesseraCallFrame* frame);
// Makes `callee` (an rtCallableProgram variable's binding, or a program called by id) the running
// program, keeping its caller in *frame, and returns its function (callable.cc).
void* EnterCallee(ThreadState& ts, const BoundProgram& callee, TesseraCallFrame* frame);
// Ends the calls an any-hit program made (innermost first) before rtIgnoreIntersection or
// rtTerminateRay leaves their frames behind.
void EndAnyHitCalls(ThreadState& ts);
// OptiX 6 hit queries (trace.cc).
unsigned RtGetPrimitiveIndex();
unsigned RtTriangleHit();  // 0: not built-in triangles, 1: front face, 2: back face
void RtTriangleBarycentrics(float* uv);
// tesseraSpawnPoint (trace.cc).
void RtSpawnPoint(const float* dir, float* origin);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_THREAD_STATE_H_
