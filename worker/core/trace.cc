// rtTrace through Embree and the intersection/any-hit protocol (OptiX 3 guide §4.1.4, §4.8).
#include <embree3/rtcore.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <new>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "callbacks.h"
#include "float_steps.h"
#include "interrupt.h"
#include "tessera/accuracy.h"
#include "tessera/rt.h"
#include "thread_state.h"
#include "watertight.h"

namespace tessera::worker {
namespace {

// OptiX 6 RTrayflags (optix_declarations.h values). Tessera has no geometry or instance flags, so
// every geometry runs its any-hit program unless the ray disables them: FORCE_ANYHIT (1 << 1)
// changes nothing, and the two CULL_*_ANYHIT flags cull either everything or nothing.
constexpr unsigned kRayFlagDisableAnyHit = 1u << 0;
constexpr unsigned kRayFlagTerminateOnFirstHit = 1u << 2;
constexpr unsigned kRayFlagDisableClosestHit = 1u << 3;
constexpr unsigned kRayFlagCullBackFacing = 1u << 4;
constexpr unsigned kRayFlagCullFrontFacing = 1u << 5;
constexpr unsigned kRayFlagCullDisabledAnyHit = 1u << 6;
constexpr unsigned kRayFlagCullEnabledAnyHit = 1u << 7;
constexpr unsigned kRayFlagsKnown = (1u << 8) - 1;
constexpr unsigned kRayFlagsRejected =
    kRayFlagCullBackFacing | kRayFlagCullFrontFacing | ~kRayFlagsKnown;

RayData ToObject(const RayData& r, const Mat& inv) {
  RayData o;
  o.ray_type = r.ray_type;
  o.tmin = r.tmin;
  o.tmax = r.tmax;
  for (int i = 0; i < 3; ++i) {
    o.origin[i] = inv[i * 4] * r.origin[0] + inv[i * 4 + 1] * r.origin[1] +
                  inv[i * 4 + 2] * r.origin[2] + inv[i * 4 + 3];
    o.direction[i] = inv[i * 4] * r.direction[0] + inv[i * 4 + 1] * r.direction[1] +
                     inv[i * 4 + 2] * r.direction[2];
  }
  return o;
}

// Embree reads the ray's origin and tnear, and its direction and time, as 16-byte vectors: each is
// stored whole, so that the loads take the stores' data (CopyWords says why).
static_assert(offsetof(RTCRay, tnear) == 12 && offsetof(RTCRay, dir_x) == 16 &&
                  offsetof(RTCRay, time) == 28 && offsetof(RTCRay, tfar) == 32 &&
                  offsetof(RTCRay, flags) == 44,
              "Embree 3's RTCRay layout");
void ToEmbree(const RayData& r, RTCRayHit& rh) {
  StoreVec4(&rh.ray.org_x, Word(r.origin[0]), Word(r.origin[1]), Word(r.origin[2]), Word(r.tmin));
  StoreVec4(&rh.ray.dir_x, Word(r.direction[0]), Word(r.direction[1]), Word(r.direction[2]), 0.f);
  float all_ones, zero = 0.f;
  const unsigned mask = 0xFFFFFFFFu;
  std::memcpy(&all_ones, &mask, sizeof(mask));
  StoreVec4(&rh.ray.tfar, Word(r.tmax), all_ones, zero, zero);  // tfar, mask, id, flags
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

RayData FromEmbree(const RTCRay& e, unsigned ray_type) {
  return RayData{
      {e.org_x, e.org_y, e.org_z}, {e.dir_x, e.dir_y, e.dir_z}, ray_type, e.tnear, e.tfar};
}

void RethrowPending(ThreadState& ts) {
  if (ts.pending) {
    std::exception_ptr p = ts.pending;
    ts.pending = nullptr;
    std::rethrow_exception(p);
  }
}

// Always inline: one or two small copies, on every hit path. Word by word: programs and
// StoreAttributes store attributes a field at a time (CopyWords).
__attribute__((always_inline)) inline void LoadAttributes(const ModuleState& ms,
                                                          const BoundProgram& p,
                                                          const unsigned char* block) {
  for (const auto& a : p.attributes) CopyWords(ms.slots[a.var], block + a.offset, a.size);
}

__attribute__((always_inline)) inline void StoreAttributes(const ModuleState& ms,
                                                           const BoundProgram& p,
                                                           unsigned char* block) {
  for (const auto& a : p.attributes) CopyWords(block + a.offset, ms.slots[a.var], a.size);
}

// Copies between a payload and a payload variable with `copy`. The payload may be one of the
// variables, or lie inside one (a program that traces its own rtPayload variable or a member of
// it): overlapping bytes take memmove.
template <typename Copy>
inline void CopyPayload(void* dst, const void* src, size_t n, Copy copy) {
  auto* d = static_cast<unsigned char*>(dst);
  const auto* s = static_cast<const unsigned char*>(src);
  if (d + n <= s || s + n <= d) {
    copy(d, s, n);
  } else if (d != s) {
    std::memmove(d, s, n);
  }
}

// The payload variable the payload comes back from whatever the program changes: the program's
// only payload variable of the traced size (a module declaring a radiance and a shadow payload of
// different sizes has one of each, and ChoosePayload's rule then always picks it). Null when
// there are several of that size or none: ChoosePayload must compare, and so needs the payload
// as it was before the program ran.
inline const BoundProgram::SlotRef* SolePayloadOfSize(const BoundProgram& p, size_t size) {
  if (p.payload.size() == 1) return p.payload.front().size == size ? &p.payload.front() : nullptr;
  const BoundProgram::SlotRef* sole = nullptr;
  for (const BoundProgram::SlotRef& r : p.payload) {
    if (r.size != size) continue;
    if (sole != nullptr) return nullptr;
    sole = &r;
  }
  return sole;
}

// Keeps the payload as the program receives it (ChoosePayload compares with it, since `dst` may be
// one of the slots itself: a program that traces its own rtPayload variable).
// Returns SolePayloadOfSize, for the ReadPayload after the program.
inline const BoundProgram::SlotRef* KeepPayloadBefore(const BoundProgram& p, Frame& f) {
  const BoundProgram::SlotRef* sole = SolePayloadOfSize(p, f.payload_size);
  if (sole == nullptr) {
    const auto* bytes = static_cast<const unsigned char*>(f.payload);
    f.payload_before.assign(bytes, bytes + f.payload_size);
  }
  return sole;
}

// Copies the payload back from one of several payload variables (a radiance and a shadow payload,
// say): the first of the traced payload's size that the program changed, else the first of that
// size, else the first of another size that the program changed.
__attribute__((noinline)) void ChoosePayload(const ModuleState& ms, const BoundProgram& p,
                                             const Frame& f) {
  const size_t size = f.payload_size;
  const BoundProgram::SlotRef *same_size = nullptr, *changed = nullptr, *changed_other = nullptr;
  for (const BoundProgram::SlotRef& r : p.payload) {
    const size_t n = std::min<size_t>(size, r.size);
    const bool differs = std::memcmp(ms.slots[r.var], f.payload_before.data(), n) != 0;
    if (r.size == size) {
      if (same_size == nullptr) same_size = &r;
      if (differs && changed == nullptr) changed = &r;
    } else if (differs && changed_other == nullptr) {
      changed_other = &r;
    }
  }
  const BoundProgram::SlotRef* chosen = changed ? changed : same_size ? same_size : changed_other;
  if (chosen == nullptr) {
    if (p.payload.empty()) return;
    chosen = &p.payload.front();
  }
  CopyPayload(f.payload, ms.slots[chosen->var], std::min<size_t>(size, chosen->size), CopyWords);
}

// `sole`: what KeepPayloadBefore returned for the program.
inline void ReadPayload(const ModuleState& ms, const BoundProgram& p, const Frame& f,
                        const BoundProgram::SlotRef* sole) {
  if (sole != nullptr) {
    // The program has just written it.
    CopyPayload(f.payload, ms.slots[sole->var], f.payload_size, CopyWords);
  } else {
    ChoosePayload(ms, p, f);
  }
}

// Runs a closest-hit or miss program on the current frame's payload.
// `attributes_in_slots`: the program's module already holds the hit's attributes (its attribute
// program has just stored them from there).
void Shade(ThreadState& ts, const BoundProgram& p, Frame& f, bool attributes_in_slots = false) {
  Enter(ts, p);
  const ModuleState& ms = *ts.current_module;
  WriteRaySlots</*kSettled=*/true>(ms, p.ray, f.ray);
  const BoundProgram::SlotRef* sole = KeepPayloadBefore(p, f);
  // The caller stored its payload before the traversal, so those stores have long reached the
  // cache: a block copy per variable, not CopyWords' word by word (which the copy back after the
  // program needs, its stores being fresh).
  for (const BoundProgram::SlotRef& r : p.payload) {
    CopyPayload(ms.slots[r.var], f.payload, std::min<size_t>(f.payload_size, r.size), CopyBytes);
  }
  if (p.kind == ProgramKind::kClosestHit) {
    WriteSlots<sizeof(float)>(ms, p.distance, &f.hit.t);
    if (!attributes_in_slots) LoadAttributes(ms, p, f.hit.attributes);
  }
  CallProgram(ts, p);
  ReadPayload(*ts.current_module, p, f, sole);
}

void CopyXform(Xform& to, const Xform& from) {
  to.active = from.active;
  if (from.active) {
    to.to_world = from.to_world;
    to.to_object = from.to_object;
  }
}

// Where Embree hit a triangle: barycentrics, and which face (Embree's geometric normal is
// (v1 - v0) x (v2 - v0); the front face winds counter-clockwise seen from the ray, as in OptiX).
inline void SetTriangleHit(Hit& h, const RTCHit& e, const RayData& ray) {
  h.barycentrics[0] = e.u;
  h.barycentrics[1] = e.v;
  h.back_face =
      e.Ng_x * ray.direction[0] + e.Ng_y * ray.direction[1] + e.Ng_z * ray.direction[2] > 0.f;
}

// The transform of instance `inst` of `ctx.scene` below ctx.base, into `out`.
void ComposeInstance(const TraceContext& ctx, unsigned inst, Xform& out) {
  const Xform& x = ctx.scene->instances[inst].xform;
  const Xform& base = *ctx.base;
  if (!base.active) {
    CopyXform(out, x);
  } else if (!x.active) {
    CopyXform(out, base);
  } else {
    out.active = true;
    out.to_world = MulMat(base.to_world, x.to_world);
    out.to_object = MulMat(x.to_object, base.to_object);
  }
}

// Makes the frame's transform that of the instance a callback runs in (args->context->instID[0]):
// programs read it (rtTransform*), and hits keep it.
__attribute__((noinline)) void SelectInstanceSlow(Frame& f, TraceContext& ctx, unsigned inst) {
  ctx.current = inst;
  if (inst == RTC_INVALID_GEOMETRY_ID) {
    CopyXform(f.xform, *ctx.base);
  } else {
    ComposeInstance(ctx, inst, f.xform);
  }
}
inline void SelectInstance(Frame& f, RTCIntersectContext* context) {
  TraceContext& ctx = ContextOf(context);
  if (__builtin_expect(context->instID[0] != ctx.current, 0)) {
    SelectInstanceSlow(f, ctx, context->instID[0]);
  }
}

void IntersectScene(ThreadState& ts, const SceneEntry& scene, const RayData& ray,
                    bool geometry_group);
inline bool ValidRay(const RayData& r);

// A flattened Group of one instance and nothing else: the ray moves into the GeometryGroup's
// space here, as TraverseNode moves it below a Transform, and traces the GeometryGroup's scene,
// sparing Embree's instance level.
__attribute__((noinline)) void IntersectSingleInstance(ThreadState& ts, const SceneEntry& scene,
                                                       const RayData& ray) {
  const FlatInstance& instance = scene.instances.front();
  if (!instance.xform.active) {
    IntersectScene(ts, *instance.scene, ray, true);
    return;
  }
  const RayData object_ray = ToObject(ray, instance.xform.to_object);
  if (!ValidRay(object_ray)) {
    Raise(RT_EXCEPTION_INVALID_RAY, "the ray is invalid in the space of a flattened transform");
    return;  // the exception is disabled: nothing below the transform is hit
  }
  Frame& f = ts.top();
  if (!f.xform.active) {
    CopyXform(f.xform, instance.xform);
    IntersectScene(ts, *instance.scene, object_ray, true);
    f.xform.active = false;  // identity again: readers of an inactive transform skip its matrices
    return;
  }
  const Xform saved = f.xform;
  f.xform.to_world = MulMat(saved.to_world, instance.xform.to_world);
  f.xform.to_object = MulMat(instance.xform.to_object, saved.to_object);
  IntersectScene(ts, *instance.scene, object_ray, true);
  f.xform = saved;
}

// `ray` for Embree in `scene`: robust and watertight scenes take t == tnear, so the ray enters with
// the float after its tmin (the default takes t > tnear).
inline void ToEmbree(const SceneEntry& scene, const RayData& ray, RTCRayHit& rh) {
  ToEmbree(ray, rh);
  if (scene.tnear_inclusive) rh.ray.tnear = NextFloatUp(ray.tmin);
}

// A ray that asks only whether anything is in its way through a scene Embree can answer for alone
// (SceneEntry::occludable): Embree's occlusion query, which stops at the first triangle it finds,
// as Embree's own renderers trace shadow rays. A hit names the scene's `occluder` plan and ends
// the ray; nothing reads more of it, since no closest-hit program runs.
__attribute__((noinline)) void OccludeScene(ThreadState& ts, const SceneEntry& scene,
                                            const RayData& ray) {
  RTCRayHit rh;
  ToEmbree(scene, ray, rh);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded1(scene.scene, &ctx, &rh.ray);
  if (rh.ray.tfar >= 0.f) return;  // Embree sets -inf when something is in the way
  Frame& f = ts.top();
  f.hit.instance = scene.occluder;
  f.hit.geometry = nullptr;
  f.hit.deferred = false;
  f.terminated = true;
}

constexpr unsigned kOcclusionFlags = kRayFlagTerminateOnFirstHit | kRayFlagDisableClosestHit;

// The transform above a scene traced from where there is none.
constexpr Xform kNoTransform{};

__attribute__((always_inline)) inline void TakeHit(ThreadState& ts, const SceneEntry& scene,
                                                   const RayData& ray, bool geometry_group,
                                                   const RTCRayHit& rh, const TraceContext& ctx);

void IntersectScene(ThreadState& ts, const SceneEntry& scene, const RayData& ray,
                    bool geometry_group) {
  if (__builtin_expect(scene.single_instance, 0)) {
    IntersectSingleInstance(ts, scene, ray);
    return;
  }
  Frame& f = ts.top();
  if ((f.flags & kOcclusionFlags) == kOcclusionFlags && scene.occludable &&
      !(scene.any_hit_types & AnyHitBit(ray.ray_type, f.flags & kRayFlagDisableAnyHit)) &&
      !ts.verify_triangles) {
    OccludeScene(ts, scene, ray);
    return;
  }
  RTCRayHit rh;
  ToEmbree(scene, ray, rh);
  TraceContext ctx;
  rtcInitIntersectContext(&ctx.embree);
  if (__builtin_expect(ts.verify_triangles, 0)) ctx.embree.filter = &VerifyTriangles;
  ctx.scene = &scene;
  ctx.any_hit_bit = AnyHitBit(ray.ray_type, f.flags & kRayFlagDisableAnyHit);
  const bool instanced = !scene.instances.empty();
  // The transform above a scene with instances. None (the commonest case: a trace from a program
  // with no Transform above it) needs no copy: a copy would read the frame's transform, whose flag
  // rtTrace has just stored, with wide loads that wait for that store. Storage for one, filled
  // only when there is one: an Xform itself would write its two identity matrices on every trace.
  alignas(Xform) unsigned char base_storage[sizeof(Xform)];
  if (instanced) ctx.base = f.xform.active ? new (base_storage) Xform(f.xform) : &kNoTransform;
  rtcIntersect1(scene.scene, &ctx.embree, &rh);
  if (ctx.current != RTC_INVALID_GEOMETRY_ID) CopyXform(f.xform, *ctx.base);
  RethrowPending(ts);
  TakeHit(ts, scene, ray, geometry_group, rh, ctx);
}

// What IntersectScene makes of Embree's answer `rh` for `ray` in `scene`: a native triangle closer
// than the frame's hit becomes it, its attributes deferred.
__attribute__((always_inline)) inline void TakeHit(ThreadState& ts, const SceneEntry& scene,
                                                   const RayData& ray, bool geometry_group,
                                                   const RTCRayHit& rh, const TraceContext& ctx) {
  Frame& f = ts.top();
  const bool instanced = !scene.instances.empty();
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || f.terminated) return;
  const unsigned inst = rh.hit.instID[0];
  const GeometryInfo* info;
  if (geometry_group) {
    info = scene.geometries[rh.hit.geomID].get();
  } else if (instanced && inst != RTC_INVALID_GEOMETRY_ID) {
    info = scene.instances[inst].scene->geometries[rh.hit.geomID].get();
  } else {
    return;  // a Group's child committed its own hit
  }
  // Embree found it within the ray, clipped to the closest hit so far: t == tmax counts. A
  // geometry whose filter runs programs for this ray type has committed its hit.
  if (!info->triangles || (info->filter && (info->plan->any_hit_types & ctx.any_hit_bit)) ||
      !(rh.ray.tfar <= f.hit.t)) {
    return;
  }
  // Verified, the program has committed the hit already.
  if (ts.verify_triangles && !info->plan->builtin_triangles) return;
  // A native triangle is the closest so far: its attributes come after traversal.
  f.hit.t = rh.ray.tfar;
  f.hit.instance = info->plan;
  f.hit.primitive = rh.hit.primID;
  f.hit.material = 0;
  f.hit.deferred = true;
  // rtTrace stored `ray` word by word; the attribute step after traversal copies the hit's ray
  // as a block (TriangleAttributes<true>), so it is stored in blocks.
  if (geometry_group) {
    StoreRayBlocks(&f.hit.object_ray, ray);
    CopyXform(f.hit.xform, f.xform);
  } else {
    ComposeInstance(ctx, inst, f.hit.xform);
    if (scene.instances[inst].xform.active) {
      f.hit.object_ray = ToObject(ray, scene.instances[inst].xform.to_object);
    } else {
      StoreRayBlocks(&f.hit.object_ray, ray);
    }
  }
  if (f.flags & kRayFlagTerminateOnFirstHit) f.terminated = true;
  // Only built-in triangles tell programs their face; barycentrics place the hit point for
  // tesseraSpawnPoint.
  SetTriangleHit(f.hit, rh.hit, f.hit.object_ray);
  f.hit.geometry = info;
}

// Whether a ray may be traced: what Embree takes (origin and direction within +-1.844e18, its
// FLT_LARGE; it asserts on anything else, which ends the process), 0 <= tmin <= tmax. A NaN fails.
// Decided on the ray's nine words (RayData's layout): |x| <= 1.844e18, a NaN failing, is the
// magnitude's bits compared as an integer.
inline bool ValidRayWords(const uint32_t w[9]) {
  static_assert(sizeof(RayData) == 36 && offsetof(RayData, tmin) == 28 &&
                offsetof(RayData, tmax) == 32);
  constexpr uint32_t kLargeBits = __builtin_bit_cast(uint32_t, 1.844e18f);
  bool ok = true;
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) ok &= (w[i] & 0x7fffffffu) <= kLargeBits;  // origin, direction
  float tmin, tmax;
  std::memcpy(&tmin, &w[7], sizeof(tmin));
  std::memcpy(&tmax, &w[8], sizeof(tmax));
  return ok & (tmin >= 0.f) & (tmin <= tmax);
}
inline bool ValidRay(const RayData& r) {
  uint32_t w[9];
  CopyWords(w, &r, sizeof(w));  // rays here were just built field by field
  return ValidRayWords(w);
}

// rtTrace's copy of the program's ray into its frame, word by word (the program has just written
// it: CopyWords), checked on the words as they pass through registers, so that no check loads
// what was just stored.
inline bool CopyValidRay(RayData& dst, const void* src) {
  const auto* s = static_cast<const unsigned char*>(src);
  auto* d = reinterpret_cast<unsigned char*>(&dst);
  uint32_t w[9];
#pragma GCC unroll 9
  for (int i = 0; i < 9; ++i) {
    std::memcpy(&w[i], s + 4 * i, 4);
    asm("" : "+r"(w[i]));
    std::memcpy(d + 4 * i, &w[i], 4);
  }
  return ValidRayWords(w);
}

void Visit(ThreadState& ts, uint64_t id, const NodeInfo& node, const RayData& ray);

// Intersects one node; `parent_ray` is in the node's parent space. Hits are committed to the top
// frame.
void TraverseNode(ThreadState& ts, uint64_t id, const NodeInfo* node, const RayData& parent_ray) {
  Frame& f = ts.top();
  RayData ray;
  CopyWords(&ray, &parent_ray, sizeof(ray));  // often just stored field by field (FromEmbree)
  ray.tmax = std::min(ray.tmax, f.hit.t);
  if (node == nullptr) {
    throw FatalError{absl::NotFoundError(absl::StrCat("graph node #", id, " is unknown"))};
  }
  switch (node->type) {
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
    case RT_OBJECTTYPE_GROUP:
      if (node->scene == nullptr) {
        if (auto it = ts.plan->node_problems.find(id); it != ts.plan->node_problems.end()) {
          throw FatalError{it->second};
        }
        throw FatalError{absl::FailedPreconditionError(absl::StrCat(
            "node #", id,
            " has no acceleration structure on the device: no variable of object type reaches "
            "it"))};
      }
      IntersectScene(ts, *node->scene, ray, node->type == RT_OBJECTTYPE_GEOMETRY_GROUP);
      return;
    case RT_OBJECTTYPE_TRANSFORM: {
      const TransformRec& t = *node->transform;
      const RayData object_ray = ToObject(ray, t.inverse);
      if (!ValidRay(object_ray)) {  // a degenerate inverse (infinite or huge entries)
        Raise(RT_EXCEPTION_INVALID_RAY,
              absl::StrCat("the ray is invalid in the space of transform #", id));
        return;  // the exception is disabled: nothing below the transform is hit
      }
      Xform saved = f.xform;
      f.xform.to_world = saved.active ? MulMat(saved.to_world, t.matrix) : t.matrix;
      f.xform.to_object = saved.active ? MulMat(t.inverse, saved.to_object) : t.inverse;
      f.xform.active = true;
      TraverseNode(ts, t.child.id, node->child, object_ray);
      f.xform = saved;
      return;
    }
    case RT_OBJECTTYPE_SELECTOR:
      Visit(ts, id, *node, ray);
      return;
    default:
      throw FatalError{absl::InvalidArgumentError(
          absl::StrCat("node #", id, " is not a graph node (type ", node->type, ")"))};
  }
}

// Runs a selector's visit program on `ray` (in the selector's space); its rtIntersectChild calls
// traverse the children it picks (OptiX guide, "Selector Programs").
void Visit(ThreadState& ts, uint64_t id, const NodeInfo& node, const RayData& ray) {
  if (node.visit == nullptr) {
    if (auto it = ts.plan->node_problems.find(id); it != ts.plan->node_problems.end()) {
      throw FatalError{it->second};
    }
    throw FatalError{absl::FailedPreconditionError(
        absl::StrCat("selector #", id, " has no visit program on the device"))};
  }
  Frame& f = ts.top();
  const BoundProgram& v = *node.visit;
  ts.visits.push_back(VisitState{id, &node, ray});
  Enter(ts, v);
  const ModuleState& ms = *ts.current_module;
  WriteRaySlots(ms, v.ray, ray);
  WriteSlots<sizeof(float)>(ms, v.distance, &f.hit.t);
  const BoundProgram::SlotRef* sole = KeepPayloadBefore(v, f);
  WriteSlots(ms, v.payload, f.payload, f.payload_size);
  CallProgram(ts, v);
  ReadPayload(*ts.current_module, v, f, sole);
  ts.visits.pop_back();
}

// Runs the intersection program of `instance` for one primitive. Returns whether it committed.
bool RunIntersection(ThreadState& ts, const InstancePlan* instance, unsigned primitive,
                     const RayData& ray, IntersectMode mode, float forced_t) {
  const BoundProgram& p = *instance->intersection;
  ts.is.instance = instance;
  ts.is.primitive = primitive;
  CopyWords(&ts.is.ray, &ray, sizeof(ray));  // often just stored field by field (FromEmbree)
  ts.is.mode = mode;
  ts.is.forced_t = forced_t;
  ts.is.candidate_ok = false;
  ts.is.committed = false;
  ts.is.reported = false;
  Enter(ts, p);
  WriteRaySlots(*ts.current_module, p.ray, ray);
  WriteSlots<sizeof(float)>(*ts.current_module, p.distance, &ts.top().hit.t);
  CallProgram(ts, p, static_cast<int>(primitive));
  return ts.is.committed;
}

void Commit(ThreadState& ts, Frame& f, const Hit& c, bool terminate) {
  f.hit.t = c.t;
  f.hit.instance = c.instance;
  f.hit.material = c.material;
  f.hit.primitive = c.primitive;
  f.hit.deferred = false;
  f.hit.back_face = c.back_face;
  f.hit.barycentrics[0] = c.barycentrics[0];
  f.hit.barycentrics[1] = c.barycentrics[1];
  f.hit.geometry = c.geometry;
  CopyWords(f.hit.attributes, c.attributes, ts.plan->attribute_bytes);  // just stored by words
  CopyXform(f.hit.xform, f.xform);
  ts.is.committed = true;
  ts.is.ray.tmax = c.t;
  if (terminate || (f.flags & kRayFlagTerminateOnFirstHit)) f.terminated = true;
}

// Runs an any-hit program until it returns or ends itself: rtIgnoreIntersection and
// rtTerminateRay do not return, as in OptiX, so a program's code after them never runs. They
// longjmp back here; what that skips is the program's own frames (any-hit programs cannot trace,
// so no engine state lives there; the callable programs it called are ended first,
// EndAnyHitCalls) and the engine call itself, none with destructors to run.
__attribute__((noinline)) void RunAnyHit(ThreadState& ts, const BoundProgram& ah) {
  std::jmp_buf end;
  struct Restore {
    ThreadState& ts;
    std::jmp_buf* outer;
    size_t outer_calls;
    ~Restore() {  // also when the program throws (rtThrow, a bad call)
      ts.ah_end = outer;
      ts.ah_calls = outer_calls;
    }
  } restore{ts, ts.ah_end, ts.ah_calls};
  ts.ah_end = &end;
  ts.ah_calls = ts.calls.size();
  if (setjmp(end) == 0) {
    CallProgram(ts, ah);
  } else if (!__atomic_load_n(&ah.arguments_checked, __ATOMIC_RELAXED)) {
    VerifyScratch(ts, ah);  // ended by rtIgnoreIntersection or rtTerminateRay
  }
}

// Runs any-hit program `ah` on candidate `c` of the top frame (`object_ray` in the candidate's
// space) and commits the candidate unless the program ignored it. The caller makes its own
// program current again afterwards.
bool OfferToAnyHit(ThreadState& ts, Frame& f, const Hit& c, const BoundProgram& ah,
                   const RayData& object_ray) {
  // The running program (an intersection program) resumes after this: keep its slots if the
  // any-hit program lives in the same module.
  SuspendedSlots& suspended = Suspend(ts, ts.depth);
  ts.object_ray = &object_ray;
  Enter(ts, ah);
  const ModuleState& ms = *ts.current_module;
  WriteRaySlots(ms, ah.ray, object_ray);
  WriteSlots<sizeof(float)>(ms, ah.distance, &c.t);
  const BoundProgram::SlotRef* sole = KeepPayloadBefore(ah, f);
  WriteSlots(ms, ah.payload, f.payload, f.payload_size);
  LoadAttributes(ms, ah, c.attributes);
  ts.ah_ignore = ts.ah_terminate = false;
  RunAnyHit(ts, ah);
  ReadPayload(ms, ah, f, sole);
  const bool accepted = !ts.ah_ignore;
  const bool terminate = ts.ah_terminate;
  Resume(ts, suspended);
  if (accepted) Commit(ts, f, c, terminate);
  return accepted;
}

// The attributes of a hit on built-in triangles (GeometryTriangles) whose material the caller
// has set: zeros, the barycentrics where a program declares attribute rtTriangleBarycentrics,
// then what the attribute program, if any, writes. `object_ray` is the ray in the triangles'
// space.
// Returns the attribute program it ran (null for none), whose module's slots then hold `h`'s
// attributes. kRaySettled: `object_ray` was stored in blocks at the end of traversal
// (StoreRayBlocks), so one block copy reads it, each load taking one store's data; a ray just
// built field by field is read word by word.
template <bool kRaySettled>
const BoundProgram* TriangleAttributes(ThreadState& ts, Hit& h, const RayData& object_ray) {
  const LaunchPlan& plan = *ts.plan;
  const InstancePlan& ip = *h.instance;
  h.deferred = false;
  // A fixed size is two vector stores, not a call; the block holds kMaxBytes.
  constexpr size_t kUsual = 64;
  static_assert(AttributeLayout::kMaxBytes >= kUsual);
  if (plan.attribute_bytes <= kUsual) {
    std::memset(h.attributes, 0, kUsual);
  } else {
    std::memset(h.attributes, 0, plan.attribute_bytes);
  }
  if (plan.barycentrics_offset >= 0) {
    std::memcpy(h.attributes + plan.barycentrics_offset, h.barycentrics, sizeof(h.barycentrics));
  }
  const BoundProgram* p = ip.attribute;
  if (p == nullptr) return nullptr;
  ts.object_ray = &object_ray;
  Enter(ts, *p);
  const ModuleState& ms = *ts.current_module;
  WriteRaySlots<kRaySettled>(ms, p->ray, object_ray);
  WriteSlots<sizeof(float)>(ms, p->distance, &h.t);
  LoadAttributes(ms, *p, h.attributes);
  ts.attribute_hit = &h;
  CallProgram(ts, *p);
  StoreAttributes(ms, *p, h.attributes);
  return p;
}

// A candidate hit on built-in triangles of a geometry with an any-hit program (for some ray
// type). Returns whether Embree should keep it.
bool FilterBuiltin(ThreadState& ts, Frame& f, const GeometryInfo* info, const RTCRay& ray,
                   const RTCHit& hit) {
  const InstancePlan* ip = info->plan;
  const RayData object_ray = FromEmbree(ray, f.ray.ray_type);
  const unsigned material = ip->TriangleMaterial(hit.primID);
  const BoundProgram* ah = nullptr;  // TriangleMaterial checked `material`
  if (f.ray.ray_type < ip->materials[material].size() && !(f.flags & kRayFlagDisableAnyHit)) {
    ah = ip->materials[material][f.ray.ray_type].any_hit;
  }
  // Without an any-hit program the candidate is the closest so far, its attributes computed
  // after traversal; with one, it is offered to the program now.
  Hit& c = ah == nullptr ? f.hit : ts.candidate;
  c.t = ray.tfar;
  c.instance = ip;
  c.primitive = hit.primID;
  SetTriangleHit(c, hit, object_ray);
  c.geometry = info;
  CopyXform(c.xform, f.xform);
  if (ah == nullptr) {
    c.deferred = true;
    CopyWords(&c.object_ray, &object_ray, sizeof(object_ray));
    if (f.flags & kRayFlagTerminateOnFirstHit) f.terminated = true;
    return true;
  }
  c.material = material;
  TriangleAttributes</*kRaySettled=*/false>(ts, c, object_ray);
  return OfferToAnyHit(ts, f, c, *ah, object_ray);
}

template <typename F>
void Guard(ThreadState& ts, F&& f) {
  if (ts.pending) return;
  try {
    f();
  } catch (...) {
    ts.pending = std::current_exception();
  }
}

// An rtTrace that cannot run: too deep, an invalid ray, or a ray type the context lacks. Returns
// whether the ray is traced as a miss: an invalid ray when RT_EXCEPTION_INVALID_RAY is disabled
// (OptiX leaves it undefined; a NaN ray meets nothing on a GPU either). Too deep a trace with
// RT_EXCEPTION_STACK_OVERFLOW disabled does not run at all.
__attribute__((noinline)) bool RejectTrace(ThreadState& ts, const RayData& ray) {
  const LaunchPlan& plan = *ts.plan;
  if (static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit) {
    Raise(RT_EXCEPTION_STACK_OVERFLOW,
          absl::StrCat("rtTrace nested ", ts.depth + 1, " deep: the launch index has used the ",
                       kNativeStackBudget / 1024,
                       " KiB of native stack it may take for nested calls (programs' local "
                       "variables take it too)"));
    return false;
  }
  if (ts.depth >= plan.max_depth) {
    Raise(RT_EXCEPTION_STACK_OVERFLOW,
          absl::StrCat("rtTrace nested ", ts.depth + 1, " deep exceeds the stack size (",
                       plan.max_depth, " levels; 128 bytes each, at most 1024)"));
    return false;
  }
  if (!ValidRay(ray)) {
    Raise(RT_EXCEPTION_INVALID_RAY,
          absl::StrFormat("invalid ray: origin (%g, %g, %g) direction (%g, %g, %g) tmin %g "
                          "tmax %g",
                          ray.origin[0], ray.origin[1], ray.origin[2], ray.direction[0],
                          ray.direction[1], ray.direction[2], ray.tmin, ray.tmax));
    return true;
  }
  throw FatalError{absl::InvalidArgumentError(
      absl::StrCat("rtTrace with ray type ", ray.ray_type, " but the context has ",
                   plan.ray_type_count, " ray types (", ts.current->name, ")"))};
}

// Ray flags Tessera cannot honour stop the launch, naming them, rather than being ignored.
__attribute__((noinline)) void RejectRayFlags(const ThreadState& ts, unsigned flags) {
  std::string names;
  if (flags & kRayFlagCullBackFacing) names += " RT_RAY_FLAG_CULL_BACK_FACING_TRIANGLES";
  if (flags & kRayFlagCullFrontFacing) names += " RT_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES";
  if (flags & ~kRayFlagsKnown) names += absl::StrFormat(" 0x%x", flags & ~kRayFlagsKnown);
  throw FatalError{absl::UnimplementedError(absl::StrCat(
      "rtTrace from ", ts.current->name, " with ray flags Tessera does not support:", names,
      " (face culling needs a filter on every built-in triangle; docs/COMPATIBILITY.md)"))};
}

// The world-space hit point of `h` (a hit of frame `f`) with its error bound. Triangles: from
// the vertices and barycentrics, carried through the hit's transform; otherwise ray.origin +
// t * ray.direction, bounded as three operations on each component (the intersection program's t
// is taken as exact: its own error is the program's).
BoundedPoint HitPoint(const Frame& f, const Hit& h, float normal[3]) {
  const GeometryInfo* g = h.geometry;
  if (g != nullptr && g->vertices != nullptr) {
    const uint32_t* tri = g->indices + 3 * size_t{h.primitive};
    const float* a = g->vertices + 3 * size_t{tri[0]};
    const float* b = g->vertices + 3 * size_t{tri[1]};
    const float* c = g->vertices + 3 * size_t{tri[2]};
    BoundedPoint p = TrianglePoint(a, b, c, h.barycentrics[0], h.barycentrics[1]);
    const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    if (!h.xform.active) {
      for (int k = 0; k < 3; ++k) normal[k] = n[k];
      return p;
    }
    // Normals transform with the inverse transpose: column k of to_object.
    const Mat& inv = h.xform.to_object;
    for (int k = 0; k < 3; ++k) {
      normal[k] = inv[k] * n[0] + inv[4 + k] * n[1] + inv[8 + k] * n[2];
    }
    return TransformPoint(h.xform.to_world.data(), p);
  }
  BoundedPoint p;
  for (int k = 0; k < 3; ++k) {
    const float step = h.t * f.ray.direction[k];
    p.p[k] = f.ray.origin[k] + step;
    p.err[k] = Gamma(3) * (std::fabs(f.ray.origin[k]) + std::fabs(step));
    normal[k] = 0.f;
  }
  return p;
}

// TESSERA_ACCURACY_OFFSET_RAYS: a ray a closest-hit program traces from its hit point (`caller`'s
// hit) starts past the point's error bound instead, with tmin 0. Triangle hits only: an
// intersection program's surface is unknown.
__attribute__((noinline)) void OffsetFromHit(const Frame& caller, RayData& ray) {
  const Hit& h = caller.hit;
  if (h.geometry == nullptr || h.geometry->vertices == nullptr) return;
  float n[3];
  const BoundedPoint p = HitPoint(caller, h, n);
  float scale[3];
  for (int k = 0; k < 3; ++k) {
    scale[k] = std::fabs(caller.ray.origin[k]) + std::fabs(h.t * caller.ray.direction[k]);
  }
  if (!StartsAtHit(p, ray.origin, scale)) return;
  OffsetRayOrigin(p, n, ray.direction, ray.origin);
  ray.tmin = 0.f;
}

// The watertight test found a triangle whose intersection program rejects the hit with its own,
// less exact test (a ray through a vertex or an edge): the program is asked again for the hit's
// attributes with the ray aimed a hair inside the triangle, towards its centroid, so that the
// watertight test keeps deciding what is hit. Returns whether the program reported.
__attribute__((noinline)) bool AttributesInside(ThreadState& ts, Hit& h) {
  const GeometryInfo* g = h.geometry;
  if (g == nullptr || !g->watertight) return false;
  const uint32_t* tri = g->indices + 3 * size_t{h.primitive};
  const float* v[3] = {g->vertices + 3 * size_t{tri[0]}, g->vertices + 3 * size_t{tri[1]},
                       g->vertices + 3 * size_t{tri[2]}};
  for (float step : {1e-6f, 1e-4f, 1e-2f}) {
    const float u = h.barycentrics[0] + (1.f / 3.f - h.barycentrics[0]) * step;
    const float w = h.barycentrics[1] + (1.f / 3.f - h.barycentrics[1]) * step;
    RayData nudged = h.object_ray;
    for (int k = 0; k < 3; ++k) {
      const float target = (1.f - u - w) * v[0][k] + u * v[1][k] + w * v[2][k];
      // Scaled so that the program's t comes out near the hit's (which the hit keeps).
      nudged.direction[k] =
          h.t > 0.f ? (target - nudged.origin[k]) / h.t : h.object_ray.direction[k];
    }
    if (RunIntersection(ts, h.instance, h.primitive, nudged, IntersectMode::kDeferred, h.t)) {
      return true;
    }
  }
  return false;
}

// Traverses the scene `top` (node `node`) with `ray`, committing hits to the top frame.
inline void Traverse(ThreadState& ts, unsigned long long node, const NodeInfo* top,
                     const RayData& ray) {
  if (top->scene != nullptr) {  // a Group or GeometryGroup: no transform to apply
    IntersectScene(ts, *top->scene, ray, top->type == RT_OBJECTTYPE_GEOMETRY_GROUP);
  } else {
    TraverseNode(ts, node, top, ray);
  }
}

// Traces the top frame's ray again from the start, with every candidate on a native triangle that
// has an intersection program put to that program before Embree takes it (VerifyTriangles).
__attribute__((noinline)) void TraverseVerified(ThreadState& ts, unsigned long long node,
                                                const NodeInfo* top, const RayData& ray) {
  Frame& f = ts.top();
  f.hit.t = ray.tmax;
  f.hit.instance = nullptr;
  f.hit.geometry = nullptr;
  f.terminated = false;
  f.xform.active = false;
  struct Verifying {
    ThreadState& ts;
    ~Verifying() { ts.verify_triangles = false; }
  } verifying{ts};
  ts.verify_triangles = true;
  Traverse(ts, node, top, ray);
}

// A ray generation program's first rtTrace while its lane collects (packet_trace.h): the ray is
// kept for the block's packet when the packet can answer it (a ray of the launch's own program,
// no flags, a scene Embree traverses without the engine), and the run ends here either way.
[[noreturn]] __attribute__((noinline)) void CollectTrace(ThreadState& ts, unsigned long long node,
                                                         const void* ray_ptr, unsigned mask,
                                                         unsigned flags) {
  PacketLane& lane = *ts.packet.collecting;
  const LaunchPlan& plan = *ts.plan;
  lane.scene = nullptr;
  if (ts.depth == 0 && flags == 0 && (mask & 0xFFu) != 0 && plan.max_depth > 0 &&
      CopyValidRay(lane.ray, ray_ptr) && lane.ray.ray_type < plan.ray_type_count) {
    if (node != ts.last_node_id || ts.last_node == nullptr) {  // as Trace keeps it
      ts.last_node = plan.Node(node);
      ts.last_node_id = node;
    }
    const NodeInfo* top = ts.last_node;
    if (top != nullptr && top->scene != nullptr && top->scene->packets) {
      // A single flattened instance (without a transform, or it would not take packets) is
      // traced as its GeometryGroup's scene, as IntersectSingleInstance does.
      lane.scene = top->scene->single_instance ? top->scene->instances.front().scene : top->scene;
      ToEmbree(*lane.scene, lane.ray, lane.hit);
    }
  }
  __builtin_longjmp(ts.packet.jump, 1);
}

// The first trace of a lane whose ray its block's packet traced: the packet's hit is taken as
// rtcIntersect1's would be, if this is still that ray (the same bits, traced the same way).
__attribute__((noinline)) void TraverseReplayed(ThreadState& ts, unsigned long long node,
                                                const NodeInfo* top, const RayData& ray) {
  const PacketLane& lane = *ts.packet.replay;
  ts.packet.replay = nullptr;
  const SceneEntry* scene = top->scene;
  bool geometry_group = top->type == RT_OBJECTTYPE_GEOMETRY_GROUP;
  if (scene != nullptr && scene->single_instance) {
    scene = scene->instances.front().scene;
    geometry_group = true;
  }
  Frame& f = ts.top();
  if (ts.depth != 1 || f.flags != 0 || scene != lane.scene ||
      std::memcmp(&ray, &lane.ray, sizeof(RayData)) != 0) {
    Traverse(ts, node, top, ray);
    return;
  }
  ++ts.packet_answers;
  TraceContext ctx;
  ctx.scene = scene;
  ctx.any_hit_bit = AnyHitBit(ray.ray_type, false);
  ctx.base = &kNoTransform;  // a launch's own trace has no transform above it
  TakeHit(ts, *scene, ray, geometry_group, lane.hit, ctx);
}

// rtTrace with an OptiX 6 visibility mask and RTrayflags. Geometry has the default mask 0xFF (there
// is no rtGeometryGroupSetVisibilityMask), so a mask with none of its low 8 bits set hits nothing.
// A ray without a time of its own (has_time 0) takes its caller's: the traced ray's, or 0 in a
// launch's own programs.
__attribute__((always_inline)) inline void Trace(unsigned long long node, const void* ray_ptr,
                                                 void* payload, size_t payload_size, unsigned mask,
                                                 unsigned flags, bool has_time, float time) {
  // A program looping on rtTrace spends its time in the engine and Embree, where an interrupt
  // only leaves a request (interrupt.h).
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(
      ts,
      Bit(ProgramKind::kRayGeneration) | Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kMiss),
      "rtTrace");
  if (__builtin_expect(ts.packet.collecting != nullptr, 0)) {
    CollectTrace(ts, node, ray_ptr, mask, flags);
  }
  ++ts.traces;
  const LaunchPlan& plan = *ts.plan;
  // The ray goes straight into the frame it is traced in: frames has max_depth + 1 entries, so
  // frames[depth] exists even for a trace that RejectTrace refuses, and nothing writes it before
  // the frame is pushed.
  Frame& f = ts.frames[ts.depth];
  RayData& ray = f.ray;
  const bool valid = CopyValidRay(ray, ray_ptr);
  bool as_miss = false;
  if (__builtin_expect(ts.depth >= plan.max_depth || !valid ||
                           ray.ray_type >= plan.ray_type_count ||
                           static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit,
                       0)) {
    // Raises, throws, or returns when the exception is disabled.
    if (!RejectTrace(ts, ray)) return;
    as_miss = true;
  } else if (__builtin_expect(plan.accuracy_flags & TESSERA_ACCURACY_OFFSET_RAYS, 0) &&
             ts.kind == ProgramKind::kClosestHit) {
    OffsetFromHit(ts.top(), ray);
  }
  if (__builtin_expect(node != ts.last_node_id || ts.last_node == nullptr, 0)) {
    ts.last_node = plan.Node(node);
    ts.last_node_id = node;
    if (ts.last_node == nullptr && node == 0) {
      throw FatalError{absl::InvalidArgumentError(absl::StrCat(
          "rtTrace on an rtObject that no scope sets (", ts.current->name,
          "): set the rtObject variable it traces with rtVariableSetObject to a group, geometry "
          "group, transform or selector"))};
    }
    if (ts.last_node == nullptr) {
      throw FatalError{absl::InvalidArgumentError(absl::StrCat(
          "rtTrace on object #", node, " which is not a graph node (", ts.current->name, ")"))};
    }
  }
  const NodeInfo* top = ts.last_node;
  if (__builtin_expect(flags & kRayFlagsRejected, 0)) RejectRayFlags(ts, flags);
  // Culling every geometry (no visible mask bit; any-hit culled the way the flags ask) leaves the
  // miss program.
  const bool any_hit_disabled = flags & kRayFlagDisableAnyHit;
  const bool cull_all = as_miss || (mask & 0xFFu) == 0 ||
                        ((flags & kRayFlagCullDisabledAnyHit) && any_hit_disabled) ||
                        ((flags & kRayFlagCullEnabledAnyHit) && !any_hit_disabled);

