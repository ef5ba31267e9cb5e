// Per-thread execution state of the OptiX 7 engine: the running program (its kind, SBT data, the
// ray and hit it sees), one frame per optixTrace in progress, the exception being handled, and
// how any-hit programs end. Each thread owns its state, so nothing on the per-ray path locks.
// Internal to worker/core (optix7_*.cc).
#ifndef TESSERA_WORKER_CORE_OPTIX7_THREAD_H_
#define TESSERA_WORKER_CORE_OPTIX7_THREAD_H_

#include <embree3/rtcore.h>

#include <array>
#include <csetjmp>
#include <cstdint>
#include <exception>
#include <string>
#include <vector>

#include "optix7_launch.h"
#include "optix7_scene.h"
#include "runtime.h"
#include "tessera/optix7_device_abi.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::worker {

enum class Optix7Kind : uint8_t {
  kRaygen,
  kMiss,
  kClosestHit,
  kAnyHit,
  kIntersection,
  kException,
  kDirectCallable,
  kContinuationCallable,
};

// The instances and transforms between a trace's root and the scene being traversed (the
// transform list, outermost first), with their product at the ray's time.
struct Optix7Path {
  static constexpr unsigned kMax = Optix7SceneCache::kMaxGraphDepth;
  uint32_t size = 0;
  uint32_t instance_index = 0;                      // of `instance` in its IAS
  const Optix7Scene::Instance* instance = nullptr;  // the last (innermost) instance
  alignas(16) float to_world[12];                   // when size > 0
  alignas(16) float to_object[12];
  uint64_t handles[kMax];                        // instance records' and transforms' handles
  const Optix7Scene::Instance* instances[kMax];  // null for transforms

  // Appends a transform (`inst` null) or an instance, given its matrices at the ray's time.
  void Push(uint64_t handle, const Optix7Scene::Instance* inst, const float w[12],
            const float o[12]);
};

// A primitive under consideration or hit: where it is and, once reported, how it was hit.
struct Optix7Hit {
  float t = 0;
  // Built-in primitives: their face is worked out when a program asks for the hit kind (or the
  // ray's culling flags need it), not at every hit: SettleHitKind. Read it through HitKind.
  uint32_t hit_kind = 0;
  bool face_pending = false;
  uint32_t attributes[8] = {};  // triangles: the barycentrics' bits in 0 and 1
  uint32_t primitive = 0;       // optixGetPrimitiveIndex: with the input's primitive index offset
  uint32_t sbt_gas_index = 0;
  uint32_t geometry_flags = 0;                      // the record's OptixGeometryFlags
  const Optix7Scene::Instance* instance = nullptr;  // the innermost; null: no instance on the way
  uint32_t instance_index = 0;
  uint64_t gas = 0;  // the GAS's traversable handle
  const Optix7Scene* gas_scene = nullptr;
  Optix7Path path;  // the transform list; path.size 0: object space is world space
  const Optix7Scene::Geometry* geometry = nullptr;
  uint32_t local_primitive = 0;  // within the build input (Embree's primID)
  const Optix7Record* record = nullptr;
};

// One optixTrace in progress.
struct Optix7Frame {
  TesseraOptix7Trace ray{};  // world space; SBT offset, stride and miss index already masked
  uint32_t payload[32] = {};
  uint32_t num_payload = 0;
  unsigned int* const* variables = nullptr;  // the caller's payload variables
  uint64_t root_handle = 0;
  const Optix7Scene* root = nullptr;
  Optix7Hit candidate;  // of the running intersection or any-hit program
  Optix7Hit committed;  // the closest accepted so far, when `has_committed`
  bool has_committed = false;
  bool terminated = false;  // optixTerminateRay or TERMINATE_ON_FIRST_HIT: accept no more hits
  // An exception or error raised inside an Embree callback: kept there (nothing may unwind
  // through Embree) and rethrown once traversal returns.
  std::exception_ptr pending;
  // While an intersection program runs: Embree's ray and hit (object-space ray, current tfar)
  // and the instance ID it reached the primitive through.
  RTCRayHit* embree = nullptr;
  unsigned embree_geometry = 0, embree_instance = 0;
};

// What the running program sees.
struct Optix7Context {
  Optix7Kind kind = Optix7Kind::kRaygen;
  const Optix7Record* record = nullptr;  // its SBT record (optixGetSbtDataPointer)
  Optix7Frame* frame = nullptr;          // the ray it serves; null in raygen and exception
  Optix7Hit* hit = nullptr;              // intersection and any-hit: the candidate; closest hit
};

// An exception raised at a launch index (optixThrowException, or one of OptiX's built-in codes):
// thrown as a C++ exception to the launch index's loop, which runs the exception program.
struct Optix7Exception {
  int code = 0;
  std::string text;  // for the report without exception program
  uint32_t details[8] = {};
  uint64_t invalid_traversable = 0;
  int invalid_sbt_offset = 0;
  float invalid_ray[9] = {};
};

struct Optix7Lane;

// The native stack a launch index may use below where it began (the thread's tile, or its lane's
// stack): optixTrace and callables raise OPTIX_EXCEPTION_CODE_STACK_OVERFLOW past it.
inline constexpr size_t kOptix7StackBudget = 3 * 1024 * 1024 + 256 * 1024;

