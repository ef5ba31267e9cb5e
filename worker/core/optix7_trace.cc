// optixTrace over Embree: SBT indexing (OptiX 7.7 guide 7.3), visibility masks, ray, instance and
// geometry flags, intersection and any-hit programs run from Embree's callbacks, then the
// closest-hit or miss program. Nothing unwinds through Embree: an exception raised in a callback
// waits in the frame until traversal returns.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "float_steps.h"
#include "interrupt.h"
#include "optix7_batch.h"
#include "optix7_engine.h"
#include "optix7_thread.h"
#include "optix_types.h"
#include "tessera/accuracy.h"

namespace tessera::worker {
namespace {

// What Embree hands the callbacks: its context first, then the trace's own state. One per
// rtcIntersect1: the trace's root, or a node's child (Optix7Node) traced in the child's space.
struct TraceContext {
  RTCIntersectContext rtc;
  Optix7Thread* ts;
  Optix7Frame* frame;
  const Optix7Scene* scene;  // what this rtcIntersect1 traverses
  uint64_t scene_handle;     // its traversable handle
  const Optix7Path* path;    // between the root and `scene`; null at the root
};

template <typename T>
T Read(uint64_t address) {
  T v;
  std::memcpy(&v, reinterpret_cast<const void*>(address), sizeof(v));
  return v;
}

// Makes `ctx` the running program's for the scope, restoring the caller's on every way out.
class Running {
 public:
  Running(Optix7Thread& ts, const Optix7Context& ctx) : ts_(ts), saved_(ts.ctx) { ts.ctx = ctx; }
  ~Running() { ts_.ctx = saved_; }
  Running(const Running&) = delete;
  Running& operator=(const Running&) = delete;