  const BoundProgram* caller = ts.current;
  SuspendedSlots& suspended = Suspend(ts, ts.depth);
  if (!has_time) time = ts.depth > 0 ? ts.frames[ts.depth - 1].time : 0.f;
  ++ts.depth;
  f.payload = payload;
  f.payload_size = payload_size;
  f.hit.t = ray.tmax;
  f.hit.instance = nullptr;
  f.hit.geometry = nullptr;
  f.terminated = false;
  f.flags = flags;
  f.time = time;
  f.xform.active = false;
  if (__builtin_expect(cull_all, 0)) {
    // Nothing to traverse: the ray misses.
  } else if (__builtin_expect(ts.packet.replay != nullptr, 0)) {
    TraverseReplayed(ts, node, top, ray);
  } else {
    Traverse(ts, node, top, ray);
  }

  if (f.hit.instance != nullptr && f.hit.deferred && !f.hit.instance->builtin_triangles &&
      !RunIntersection(ts, f.hit.instance, f.hit.primitive, f.hit.object_ray,
                       IntersectMode::kDeferred, f.hit.t) &&
      !AttributesInside(ts, f.hit)) {
    // The intersection program did not report the triangle Embree found (its own test rejected
    // it): traversal goes on past it, as the program's hit would in OptiX. The ray is traced
    // again with every triangle candidate put to the program first.
    TraverseVerified(ts, node, top, ray);
  }
  if (f.hit.instance != nullptr) {
    const bool builtin_pending = f.hit.deferred && f.hit.instance->builtin_triangles;
    if (builtin_pending) f.hit.material = f.hit.instance->TriangleMaterial(f.hit.primitive);
    const auto& groups = f.hit.instance->materials;
    if (!(flags & kRayFlagDisableClosestHit) && f.hit.material < groups.size() &&
        ray.ray_type < groups[f.hit.material].size()) {
      if (const BoundProgram* ch = groups[f.hit.material][ray.ray_type].closest_hit) {
        // Built-in triangles' attributes are for the closest-hit program alone: a ray that runs
        // none (a shadow ray with DISABLE_CLOSESTHIT, a ray type without one) skips the attribute
        // program, as OptiX runs it only where its results are read.
        // A closest-hit program of the attribute program's module reads the attributes where
        // that program wrote them: the same variables, placed in the plan's one layout, and
        // nothing runs in the module in between (Enter clears attributes only for a new launch
        // index, which the attribute program's Enter has already seen).
        bool in_slots = false;
        if (builtin_pending) {
          const BoundProgram* attribute =
              TriangleAttributes</*kRaySettled=*/true>(ts, f.hit, f.hit.object_ray);
          in_slots = attribute != nullptr && attribute->module_index == ch->module_index &&
                     !ch->attributes_alias;
        }
        Shade(ts, *ch, f, in_slots);
      }
    }
  } else if (ray.ray_type < plan.miss.size() && plan.miss[ray.ray_type] != nullptr) {
    Shade(ts, *plan.miss[ray.ray_type], f);
  }
  --ts.depth;
  if (__builtin_expect(suspended.saved && suspended.reads_per_call, 0)) {
    // The caller's values come back, but the payload may be one of them (a program that traces
    // its own rtPayload variable): it keeps what this trace made of it.
    ts.resume_payload.assign(static_cast<unsigned char*>(payload),
                             static_cast<unsigned char*>(payload) + payload_size);
    Resume(ts, suspended);
    std::memcpy(payload, ts.resume_payload.data(), payload_size);
  } else {
    Resume(ts, suspended);
  }
  ReturnTo(ts, *caller, *suspended.module);
  // A ray generation program gets back no per-call values (Resume), and its time may have been
  // overwritten by a program of its module that this ray ran.
  if (__builtin_expect(!caller->time.empty(), 0)) WriteTime(ts, *suspended.module, *caller);
}

}  // namespace