struct Optix7Thread {
  const Optix7Launch* launch = nullptr;
  // Batched tracing (optix7_batch.h): the lane this state runs a launch index of (null: the
  // thread's own state) and the state whose tile reports it shares (its own, for a thread).
  Optix7Lane* lane = nullptr;
  Optix7Thread* tile = this;
  Index3 index{}, dims{};
  v1::TileResult* out = nullptr;
  bool report_sent = false;                         // this tile's first report went out (tile)
  v1::ExceptionReport* reports_not_sent = nullptr;  // counts the rest (tile)
  Optix7Context ctx;
  std::vector<Optix7Context> callers;  // of the callables running, innermost last
  std::array<Optix7Frame, 32> frames;  // frames[0, depth) are live; maxTraceDepth <= 31
  unsigned depth = 0;
  Optix7Exception exception;  // the one the exception program handles
  // Any-hit programs end through optixIgnoreIntersection and optixTerminateRay without returning:
  // they jump back to RunAnyHit (optix7_trace.cc), which set `any_hit_end`.
  std::jmp_buf* any_hit_end = nullptr;
  bool ignored = false, terminate = false;
  // The last scene looked up by handle, for the launch of serial `scene_serial`.
  uint64_t scene_serial = 0, scene_handle = 0;
  const Optix7Scene* scene = nullptr;
  // Nested optixTrace and callable calls raise OPTIX_EXCEPTION_CODE_STACK_OVERFLOW below this
  // address: a fixed budget below where the tile began, so the same on every thread.
  const char* stack_limit = nullptr;
  const char* stack_floor = nullptr;  // the thread's stack end plus a reserve

  Optix7Frame& top() { return frames[depth - 1]; }
};

// The calling thread's state: initial-exec TLS, one load per access.
extern __thread Optix7Thread* t_optix7 __attribute__((tls_model("initial-exec")));
Optix7Thread& CreateOptix7Thread();
inline Optix7Thread& Optix7TS() {
  if (__builtin_expect(t_optix7 == nullptr, 0)) return CreateOptix7Thread();
  return *t_optix7;
}

// The table that OptiX 7 modules receive (optix7_runtime.cc), and its exception and callable
// entries (optix7_calls.cc).
const TesseraOptix7Runtime* Optix7Runtime();
void FillCallsTable(TesseraOptix7Runtime& r);

// Throws Optix7Exception `e`, filling its text with the code's name, the launch index, the running
// program and `what`.
[[noreturn]] void Raise(Optix7Thread& ts, Optix7Exception e, const std::string& what);
// A launch-stopping error (FatalError) naming the running program: "`call` from <program>: what".
[[noreturn]] void Fail(const Optix7Thread& ts, const char* call, const std::string& what);
// Fails unless the running program is of a kind in `kinds` (bits of Optix7Kind).
constexpr unsigned KindBit(Optix7Kind k) { return 1u << static_cast<unsigned>(k); }
void CheckKind(const Optix7Thread& ts, unsigned kinds, const char* call);
std::string ProgramName(const Optix7Context& ctx);
const char* ExceptionCodeName(int code);

// The scene of traversable `handle` for the thread's launch (cached per thread); fails naming
// `call` when the handle is not one the engine can trace.
const Optix7Scene* SceneOf(Optix7Thread& ts, uint64_t handle, const char* call);

// Tracing (optix7_trace.cc). The intersection functions of custom primitives and of nodes
// (Optix7Node) are Embree's, handed to Optix7SceneCache.
RTCIntersectFunctionN Optix7IntersectFunction();
RTCIntersectFunctionN Optix7NodeIntersectFunction();
// Hit kinds of built-in spheres (custom primitives have 0..127, triangles 0xFE and 0xFF); the
// lowest bit says the face, 0 front, as for triangles.
inline constexpr unsigned kOptix7SphereFrontFace = 0x86, kOptix7SphereBackFace = 0x87;
// Vertex `index` of a triangle or sphere build input of GAS `gas` (its descriptor) at Embree time
// `time` (the GAS's motion range as [0, 1]): keys interpolated as Embree does. `n` floats.
void Optix7Vertex(uint64_t gas, const memory::AccelInput& in, const Optix7Scene& s, uint32_t index,
                  float time, unsigned n, float* out);
void Optix7Trace(const TesseraOptix7Trace* ray, unsigned int num_payload,
                 unsigned int* const* payload);
// The hit kind of `h` (the frame's candidate or committed hit), its face worked out first if it
// is pending.
uint32_t Optix7HitKind(const Optix7Frame& f, Optix7Hit& h);

int Optix7ReportIntersection(float hit_t, unsigned int hit_kind, unsigned int num_attributes,
                             const unsigned int* attributes);
void Optix7IgnoreIntersection();
void Optix7TerminateRay();

// Accuracy (optix7_accuracy.cc): the table's tesseraOptixGetSpawnPoint entry, and
// TESSERA_ACCURACY_OFFSET_RAYS: a ray the running closest-hit program traces from its triangle
// hit's point (StartsAtHit, watertight.h) starts at the spawn point instead, with tmin 0.
void FillAccuracyTable(TesseraOptix7Runtime& r);
void OffsetSpawnedRay(const Optix7Thread& ts, TesseraOptix7Trace& ray);
// Forgets what a launch index left half done (an exception or an interrupt unwound it).
void ResetOptix7Nesting(Optix7Thread& ts);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_THREAD_H_