 private:
  Optix7Thread& ts_;
  Optix7Context saved_;
};

// An instance's handle in a transform list is the address of its OptixInstance record in the
// IAS descriptor, which optixGetInstance*FromHandle read like OptiX's.
uint64_t InstanceRecord(uint64_t ias, uint32_t index) {
  const auto* header = reinterpret_cast<const memory::AccelHeader*>(ias);
  return ias + header->inputs_offset + uint64_t{index} * memory::kInstanceBytes;
}

// Where primitive `prim` of Embree geometry `geom` lies, reached through Embree instance `inst`
// of the context's scene (an IAS) or directly (a GAS), below the context's path, and which hit
// group record it runs (guide 7.3: instance.sbtOffset + sbtGASIndex * sbtStride + sbtOffset; the
// instance is the innermost one, the most recently visited).
void Locate(const TraceContext& c, unsigned inst, unsigned geom, unsigned prim, Optix7Hit& h) {
  Optix7Thread& ts = *c.ts;
  const Optix7Frame& f = *c.frame;
  const Optix7Scene* gas = c.scene;
  h.gas = c.scene_handle;
  if (c.path != nullptr) {
    h.path = *c.path;
  } else {
    h.path.size = 0;
    h.path.instance = nullptr;
    h.path.instance_index = 0;
  }
  if (c.scene->kind == memory::AccelKind::kInstances) {
    const Optix7Scene::Instance& instance = c.scene->instances[inst];
    h.path.Push(InstanceRecord(c.scene_handle, inst), &instance, instance.to_world,
                instance.to_object);
    h.path.instance = &instance;
    h.path.instance_index = inst;
    gas = c.scene->children[inst];
    h.gas = instance.child;
  }
  h.instance = h.path.instance;
  h.instance_index = h.path.instance_index;
  h.gas_scene = gas;
  const Optix7Scene::Geometry& g = gas->geometries[geom];
  h.geometry = &g;
  h.local_primitive = prim;
  h.primitive = prim + g.input.primitive_index_offset;
  uint32_t local_sbt = 0;
  if (g.input.num_sbt_records > 1) {
    local_sbt = Read<uint32_t>(h.gas + g.input.sbt_index_offsets_offset + 4ull * prim);
  }
  h.sbt_gas_index = g.sbt_base + local_sbt;
  h.geometry_flags = Read<uint32_t>(h.gas + g.input.flags_offset + 4ull * local_sbt);
  const uint64_t index = uint64_t{h.instance != nullptr ? h.instance->sbt_offset : 0} +
                         uint64_t{h.sbt_gas_index} * f.ray.sbt_stride + f.ray.sbt_offset;
  const std::vector<Optix7Record>& records = ts.launch->hit;
  if (index >= records.size()) {
    Optix7Exception e;
    e.code = OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_HIT_SBT;
    e.invalid_sbt_offset = static_cast<int>(index);
    Raise(ts, e,
          absl::StrCat("hit group record ", index, " (instance SBT offset ",
                       h.instance != nullptr ? h.instance->sbt_offset : 0, ", SBT-GAS index ",
                       h.sbt_gas_index, ", stride ", f.ray.sbt_stride, ", offset ",
                       f.ray.sbt_offset, ") past the ", records.size(), " hit group records"));
  }
  h.record = &records[index];
}

// OptiX 7.7 guide 5.5 and 11.2: instance masks against the ray's (a GAS traced directly has none).
inline bool Visible(const Optix7Frame& f, const Optix7Hit& h) {
  return h.instance == nullptr || (h.instance->mask & f.ray.visibility_mask & 0xFFu) != 0;
}

enum class AnyHit { kCull, kOpaque, kRun };

// Whether the hit's any-hit program runs: geometry flags, overridden by instance flags,
// overridden by ray flags (guide 11.2); the culling ray flags act on the outcome.
AnyHit DecideAnyHit(const Optix7Frame& f, const Optix7Hit& h) {
  const unsigned ray = f.ray.ray_flags;
  const unsigned inst = h.instance != nullptr ? h.instance->flags : 0;
  bool enabled = !(h.geometry_flags & OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT);
  if (inst & OPTIX_INSTANCE_FLAG_DISABLE_ANYHIT) enabled = false;
  if (inst & OPTIX_INSTANCE_FLAG_ENFORCE_ANYHIT) enabled = true;
  if (ray & OPTIX_RAY_FLAG_DISABLE_ANYHIT) enabled = false;
  if (ray & OPTIX_RAY_FLAG_ENFORCE_ANYHIT) enabled = true;
  if ((ray & OPTIX_RAY_FLAG_CULL_DISABLED_ANYHIT) && !enabled) return AnyHit::kCull;
  if ((ray & OPTIX_RAY_FLAG_CULL_ENFORCED_ANYHIT) && enabled) return AnyHit::kCull;
  return enabled && h.record->group->any_hit.function != nullptr ? AnyHit::kRun : AnyHit::kOpaque;
}

// The world-space direction in the hit's object space.
void ObjectDirection(const Optix7Frame& f, const Optix7Hit& h, float out[3]) {
  const float* d = f.ray.direction;
  if (h.path.size == 0) {
    std::memcpy(out, d, 3 * sizeof(float));
    return;
  }
  const float* m = h.path.to_object;
  for (int r = 0; r < 3; ++r) out[r] = m[r * 4] * d[0] + m[r * 4 + 1] * d[1] + m[r * 4 + 2] * d[2];
}

// A triangle's hit kind, from its vertices as the descriptor holds them: front where its
// vertices wind counter-clockwise seen from the ray (the normal (v1-v0) x (v2-v0) faces the
// ray), flipped by OPTIX_INSTANCE_FLAG_FLIP_TRIANGLE_FACING.
void TriangleFace(const Optix7Frame& f, Optix7Hit& h) {
  const memory::AccelInput& in = h.geometry->input;
  uint32_t idx[3];
  std::memcpy(idx,
              reinterpret_cast<const void*>(h.gas + in.indices_offset + 12ull * h.local_primitive),
              sizeof(idx));
  float p[3][3];
  const float time = h.gas_scene->time.Normalized(f.ray.ray_time);
  for (int k = 0; k < 3; ++k) Optix7Vertex(h.gas, in, *h.gas_scene, idx[k], time, 3, p[k]);
  const float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  const float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
  float d[3];
  ObjectDirection(f, h, d);
  bool front = n[0] * d[0] + n[1] * d[1] + n[2] * d[2] < 0.f;
  const unsigned inst = h.instance != nullptr ? h.instance->flags : 0;
  if (inst & OPTIX_INSTANCE_FLAG_FLIP_TRIANGLE_FACING) front = !front;
  h.hit_kind = front ? OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE : OPTIX_HIT_KIND_TRIANGLE_BACK_FACE;
}

// A sphere's hit kind: front where the ray enters it (the hit point's offset from the centre
// against the ray), back where it leaves (a ray from inside).
void SphereFace(const Optix7Frame& f, Optix7Hit& h) {
  float c[4];
  Optix7Vertex(h.gas, h.geometry->input, *h.gas_scene, h.local_primitive,
               h.gas_scene->time.Normalized(f.ray.ray_time), 4, c);
  float o[3], d[3];
  ObjectDirection(f, h, d);
  if (h.path.size == 0) {
    std::memcpy(o, f.ray.origin, sizeof(o));
  } else {
    const float* m = h.path.to_object;
    for (int r = 0; r < 3; ++r) {
      o[r] = m[r * 4] * f.ray.origin[0] + m[r * 4 + 1] * f.ray.origin[1] +
             m[r * 4 + 2] * f.ray.origin[2] + m[r * 4 + 3];
    }
  }
  float dot = 0.f;
  for (int r = 0; r < 3; ++r) dot += (o[r] + h.t * d[r] - c[r]) * d[r];
  h.hit_kind = dot < 0.f ? kOptix7SphereFrontFace : kOptix7SphereBackFace;
}

void SettleFace(const Optix7Frame& f, Optix7Hit& h) {
  if (h.gas_scene->kind == memory::AccelKind::kSpheres) {
    SphereFace(f, h);
  } else {
    TriangleFace(f, h);
  }
  h.face_pending = false;
}

// Runs an any-hit program until it returns or ends itself: optixIgnoreIntersection and
// optixTerminateRay do not return, as in OptiX. They jump back here; what that skips is the
// program's own frames (any-hit programs cannot trace, so no engine state lives there) and the
// callables it called, whose callers are dropped here.
__attribute__((noinline)) void RunAnyHit(Optix7Thread& ts, Optix7Function fn) {
  std::jmp_buf end;
  struct Restore {
    Optix7Thread& ts;
    std::jmp_buf* outer;
    size_t callers;
    ~Restore() {  // also when the program throws
      ts.any_hit_end = outer;
      ts.callers.resize(callers);
    }
  } restore{ts, ts.any_hit_end, ts.callers.size()};
  ts.any_hit_end = &end;
  ts.ignored = ts.terminate = false;
  if (setjmp(end) == 0) fn();
}

// Offers candidate `h` (reported, not culled) to its any-hit program if one runs, and commits it
// unless the program ignored it. Returns whether it was accepted.
bool Accept(Optix7Thread& ts, Optix7Frame& f, const Optix7Hit& h, AnyHit decision) {
  bool terminate = false;
  if (decision == AnyHit::kRun) {
    Running running(ts, Optix7Context{Optix7Kind::kAnyHit, h.record, &f, &f.candidate});
    if (&f.candidate != &h) f.candidate = h;
    RunAnyHit(ts, h.record->group->any_hit.function);
    if (ts.ignored) return false;
    terminate = ts.terminate;
  }
  f.committed = h;
  f.has_committed = true;
  if (terminate || (f.ray.ray_flags & OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT)) f.terminated = true;
  return true;
}

// A built-in primitive's attributes (a triangle's barycentrics; spheres have none), with its face
// left pending unless the ray's culling flags need it now (a face costs the primitive's
// vertices: the eyelight bench spent 5% of its time there for programs that never asked).
// False when culled.
bool Face(const Optix7Frame& f, Optix7Hit& h, float u, float v) {
  std::memset(h.attributes, 0, sizeof(h.attributes));
  const bool triangles = h.gas_scene->kind != memory::AccelKind::kSpheres;
  if (triangles) {
    std::memcpy(&h.attributes[0], &u, 4);
    std::memcpy(&h.attributes[1], &v, 4);
  }
  h.face_pending = true;
  constexpr unsigned kCulling =
      OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES | OPTIX_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES;
  const unsigned ray = f.ray.ray_flags;
  if (!triangles || (ray & kCulling) == 0) return true;
  const unsigned inst = h.instance != nullptr ? h.instance->flags : 0;
  if (inst & OPTIX_INSTANCE_FLAG_DISABLE_TRIANGLE_FACE_CULLING) return true;
  SettleFace(f, h);
  const bool front = h.hit_kind == OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE;
  if ((ray & OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES) && !front) return false;
  if ((ray & OPTIX_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES) && front) return false;
  return true;
}

// Embree's filter for built-in triangles and spheres, in traces that need one (NeedsFilter).
void FilterTriangle(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<TraceContext*>(args->context);
  Optix7Frame& f = *c->frame;
  if (f.pending || f.terminated) {
    args->valid[0] = 0;
    return;
  }
  try {
    const unsigned n = args->N;
    Optix7Hit& h = f.candidate;
    Locate(*c, RTCHitN_instID(args->hit, n, 0, 0), RTCHitN_geomID(args->hit, n, 0),
           RTCHitN_primID(args->hit, n, 0), h);
    h.t = RTCRayN_tfar(args->ray, n, 0);
    // Embree's tnear is below tmin (EmbreeTnear): what its rounding puts before tmin is no hit;
    // what it puts past tmax (a reciprocal's ulp) is at tmax.
    if (!(h.t >= f.ray.tmin)) {
      args->valid[0] = 0;
      return;
    }
    h.t = std::min(h.t, f.ray.tmax);
    bool keep = Visible(f, h) && Face(f, h, RTCHitN_u(args->hit, n, 0), RTCHitN_v(args->hit, n, 0));
    if (keep) {
      const AnyHit decision = DecideAnyHit(f, h);
      keep = decision != AnyHit::kCull && Accept(*c->ts, f, h, decision);
    }
    if (!keep) args->valid[0] = 0;
  } catch (...) {
    f.pending = std::current_exception();
    args->valid[0] = 0;
  }
}

// Whether the ray of `rh` (in the primitive's space) meets custom primitive `h`'s box at the
// ray's time, its keys interpolated (guide 5.10.1). Embree's motion bounds only cull (a leaf's
// primitives all see its rays), so the engine tests the interpolated box itself, as OptiX does
// before it runs an intersection program.
bool MeetsMovingBox(const Optix7Frame& f, const Optix7Hit& h, const RTCRayHit& rh) {
  const Optix7Scene& s = *h.gas_scene;
  const memory::AccelInput& in = h.geometry->input;
  const float time = s.time.Normalized(f.ray.ray_time) * static_cast<float>(s.motion.keys - 1);
  const unsigned k = std::min(static_cast<unsigned>(time), s.motion.keys - 2);
  const float t = time - static_cast<float>(k);
  float a[6], b[6];
  const uint64_t box = h.gas + in.aabbs_offset + 24ull * h.local_primitive;
  std::memcpy(a, reinterpret_cast<const void*>(box + 24ull * in.primitive_count * k), sizeof(a));
  std::memcpy(b, reinterpret_cast<const void*>(box + 24ull * in.primitive_count * (k + 1)),
              sizeof(b));
  const float o[3] = {rh.ray.org_x, rh.ray.org_y, rh.ray.org_z};
  const float d[3] = {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z};
  float lo = rh.ray.tnear, hi = rh.ray.tfar;
  for (int i = 0; i < 3; ++i) {
    const float min = (1.f - t) * a[i] + t * b[i], max = (1.f - t) * a[3 + i] + t * b[3 + i];
    if (d[i] == 0.f) {
      if (o[i] < min || o[i] > max) return false;
      continue;
    }
    float t0 = (min - o[i]) / d[i], t1 = (max - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  return lo <= hi;
}

// Embree's intersection function for custom primitives: runs the hit group's intersection
// program, whose optixReportIntersection calls come to Optix7ReportIntersection.
void IntersectCustom(const RTCIntersectFunctionNArguments* args) {
  auto* c = reinterpret_cast<TraceContext*>(args->context);
  Optix7Frame& f = *c->frame;
  if (!args->valid[0] || f.pending || f.terminated) return;
  Optix7Thread& ts = *c->ts;
  try {
    Optix7Hit& h = f.candidate;
    const unsigned inst = args->context->instID[0];
    Locate(*c, inst, args->geomID, args->primID, h);
    if (!Visible(f, h) || DecideAnyHit(f, h) == AnyHit::kCull) return;
    if (h.gas_scene->motion.moves() &&
        !MeetsMovingBox(f, h, *reinterpret_cast<const RTCRayHit*>(args->rayhit))) {
      return;
    }
    const Optix7Group& g = *h.record->group;
    if (g.intersection.function == nullptr) {
      Fail(ts, "optixTrace",
           absl::StrCat("hit group record ", h.record->index, " (program group ", g.id,
                        ") is hit on custom primitives but has no intersection program"));
    }
    f.embree = reinterpret_cast<RTCRayHit*>(args->rayhit);
    f.embree_geometry = args->geomID;
    f.embree_instance = inst;
    Running running(ts, Optix7Context{Optix7Kind::kIntersection, h.record, &f, &h});
    g.intersection.function();
  } catch (...) {
    f.pending = std::current_exception();
  }
  f.embree = nullptr;
}

// Embree's tnear for a trace from tmin: Embree counts hits after tnear, OptiX from tmin on ("any
// reported hits with hitT outside of this range are ignored": [tmin, tmax] closed), so the float
// before it; hits that land before tmin are refused by the filter or by IntersectClosed. Embree
// refuses a negative tnear, so from tmin 0 a native triangle at exactly t = 0 (the ray's origin
// on it) is not hit; watertight triangles and intersection programs are.
float EmbreeTnear(float tmin) { return tmin > 0.f ? NextFloatDown(tmin) : 0.f; }

// rtcIntersect1 over OptiX's closed [tmin, tmax]. Without the filter, a triangle hit whose t
// rounds below tmin is traversed again from tmin itself (Embree's open end, rare); a t past tmax
// by rounding is tmax.
// `lane`: a lane's state whose ray goes to Embree in its block's packet (optix7_batch.h) instead,
// traced in `root`.
// Inlined: a lane resumes inside it, and each return between the suspension and optixTrace's
// caller is a mispredicted one (optix7_batch.h).
__attribute__((always_inline)) inline void IntersectClosed(
    RTCScene scene, RTCIntersectContext* context, RTCRayHit& rh, float tmin, bool filtered,
    const Optix7Frame& f, Optix7Thread* lane = nullptr, const Optix7Scene* root = nullptr) {
  const float tfar = rh.ray.tfar;
  if (lane != nullptr) {
    Optix7Batch::Wait(*lane, *root, rh);
  } else {
    rtcIntersect1(scene, context, &rh);
  }
  if (filtered || f.pending || rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
  if (!(rh.ray.tfar >= tmin)) {
    rh.ray.tnear = tmin;
    rh.ray.tfar = tfar;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, context, &rh);
  }
  if (rh.ray.tfar > tfar) rh.ray.tfar = tfar;
}

void RethrowPending(Optix7Frame& f) {
  if (f.pending) {
    std::exception_ptr p = f.pending;
    f.pending = nullptr;
    std::rethrow_exception(p);
  }
}

// Whether triangles of this trace need the per-hit filter: any-hit programs, culling, early
// termination, or an instance mask the ray's does not meet.
bool NeedsFilter(const Optix7Thread& ts, const Optix7Frame& f) {
  constexpr unsigned kPerHitFlags =
      OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT | OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES |
      OPTIX_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES | OPTIX_RAY_FLAG_CULL_DISABLED_ANYHIT |
      OPTIX_RAY_FLAG_CULL_ENFORCED_ANYHIT;
  if (ts.launch->any_hit || (f.ray.ray_flags & kPerHitFlags)) return true;
  return f.root->kind == memory::AccelKind::kInstances &&
         !f.root->all_visible.test(f.ray.visibility_mask & 0xFFu);
}

bool Finite(float v) { return std::isfinite(v); }

// OPTIX_EXCEPTION_CODE_INVALID_RAY's condition (guide 11.14): an inf or NaN argument, or a
// negative tmin. tmax may be infinite.
bool ValidRay(const TesseraOptix7Trace& r) {
  for (int i = 0; i < 3; ++i) {
    if (!Finite(r.origin[i]) || !Finite(r.direction[i])) return false;
  }
  return Finite(r.tmin) && r.tmin >= 0.f && !std::isnan(r.tmax) && Finite(r.ray_time);
}

__attribute__((noinline)) void RejectTrace(Optix7Thread& ts, const TesseraOptix7Trace& r) {
  Optix7Exception e;
  if (ts.depth >= ts.launch->max_trace_depth) {
    e.code = OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED;
    Raise(ts, e,
          absl::StrCat("optixTrace ", ts.depth + 1, " deep exceeds the pipeline's maxTraceDepth ",
                       ts.launch->max_trace_depth));
  }
  if (static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit) {
    e.code = OPTIX_EXCEPTION_CODE_STACK_OVERFLOW;
    Raise(ts, e, "optixTrace: the launch index has used the native stack it may take");
  }
  e.code = OPTIX_EXCEPTION_CODE_INVALID_RAY;
  const float v[9] = {r.origin[0],    r.origin[1], r.origin[2], r.direction[0], r.direction[1],
                      r.direction[2], r.tmin,      r.tmax,      r.ray_time};
  std::memcpy(e.invalid_ray, v, sizeof(v));
  Raise(ts, e,
        absl::StrFormat("invalid ray: origin (%g, %g, %g) direction (%g, %g, %g) tmin %g tmax %g "
                        "time %g",
                        v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]));
}

// Commits the hit an rtcIntersect1 of context `c` returned, unless it is committed already. The
// last hit accepted is the closest: a filter saw every built-in primitive accepted, custom
// primitives commit as they are reported, and a node commits its child's hit before reporting
// it; a triangle or sphere that no filter saw is committed here.
void Resolve(const TraceContext& c, const RTCRayHit& rh, bool filtered) {
  if (filtered || rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
  const Optix7Scene* gas = c.scene;
  if (c.scene->kind == memory::AccelKind::kInstances) {
    if (rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID) return;  // a node's
    gas = c.scene->children[rh.hit.instID[0]];
  }
  if (gas->kind == memory::AccelKind::kCustom) return;
  Optix7Frame& f = *c.frame;
  Optix7Hit& h = f.committed;
  Locate(c, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID, h);
  h.t = rh.ray.tfar;
  Face(f, h, rh.hit.u, rh.hit.v);  // no culling flags without the filter
  f.has_committed = true;
}

// Embree's intersection function of nodes (Optix7Node): the instance's mask, the transforms at
// the ray's time (a vanished one hides the child), then the child's scene traced in its space
// with the same tmin and tmax (directions are not normalized, so distances stay the same in
// every space); its closest hit is committed and reported to the enclosing traversal.
void IntersectNode(const RTCIntersectFunctionNArguments* args) {
  auto* c = reinterpret_cast<TraceContext*>(args->context);
  Optix7Frame& f = *c->frame;
  if (!args->valid[0] || f.pending || f.terminated) return;
  try {
    const Optix7Node& node = *static_cast<const Optix7Node*>(args->geometryUserPtr);
    const Optix7Scene::Instance& instance = c->scene->instances[node.instance];
    if ((instance.mask & f.ray.visibility_mask & 0xFFu) == 0) return;
    const float time = f.ray.ray_time;
    Optix7Path path;
    if (c->path != nullptr) path = *c->path;
    path.Push(InstanceRecord(c->scene_handle, node.instance), &instance, instance.to_world,
              instance.to_object);
    path.instance = &instance;
    path.instance_index = node.instance;
    for (const Optix7Transform& t : node.transforms) {
      if (t.motion.Vanished(time)) return;
      float w[12], o[12];
      t.At(time, w, o);
      path.Push(t.handle, nullptr, w, o);
    }
    const Optix7Scene& child = *node.child;
    if (child.motion.Vanished(time)) return;
    auto* outer = reinterpret_cast<RTCRayHit*>(args->rayhit);
    RTCRayHit rh;
    const float* m = path.to_object;
    const float* o = f.ray.origin;
    const float* d = f.ray.direction;
    rh.ray.org_x = m[0] * o[0] + m[1] * o[1] + m[2] * o[2] + m[3];
    rh.ray.org_y = m[4] * o[0] + m[5] * o[1] + m[6] * o[2] + m[7];
    rh.ray.org_z = m[8] * o[0] + m[9] * o[1] + m[10] * o[2] + m[11];
    rh.ray.dir_x = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
    rh.ray.dir_y = m[4] * d[0] + m[5] * d[1] + m[6] * d[2];
    rh.ray.dir_z = m[8] * d[0] + m[9] * d[1] + m[10] * d[2];
    rh.ray.tnear = outer->ray.tnear;
    rh.ray.tfar = outer->ray.tfar;
    rh.ray.time = child.time.Normalized(time);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    TraceContext nested;
    rtcInitIntersectContext(&nested.rtc);
    nested.rtc.filter = c->rtc.filter;
    nested.ts = c->ts;
    nested.frame = c->frame;
    nested.scene = &child;
    nested.scene_handle = node.child_handle;
    nested.path = &path;
    IntersectClosed(child.scene, &nested.rtc, rh, f.ray.tmin, c->rtc.filter != nullptr, f);
    if (f.pending || rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
    Resolve(nested, rh, c->rtc.filter != nullptr);
    outer->ray.tfar = rh.ray.tfar;
    outer->hit.geomID = args->geomID;
    outer->hit.primID = args->primID;
    outer->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;  // a node: Resolve leaves it
    outer->hit.u = outer->hit.v = 0.f;
    outer->hit.Ng_x = outer->hit.Ng_y = outer->hit.Ng_z = 0.f;
  } catch (...) {
    f.pending = std::current_exception();
  }
}

void Shade(Optix7Thread& ts, Optix7Frame& f, const RTCRayHit& rh) {
  const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  if (hit) {
    if (f.ray.ray_flags & OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT) return;
    const Optix7Record* record = f.committed.record;
    if (record->group->closest_hit.function == nullptr) return;
    Running running(ts, Optix7Context{Optix7Kind::kClosestHit, record, &f, &f.committed});
    record->group->closest_hit.function();
    return;
  }
  const std::vector<Optix7Record>& miss = ts.launch->miss;
  if (f.ray.miss_sbt_index >= miss.size()) {
    Optix7Exception e;
    e.code = OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_MISS_SBT;
    e.invalid_sbt_offset = static_cast<int>(f.ray.miss_sbt_index);
    Raise(ts, e,
          absl::StrCat("miss record ", f.ray.miss_sbt_index, " past the ", miss.size(),
                       " miss records"));
  }
  const Optix7Record& record = miss[f.ray.miss_sbt_index];
  if (record.group->entry.function == nullptr) return;
  Running running(ts, Optix7Context{Optix7Kind::kMiss, &record, &f, nullptr});
  record.group->entry.function();
}

}  // namespace

RTCIntersectFunctionN Optix7IntersectFunction() { return &IntersectCustom; }
RTCIntersectFunctionN Optix7NodeIntersectFunction() { return &IntersectNode; }

void Optix7Path::Push(uint64_t handle, const Optix7Scene::Instance* inst, const float w[12],
                      const float o[12]) {
  // Scene builds refuse graphs deeper than kMax (Optix7SceneCache::kMaxGraphDepth).
  if (size == 0) {
    std::memcpy(to_world, w, sizeof(to_world));
    std::memcpy(to_object, o, sizeof(to_object));
  } else {
    Compose(to_world, w, to_world);    // outer first: world <- ... <- this
    Compose(o, to_object, to_object);  // this inverse applies last
  }
  handles[size] = handle;
  instances[size] = inst;
  ++size;
}

void Optix7Vertex(uint64_t gas, const memory::AccelInput& in, const Optix7Scene& s, uint32_t index,
                  float time, unsigned n, float* out) {
  const uint64_t key_bytes = uint64_t{n} * 4 * in.vertex_count;
  const uint64_t at = gas + in.vertices_offset + uint64_t{n} * 4 * index;
  if (!s.motion.moves()) {
    std::memcpy(out, reinterpret_cast<const void*>(at), n * sizeof(float));
    return;
  }
  // As Embree interpolates: the segment of `time` among keys - 1 evenly spaced ones.
  const unsigned segments = s.motion.keys - 1;
  const float scaled = time * static_cast<float>(segments);
  const unsigned k = std::min(static_cast<unsigned>(std::max(scaled, 0.f)), segments - 1);
  const float t = scaled - static_cast<float>(k);
  float a[4], b[4];
  std::memcpy(a, reinterpret_cast<const void*>(at + key_bytes * k), n * sizeof(float));
  std::memcpy(b, reinterpret_cast<const void*>(at + key_bytes * (k + 1)), n * sizeof(float));
  for (unsigned i = 0; i < n; ++i) out[i] = (1.f - t) * a[i] + t * b[i];
}

void Optix7Trace(const TesseraOptix7Trace* ray, unsigned int num_payload,
                 unsigned int* const* payload) {
  // A program looping on optixTrace spends its time in the engine and Embree, where an interrupt
  // only leaves a request (interrupt.h).
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts,
            KindBit(Optix7Kind::kRaygen) | KindBit(Optix7Kind::kClosestHit) |
                KindBit(Optix7Kind::kMiss) | KindBit(Optix7Kind::kContinuationCallable),
            "optixTrace");
  if (num_payload > 32) Fail(ts, "optixTrace", absl::StrCat(num_payload, " payload values"));
  const bool debug = ts.launch->exception_flags & OPTIX_EXCEPTION_FLAG_DEBUG;
  if (__builtin_expect(ts.depth >= ts.launch->max_trace_depth ||
                           static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit ||
                           (debug && !ValidRay(*ray)),
                       0)) {
    RejectTrace(ts, *ray);
  }
  Optix7Frame& f = ts.frames[ts.depth];
  f.ray = *ray;
  if (ts.launch->accuracy & TESSERA_ACCURACY_OFFSET_RAYS) OffsetSpawnedRay(ts, f.ray);
  // Guide 10, "Limits": the bits past these widths are ignored.
  f.ray.sbt_offset &= 0xFu;
  f.ray.sbt_stride &= 0xFu;
  f.ray.miss_sbt_index &= 0xFFFFu;
  f.ray.visibility_mask &= 0xFFu;
  f.num_payload = num_payload;
  f.variables = payload;
  for (unsigned i = 0; i < num_payload; ++i) f.payload[i] = *payload[i];
  std::memset(f.payload + num_payload, 0, (32 - num_payload) * sizeof(uint32_t));
  f.has_committed = f.terminated = false;
  f.pending = nullptr;
  f.root_handle = ray->handle;
  // A null handle traces nothing (OptiX allows it: every ray misses); neither does an invalid ray
  // (an infinite or NaN origin, direction, tmin or time, a NaN tmax, a negative tmin: what the
  // DEBUG exception reports) when the DEBUG exception is off, whose Embree result would not be
  // defined: it misses, as does a ray at a time when the root has vanished (its motion flags).
  const bool traverse = ray->handle != 0 && ValidRay(f.ray);
  f.root = traverse ? SceneOf(ts, ray->handle, "optixTrace") : nullptr;
  if (f.root != nullptr && f.root->motion.Vanished(f.ray.ray_time)) f.root = nullptr;
  struct Pop {
    Optix7Thread& ts;
    ~Pop() { --ts.depth; }
  } pop{ts};
  ++ts.depth;

  RTCRayHit rh;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  bool filtered = false;
  if (f.root != nullptr) {
    rh.ray.org_x = f.ray.origin[0];
    rh.ray.org_y = f.ray.origin[1];
    rh.ray.org_z = f.ray.origin[2];
    rh.ray.tnear = EmbreeTnear(f.ray.tmin);
    rh.ray.dir_x = f.ray.direction[0];
    rh.ray.dir_y = f.ray.direction[1];
    rh.ray.dir_z = f.ray.direction[2];
    rh.ray.time = f.root->time.Normalized(f.ray.ray_time);
    rh.ray.tfar = f.ray.tmax;
    rh.ray.mask = 0xFFFFFFFFu;  // masks are the engine's (Visible)
    rh.ray.id = 0;
    rh.ray.flags = 0;
    TraceContext c;
    rtcInitIntersectContext(&c.rtc);
    filtered = NeedsFilter(ts, f);
    c.rtc.filter = filtered ? &FilterTriangle : nullptr;
    c.ts = &ts;
    c.frame = &f;
    c.scene = f.root;
    c.scene_handle = ray->handle;
    c.path = nullptr;
    // A lane's ray goes in its block's packet when nothing needs a callback per hit.
    Optix7Thread* lane = ts.lane != nullptr && !filtered && f.root->packets ? &ts : nullptr;
    IntersectClosed(f.root->scene, &c.rtc, rh, f.ray.tmin, filtered, f, lane, f.root);
    RethrowPending(f);
    Resolve(c, rh, filtered);
  }
  Shade(ts, f, rh);
  for (unsigned i = 0; i < num_payload; ++i) *payload[i] = f.payload[i];
}

uint32_t Optix7HitKind(const Optix7Frame& f, Optix7Hit& h) {
  if (h.face_pending) SettleFace(f, h);
  return h.hit_kind;
}

int Optix7ReportIntersection(float hit_t, unsigned int hit_kind, unsigned int num_attributes,
                             const unsigned int* attributes) {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kIntersection), "optixReportIntersection");
  Optix7Frame& f = *ts.ctx.frame;
  RTCRayHit* rh = f.embree;
  // Guide 11.4: a hit outside [tmin, tmax] (tmax: the closest accepted so far) is not reported;
  // nor is a NaN or infinite one (tmax may be infinite), which no program may see.
  if (f.terminated || !(hit_t >= f.ray.tmin && hit_t <= rh->ray.tfar) || !std::isfinite(hit_t)) {
    return 0;
  }
  Optix7Hit& h = *ts.ctx.hit;
  h.t = hit_t;
  h.hit_kind = hit_kind & 0x7Fu;  // the lowest 7 bits are the program's
  h.face_pending = false;
  std::memset(h.attributes, 0, sizeof(h.attributes));
  std::memcpy(h.attributes, attributes, std::min(num_attributes, 8u) * sizeof(uint32_t));
  if (!Accept(ts, f, h, DecideAnyHit(f, h))) return 0;
  rh->ray.tfar = hit_t;
  rh->hit.geomID = f.embree_geometry;
  rh->hit.primID = h.local_primitive;
  rh->hit.instID[0] = f.embree_instance;
  rh->hit.u = rh->hit.v = 0.f;
  rh->hit.Ng_x = rh->hit.Ng_y = rh->hit.Ng_z = 0.f;
  return 1;
}

void Optix7IgnoreIntersection() {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kAnyHit), "optixIgnoreIntersection");
  ts.ignored = true;
  std::longjmp(*ts.any_hit_end, 1);  // any-hit programs run only through RunAnyHit
}

void Optix7TerminateRay() {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kAnyHit), "optixTerminateRay");
  ts.terminate = true;
  std::longjmp(*ts.any_hit_end, 1);
}

}  // namespace tessera::worker