void RtTrace(unsigned long long node, const void* ray_ptr, void* payload, size_t payload_size) {
  Trace(node, ray_ptr, payload, payload_size, 0xFFu, 0u, false, 0.f);
}

void RtTraceWithFlags(unsigned long long node, const void* ray_ptr, void* payload,
                      size_t payload_size, unsigned mask, unsigned flags, int has_time,
                      float time) {
  Trace(node, ray_ptr, payload, payload_size, mask, flags, has_time != 0, time);
}

int RtPotentialIntersection(float t) {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kIntersection), "rtPotentialIntersection");
  IntersectState& is = ts.is;
  if (is.mode == IntersectMode::kSearch) {
    is.candidate_ok = t > is.ray.tmin && t < is.ray.tmax && !ts.top().terminated;
    is.candidate_t = t;
  } else {
    // Embree already chose this primitive at forced_t; the program only reports attributes (its
    // own t is Embree's). A program that tests several primitives in one call, or reports twice,
    // must not have another report replace the one for Embree's hit: after traversal the report
    // nearest Embree's t wins, during it (any-hit programs) only the first counts.
    const bool finite = std::isfinite(t);
    if (is.mode == IntersectMode::kDeferred) {
      is.candidate_error = std::fabs(t - is.forced_t);
      is.candidate_ok = finite && (!is.reported || is.candidate_error < is.reported_error);
    } else {
      is.candidate_ok = finite && !is.reported && !ts.top().terminated;
    }
    is.candidate_t = is.forced_t;
  }
  return is.candidate_ok ? 1 : 0;
}

int RtReportIntersection(unsigned material) {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kIntersection), "rtReportIntersection");
  IntersectState& is = ts.is;
  if (!is.candidate_ok) return 0;
  is.candidate_ok = false;
  const InstancePlan* inst = is.instance;
  if (material >= inst->materials.size()) {
    throw FatalError{absl::OutOfRangeError(absl::StrCat(
        "rtReportIntersection(", material, ") from ", ts.current->name, ": geometry instance #",
        inst->id, " has ", inst->materials.size(), " materials"))};
  }
  Frame& f = ts.top();
  const BoundProgram& isp = *ts.current;
  ModuleState& is_module = *ts.current_module;
  if (is.mode != IntersectMode::kSearch) {
    is.reported = true;
    is.reported_error = is.candidate_error;
  }
  if (is.mode == IntersectMode::kDeferred) {
    // The closest hit is known; record what the program reports for it.
    f.hit.material = material;
    StoreAttributes(is_module, isp, f.hit.attributes);
    is.committed = true;
    return 1;
  }
  Hit& c = ts.candidate;
  c.t = is.candidate_t;
  c.instance = inst;
  c.material = material;
  c.primitive = is.primitive;
  c.geometry = is.geometry;
  c.barycentrics[0] = is.barycentrics[0];
  c.barycentrics[1] = is.barycentrics[1];
  StoreAttributes(is_module, isp, c.attributes);

  const std::vector<HitGroup>& types = inst->materials[material];
  const BoundProgram* ah = f.ray.ray_type < types.size() && !(f.flags & kRayFlagDisableAnyHit)
                               ? types[f.ray.ray_type].any_hit
                               : nullptr;
  if (ah == nullptr) {
    Commit(ts, f, c, false);
    return 1;
  }
  const bool accepted = OfferToAnyHit(ts, f, c, *ah, is.ray);
  ReturnTo(ts, isp, is_module);
  return accepted ? 1 : 0;
}

void RtIgnoreIntersection() {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kAnyHit), "rtIgnoreIntersection");
  ts.ah_ignore = true;
  EndAnyHitCalls(ts);
  std::longjmp(*ts.ah_end, 1);  // any-hit programs run only through RunAnyHit
}

// In a miss program there is no traversal left to end: the call returns and does nothing.
void RtTerminateRay() {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss), "rtTerminateRay");
  if (ts.kind != ProgramKind::kAnyHit) return;
  ts.ah_terminate = true;
  EndAnyHitCalls(ts);
  std::longjmp(*ts.ah_end, 1);
}

// Traverses child `index` of the selector whose visit program runs, with the ray clipped to the
// closest hit so far; the visit program then sees the payload and distance as the child left
// them.
void RtIntersectChild(unsigned index) {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kVisit), "rtIntersectChild");
  const VisitState visit = ts.visits.back();  // a copy: nested visits push more
  const NodeInfo& selector = *visit.node;
  if (index >= selector.children.size()) {
    throw FatalError{absl::OutOfRangeError(
        absl::StrCat("rtIntersectChild(", index, ") from ", ts.current->name, ": selector #",
                     visit.id, " has ", selector.children.size(), " children"))};
  }
  Frame& f = ts.top();
  const BoundProgram& v = *ts.current;
  ModuleState& ms = *ts.current_module;
  // Any-hit programs below see what the visit program wrote.
  ReadPayload(ms, v, f, SolePayloadOfSize(v, f.payload_size));
  const size_t level = ts.visits.size() - 1;
  while (ts.visit_suspended.size() <= level) ts.visit_suspended.emplace_back();
  SuspendedSlots& s = SuspendInto(ts, ts.visit_suspended[level]);
  RayData ray;
  CopyWords(&ray, &visit.ray, sizeof(ray));
  ray.tmax = std::min(ray.tmax, f.hit.t);
  TraverseNode(ts, selector.children[index].id, selector.child_nodes[index], ray);
  Resume(ts, s);
  ReturnTo(ts, v, ms);
  WriteSlots<sizeof(float)>(ms, v.distance, &f.hit.t);
  KeepPayloadBefore(v, f);
  WriteSlots(ms, v.payload, f.payload, f.payload_size);
}

namespace {
// The hit the running program asks about (its kind was checked to be one of kHitPrograms).
const Hit& CurrentHit(ThreadState& ts) { return *HitOf(ts); }
constexpr unsigned kHitPrograms =
    Bit(ProgramKind::kAttribute) | Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kClosestHit);
}  // namespace

unsigned RtGetPrimitiveIndex() {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, kHitPrograms | Bit(ProgramKind::kIntersection), "rtGetPrimitiveIndex");
  if (ts.kind == ProgramKind::kIntersection) return ts.is.primitive;
  const Hit& h = CurrentHit(ts);
  return h.primitive + (h.instance->builtin_triangles ? h.instance->primitive_index_offset : 0);
}

unsigned RtTriangleHit() {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, kHitPrograms, "rtIsTriangleHit*");
  const Hit& h = CurrentHit(ts);
  if (!h.instance->builtin_triangles) return 0;
  return h.back_face ? 2 : 1;
}

void RtTriangleBarycentrics(float* uv) {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kAttribute), "rtGetTriangleBarycentrics");
  uv[0] = ts.attribute_hit->barycentrics[0];
  uv[1] = ts.attribute_hit->barycentrics[1];
}

void IntersectUserGeometry(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  ThreadState& ts = TS();
  Guard(ts, [&] {
    Frame& f = ts.top();
    if (f.terminated) return;
    auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    SelectInstance(f, args->context);
    RayData ray = FromEmbree(rh->ray, f.ray.ray_type);  // in the instance's space
    ray.tmax = std::min(ray.tmax, f.hit.t);
    ts.is.geometry = nullptr;
    if (RunIntersection(ts, info->plan, args->primID, ray, IntersectMode::kSearch, 0.f)) {
      rh->ray.tfar = f.hit.t;
      rh->hit.geomID = args->geomID;
      rh->hit.primID = args->primID;
      rh->hit.instID[0] = args->context->instID[0];
    }
  });
}

void IntersectWatertight(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  ThreadState& ts = TS();
  auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  const float key[6] = {rh->ray.org_x, rh->ray.org_y, rh->ray.org_z,
                        rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z};
  if (std::memcmp(key, ts.watertight_key, sizeof(key)) != 0) {
    ts.watertight_ray = PrepareWatertight(key, key + 3);
    std::memcpy(ts.watertight_key, key, sizeof(key));
  }
  const uint32_t* tri = info->indices + 3 * size_t{args->primID};
  TriangleHit h;
  if (!WatertightHit(ts.watertight_ray, info->vertices + 3 * size_t{tri[0]},
                     info->vertices + 3 * size_t{tri[1]}, info->vertices + 3 * size_t{tri[2]},
                     rh->ray.tnear, rh->ray.tfar, &h)) {
    return;
  }
  RTCHit hit;
  hit.Ng_x = h.ng[0];
  hit.Ng_y = h.ng[1];
  hit.Ng_z = h.ng[2];
  hit.u = h.u;
  hit.v = h.v;
  hit.primID = args->primID;
  hit.geomID = args->geomID;
  hit.instID[0] = args->context->instID[0];
  // Embree's filters decide, as for a native triangle's candidate: the geometry's (FilterTriangles,
  // installed where an any-hit program exists) and the context's (VerifyTriangles, when traced
  // again).
  if (info->filter || ts.verify_triangles) {
    RTCRay candidate = rh->ray;
    candidate.tfar = h.t;
    int valid = -1;
    RTCFilterFunctionNArguments filter{&valid,
                                       args->geometryUserPtr,
                                       args->context,
                                       reinterpret_cast<RTCRayN*>(&candidate),
                                       reinterpret_cast<RTCHitN*>(&hit),
                                       1};
    rtcFilterIntersection(args, &filter);
    if (valid == 0) return;
  }
  rh->ray.tfar = h.t;
  rh->hit = hit;
}

void IntersectChild(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  ThreadState& ts = TS();
  Guard(ts, [&] {
    Frame& f = ts.top();
    if (f.terminated) return;
    auto* info = static_cast<const ChildInfo*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    SelectInstance(f, args->context);  // the transform above the Group's scene
    float before = f.hit.t;
    TraverseNode(ts, info->child.id, info->node, FromEmbree(rh->ray, f.ray.ray_type));
    if (f.hit.t < before) {
      rh->ray.tfar = f.hit.t;
      rh->hit.geomID = args->geomID;
      rh->hit.primID = 0;
      rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }
  });
}

namespace {
// A triangle candidate put to its programs: the intersection program (or, for built-in triangles,
// the attribute program) and the any-hit program of the ray type, if any.
void FilterCandidate(const RTCFilterFunctionNArguments* args) {
  ThreadState& ts = TS();
  bool accepted = false;
  Guard(ts, [&] {
    Frame& f = ts.top();
    if (f.terminated) return;
    SelectInstance(f, args->context);
    auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    auto* hit = reinterpret_cast<RTCHit*>(args->hit);
    if (info->plan->builtin_triangles) {
      accepted = FilterBuiltin(ts, f, info, *ray, *hit);
      return;
    }
    RayData r = FromEmbree(*ray, f.ray.ray_type);
    float t = ray->tfar;
    r.tmax = f.hit.t;
    ts.is.geometry = info;
    ts.is.barycentrics[0] = hit->u;
    ts.is.barycentrics[1] = hit->v;
    accepted = RunIntersection(ts, info->plan, hit->primID, r, IntersectMode::kFiltered, t);
  });
  if (!accepted) args->valid[0] = 0;
}
}  // namespace

void FilterTriangles(const RTCFilterFunctionNArguments* args) {
  if (!args->valid[0]) return;
  // A ray type without an any-hit program on this geometry: Embree keeps the candidate, as it
  // would without a filter, and IntersectScene takes the closest after traversal. This test is
  // all such a ray pays for the filter.
  auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
  if (!(info->plan->any_hit_types & ContextOf(args->context).any_hit_bit)) return;
  FilterCandidate(args);
}

void RtSpawnPoint(const float* dir, float* origin) {
  InterruptPoint();
  ThreadState& ts = TS();
  CheckCall(ts, Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kClosestHit), "tesseraSpawnPoint");
  const Hit& h = CurrentHit(ts);
  // An untransformed triangle's point and normal depend on the hit alone: prepared once for the
  // rays a program spawns from it.
  ThreadState::SpawnCache& cache = ts.spawn_cache;
  const bool cacheable =
      h.geometry != nullptr && h.geometry->vertices != nullptr && !h.xform.active;
  uint32_t bary[2];
  std::memcpy(bary, h.barycentrics, sizeof(bary));
  if (cacheable && cache.index_serial == ts.index_serial && cache.geometry == h.geometry &&
      cache.primitive == h.primitive && cache.barycentric_bits[0] == bary[0] &&
      cache.barycentric_bits[1] == bary[1]) {
    SpawnToward(cache.base, dir, origin);
    return;
  }
  float n[3];
  const BoundedPoint p = HitPoint(ts.top(), h, n);
  if (n[0] == 0.f && n[1] == 0.f && n[2] == 0.f) {
    // No surface normal (an intersection program's hit, a degenerate triangle): move along `dir`
    // itself.
    OffsetRayOrigin(p, dir, dir, origin);
    return;
  }
  const SpawnBase base = PrepareSpawn(p, n);
  if (cacheable) {
    cache.index_serial = ts.index_serial;
    cache.geometry = h.geometry;
    cache.primitive = h.primitive;
    cache.barycentric_bits[0] = bary[0];
    cache.barycentric_bits[1] = bary[1];
    cache.base = base;
  }
  SpawnToward(base, dir, origin);
}

void VerifyTriangles(const RTCFilterFunctionNArguments* args) {
  auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
  // Candidates with their own filter, built-in triangles and intersection programs' hits need no
  // second look.
  if (info == nullptr || !info->triangles || info->plan->builtin_triangles) return;
  if (info->filter && (info->plan->any_hit_types & ContextOf(args->context).any_hit_bit)) return;
  FilterCandidate(args);
}

}  // namespace tessera::worker
