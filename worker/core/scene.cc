// Embree scenes for GeometryGroups and Groups. Groups hold the GeometryGroups below chains of
// Groups and Transforms as Embree instances with the chain's composed transform (flattened), and
// other children as one-primitive user geometries whose callback traverses the child, so graphs
// deeper than Debian Embree's single instance level work; GeometryGroups use native triangles
// where the acceleration names vertex and index buffers and user geometry (intersection
// programs) otherwise.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <tuple>

#include "absl/hash/hash.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "callbacks.h"
#include "interrupt.h"
#include "plan.h"
#include "runtime.h"
#include "scene_triangles.h"
#include "tessera/accuracy.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"
#include "watertight.h"

namespace tessera::worker {
namespace {

constexpr int kMaxGraphDepth = kMaxGraphLevels;

using Box = std::array<float, 6>;

Box EmptyBox() {
  float inf = INFINITY;
  return {inf, inf, inf, -inf, -inf, -inf};
}

void Grow(Box& b, float x, float y, float z) {
  b[0] = std::min(b[0], x);
  b[1] = std::min(b[1], y);
  b[2] = std::min(b[2], z);
  b[3] = std::max(b[3], x);
  b[4] = std::max(b[4], y);
  b[5] = std::max(b[5], z);
}

bool IsEmpty(const Box& b) { return !(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5]); }

// Embree drops a primitive whose bounds reach past +-1.844e18 (its FLT_LARGE) from the build
// without a word, so a conservative box such as +-FLT_MAX around an "infinite" plane would never
// be hit. Bounds are clamped just inside that range instead: rays cannot start beyond it
// (ValidRay in trace.cc), so only geometry wholly beyond it is lost (docs/COMPATIBILITY.md).
constexpr float kMaxBoundsExtent = 1.8e18f;
void ClampToEmbreeRange(float* b) {
  for (int k = 0; k < 6; ++k) b[k] = std::clamp(b[k], -kMaxBoundsExtent, kMaxBoundsExtent);
}

Box TransformBox(const std::array<float, 16>& m, const Box& b) {
  Box out = EmptyBox();
  if (IsEmpty(b)) return out;
  for (int c = 0; c < 8; ++c) {
    float p[3] = {b[(c & 1) ? 3 : 0], b[(c & 2) ? 4 : 1], b[(c & 4) ? 5 : 2]};
    float q[4];
    for (int r = 0; r < 4; ++r)
      q[r] = m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3];
    float w = q[3] != 0.f ? q[3] : 1.f;
    Grow(out, q[0] / w, q[1] / w, q[2] / w);
  }
  return out;
}

Box SceneBounds(RTCScene scene) {
  RTCBounds b;
  rtcGetSceneBounds(scene, &b);
  return {b.lower_x, b.lower_y, b.lower_z, b.upper_x, b.upper_y, b.upper_z};
}

void BoundsFromArray(const RTCBoundsFunctionArguments* args) {
  const auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
  const float* b = &info->bounds[size_t{args->primID} * 6];
  args->bounds_o->lower_x = b[0];
  args->bounds_o->lower_y = b[1];
  args->bounds_o->lower_z = b[2];
  args->bounds_o->upper_x = b[3];
  args->bounds_o->upper_y = b[4];
  args->bounds_o->upper_z = b[5];
}

void ChildBounds(const RTCBoundsFunctionArguments* args) {
  const auto* info = static_cast<const ChildInfo*>(args->geometryUserPtr);
  const Box& b = info->bounds;
  *args->bounds_o = RTCBounds{b[0], b[1], b[2], 0.f, b[3], b[4], b[5], 0.f};
}

}  // namespace

namespace {

// An acceleration property that is "1" or "0" (unset: false).
absl::StatusOr<bool> FlagProperty(uint64_t accel_id, const AccelRec& a, const std::string& name) {
  auto it = a.properties.find(name);
  if (it == a.properties.end() || it->second == "0") return false;
  if (it->second == "1") return true;
  return absl::InvalidArgumentError(absl::StrCat("acceleration #", accel_id, ": property ", name,
                                                 " is '", it->second, "', not \"0\" or \"1\""));
}

}  // namespace

RTCSceneFlags SceneOptions::flags() const {
  int f = RTC_SCENE_FLAG_NONE;
  if (refit) f |= RTC_SCENE_FLAG_DYNAMIC;
  if (robust || watertight) f |= RTC_SCENE_FLAG_ROBUST;
  if (compact) f |= RTC_SCENE_FLAG_COMPACT;
  return static_cast<RTCSceneFlags>(f);
}

// OptiX 3 builder names and properties (000_e8b1a455cb84dad5.txt §3.6) → Embree
// (docs/accuracy.md, "Acceleration knobs").
absl::StatusOr<SceneOptions> OptionsOf(uint64_t accel_id, const AccelRec& a, bool has_filter,
                                       uint32_t accuracy_flags) {
  SceneOptions o;
  const std::string& b = a.builder;
  // HIGH uses spatial splits, which can report one primitive twice to a filter callback: any-hit
  // programs must see each candidate once. LOW (Morton codes) builds the same hierarchy whatever
  // the thread count (scene_test.cc), so ties in t resolve alike on every device set.
  const RTCBuildQuality high = has_filter ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
  if (b == "Sbvh" || b == "TriangleKdTree" || b == "Trbvh") {
    o.quality = high;
  } else if (b == "Lbvh" || b == "MedianBvh" || b == "NoAccel") {
    o.quality = RTC_BUILD_QUALITY_LOW;
  }
  const std::string refine = Property(a, "refine", "0");
  int passes = 0;
  if (!absl::SimpleAtoi(refine, &passes) || passes < 0) {
    return absl::InvalidArgumentError(absl::StrCat(
        "acceleration #", accel_id, ": property refine is '", refine, "', not a count of passes"));
  }
  if (passes > 0) {  // refinement improves a fast build: one quality step up
    o.quality = o.quality == RTC_BUILD_QUALITY_LOW ? RTC_BUILD_QUALITY_MEDIUM : high;
  }
  auto refit = a.properties.find("refit");
  o.refit = refit != a.properties.end() && refit->second != "0";
  for (const auto& [name, flag, field] :
       {std::tuple{"robust", TESSERA_ACCURACY_ROBUST, &o.robust},
        std::tuple{"watertight", TESSERA_ACCURACY_WATERTIGHT, &o.watertight},
        std::tuple{"compact", TESSERA_ACCURACY_COMPACT, &o.compact}}) {
    absl::StatusOr<bool> set = FlagProperty(accel_id, a, name);
    if (!set.ok()) return set.status();
    *field = *set || (accuracy_flags & flag) != 0;
  }
  o.compact |= b == "BvhCompact";
  return o;
}

SceneEntry::~SceneEntry() {
  if (scene != nullptr) rtcReleaseScene(scene);
}

bool SceneCache::KeepBuilding(void* cache, double /*progress*/) {
  return !static_cast<const SceneCache*>(cache)->Cancelled();
}

absl::Status SceneCache::Commit(RTCScene scene, const std::string& what) {
  rtcSetSceneProgressMonitorFunction(scene, &SceneCache::KeepBuilding, this);
  rtcCommitScene(scene);
  const RTCError err = rtcGetDeviceError(device_);
  if (err == RTC_ERROR_CANCELLED || Cancelled()) {
    return absl::CancelledError(absl::StrCat("launch cancelled while building ", what));
  }
  if (err != RTC_ERROR_NONE) {
    return absl::InternalError(absl::StrCat("Embree could not build ", what, " (error ", err, ")"));
  }
  return absl::OkStatus();
}

absl::Status SceneCache::Update(LaunchPlan& plan, const std::vector<uint64_t>& roots,
                                const std::atomic<bool>* cancel) {
  cancel_ = cancel;
  struct Reset {
    const std::atomic<bool>*& cancel;
    ~Reset() { cancel = nullptr; }
  } reset{cancel_};
  // Scenes of nodes the replica no longer holds (destroyed GeometryGroups and Groups): ids are
  // never reused, so nothing can find them again, and each holds an Embree BVH and a copy of its
  // primitives' bounds. No plan can still point into them: every plan that did was made for an
  // earlier replica generation and is gone before a new one is made.
  for (auto it = entries_.begin(); it != entries_.end();) {
    const Replica& r = *plan.replica;
    if (r.Find(r.geometry_groups, it->first) == nullptr && r.Find(r.groups, it->first) == nullptr &&
        r.Find(r.selectors, it->first) == nullptr) {
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
  for (uint64_t id : roots) {
    uint32_t type = plan.NodeType(id);
    if (type == 0) continue;  // reported when a program traces it
    if (absl::StatusOr<const SceneEntry*> e = Node(plan, NodeRef{id, type}, 0); !e.ok()) {
      if (absl::IsCancelled(e.status())) return e.status();
      plan.node_problems.emplace(id, e.status());
    }
  }
  return absl::OkStatus();
}

namespace {
absl::Status TooDeep(uint64_t id) {
  return absl::InvalidArgumentError(absl::StrCat("graph deeper than ", kMaxGraphDepth,
                                                 " levels at node #", id,
                                                 ": Tessera traverses at most that many levels of "
                                                 "Groups and Transforms"));
}
}  // namespace

// What traversal may skip in this scene, for this plan: SceneEntry::packets (Embree calls nothing
// of the engine's, so packets can answer its rays), and SceneEntry::occludable and what goes with
// it: a GeometryGroup of built-in
// triangles (no intersection program, not the watertight test's user geometry), or a Group whose
// every child is an Embree instance of such a GeometryGroup (its children were summarized first:
// Node builds them before their parent). Selectors and children traversed by IntersectChild run
// programs, so their scenes are not.
void SceneCache::SummarizeTraversal(SceneEntry& e) {
  e.occludable = e.children.empty();
  e.any_hit_types = 0;
  e.occluder = nullptr;
  e.packets = e.children.empty();
  for (const auto& info : e.geometries) {
    e.packets =
        e.packets && info->plan != nullptr && info->triangles && !info->watertight && !info->filter;
    if (info->plan == nullptr || !info->triangles || info->watertight ||
        !info->plan->builtin_triangles) {
      e.occludable = false;
      continue;
    }
    e.any_hit_types |= info->plan->any_hit_types;
    if (e.occluder == nullptr) e.occluder = info->plan;
  }
  for (const FlatInstance& instance : e.instances) {
    e.packets = e.packets && instance.scene != nullptr && instance.scene->packets &&
                (!e.single_instance || !instance.xform.active);
    if (instance.scene == nullptr || !instance.scene->occludable) {
      e.occludable = false;
      continue;
    }
    e.any_hit_types |= instance.scene->any_hit_types;
    if (e.occluder == nullptr) e.occluder = instance.scene->occluder;
  }
  if (e.occluder == nullptr) e.occludable = false;  // nothing to hit: the usual path is as quick
}

absl::StatusOr<const SceneEntry*> SceneCache::Node(LaunchPlan& plan, NodeRef ref, int depth) {
  if (depth > kMaxGraphDepth) return TooDeep(ref.id);
  if (ref.type == RT_OBJECTTYPE_GROUP || ref.type == RT_OBJECTTYPE_GEOMETRY_GROUP ||
      ref.type == RT_OBJECTTYPE_SELECTOR) {
    // Built or checked earlier in this plan through another parent: a graph that shares
    // subgraphs costs a visit per node, not per path (2^levels when each level shares one child
    // twice).
    auto it = entries_.find(ref.id);
    if (it != entries_.end() && it->second != nullptr && it->second->plan_serial == plan.serial) {
      if (depth + it->second->height > kMaxGraphDepth) return TooDeep(ref.id);
      return it->second.get();
    }
  }
  absl::StatusOr<const SceneEntry*> built;
  switch (ref.type) {
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
      built = BuildGeometryGroup(plan, ref.id);
      break;
    case RT_OBJECTTYPE_GROUP:
      built = BuildGroup(plan, ref.id, depth);
      break;
    case RT_OBJECTTYPE_SELECTOR:
      built = BuildSelector(plan, ref.id, depth);
      break;
    case RT_OBJECTTYPE_TRANSFORM: {
      const TransformRec* t = plan.replica->Find(plan.replica->transforms, ref.id);
      if (t == nullptr) return absl::NotFoundError(absl::StrCat("unknown transform #", ref.id));
      if (t->child.id == 0) {
        return absl::FailedPreconditionError(absl::StrCat("transform #", ref.id, " has no child"));
      }
      return Node(plan, t->child, depth + 1);
    }
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("object #", ref.id, " is not a graph node (type ", ref.type, ")"));
  }
  if (built.ok()) {
    if (const auto it = entries_.find(ref.id); it != entries_.end() && it->second.get() == *built) {
      SummarizeTraversal(*it->second);
    }
  }
  // Traversal that reaches this node below a Transform or Selector root finds no scene here and
  // reports why (trace.cc TraverseNode), not only traversal from the root itself.
  if (!built.ok() && !absl::IsCancelled(built.status())) {
    plan.node_problems.emplace(ref.id, built.status());
  }
  return built;
}

absl::StatusOr<Box> SceneCache::Bounds(LaunchPlan& plan, NodeRef ref, int depth, int* height) {
  absl::StatusOr<const SceneEntry*> e = Node(plan, ref, depth);
  if (!e.ok()) return e.status();
  if (ref.type != RT_OBJECTTYPE_TRANSFORM) {
    *height = (*e)->height;
    return (*e)->bounds;
  }
  const TransformRec* t = plan.replica->Find(plan.replica->transforms, ref.id);
  absl::StatusOr<Box> child = Bounds(plan, t->child, depth + 1, height);
  if (!child.ok()) return child.status();
  ++*height;
  return TransformBox(t->matrix, *child);
}

absl::StatusOr<const SceneEntry*> SceneCache::BuildGeometryGroup(LaunchPlan& plan, uint64_t id) {
  const Replica& r = *plan.replica;
  const GeometryGroupRec* gg = r.Find(r.geometry_groups, id);
  if (gg == nullptr) return absl::NotFoundError(absl::StrCat("unknown geometry group #", id));
  const AccelRec* accel = r.Find(r.accelerations, gg->acceleration);
  if (accel == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat("geometry group #", id, " has no acceleration"));
  }
  bool any_filter = false;
  for (uint64_t gid : gg->children) {
    const InstanceRec* gi = r.Find(r.instances, gid);
    const GeometryRec* g = gi ? r.Find(r.geometries, gi->geometry) : nullptr;
    if (g == nullptr) {
      return absl::FailedPreconditionError(
          absl::StrCat("geometry group #", id, ": child #", gid, " has no geometry"));
    }
    auto ip = plan.instances.find(gid);
    if (ip != plan.instances.end() && !ip->second.problem.ok()) return ip->second.problem;
    // Checked for a scene kept from an earlier plan too: traversal runs the intersection
    // program of every geometry (triangles report their attributes through it) but built-in
    // triangles'.
    if (ip == plan.instances.end() ||
        (ip->second.intersection == nullptr && !ip->second.builtin_triangles)) {
      return absl::FailedPreconditionError(absl::StrCat("geometry group #", id, ": geometry #",
                                                        gi->geometry, " of child #", gid,
                                                        " has no intersection program"));
    }
    any_filter |= ip->second.has_any_hit;
  }
  absl::StatusOr<SceneOptions> options =
      OptionsOf(gg->acceleration, *accel, any_filter, plan.accuracy_flags);
  if (!options.ok()) return options.status();
  // What a refit keeps (layout), and what the scene depends on besides (stamp): the
  // acceleration's epoch and the triangles' description.
  size_t layout = absl::HashOf(gg->acceleration, accel->builder, accel->properties, gg->children,
                               options->quality, options->refit, options->robust,
                               options->watertight, options->compact);
  for (uint64_t gid : gg->children) {
    const InstanceRec& gi = r.instances.at(gid);
    const GeometryRec& g = r.geometries.at(gi.geometry);
    layout = absl::HashOf(layout, gi.geometry, g.primitive_count, plan.instances[gid].has_any_hit,
                          g.builtin_triangles);
  }
  size_t stamp = absl::HashOf(layout, accel->build_epoch);
  for (uint64_t gid : gg->children) {
    stamp = absl::HashOf(stamp, r.geometries.at(r.instances.at(gid).geometry).mesh_stamp);
  }
  auto& slot = entries_[id];
  if (slot && slot->stamp == stamp) {
    for (auto& info : slot->geometries) info->plan = &plan.instances[info->instance_id];
    slot->plan_serial = plan.serial;
    return slot.get();
  }
  const std::string what = absl::StrCat("geometry group #", id);
  if (slot && slot->refit && options->refit && slot->layout == layout) {
    // The same geometries with new data: Embree refits the hierarchy in place.
    for (auto& info : slot->geometries) info->plan = &plan.instances[info->instance_id];
    absl::Status s = MakeGeometries(plan, id, *gg, *accel, *options, *slot, /*refit=*/true);
    if (s.ok()) s = Commit(slot->scene, what);
    if (s.ok()) {
      slot->stamp = stamp;
      slot->build_epoch = accel->build_epoch;
      slot->plan_serial = plan.serial;
      slot->bounds = slot->geometries.empty() ? EmptyBox() : SceneBounds(slot->scene);
      ++refitted_;
      return slot.get();
    }
    slot.reset();  // built again from scratch below, which reports a lasting problem
    if (absl::IsCancelled(s)) return s;
  }

  auto entry = std::make_unique<SceneEntry>();
  entry->stamp = stamp;
  entry->layout = layout;
  entry->refit = options->refit;
  entry->tnear_inclusive = options->robust || options->watertight;
  entry->plan_serial = plan.serial;
  entry->acceleration = gg->acceleration;
  entry->build_epoch = accel->build_epoch;
  entry->scene = rtcNewScene(device_);
  rtcSetSceneBuildQuality(entry->scene, options->quality);
  // Native triangles with intersection programs: a ray whose hit the program rejects is traced
  // again with a context filter (trace.cc, TraverseVerified).
  const int verify = TriangleBuilder(*accel) ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION : 0;
  rtcSetSceneFlags(entry->scene, static_cast<RTCSceneFlags>(options->flags() | verify));
  if (absl::Status s = MakeGeometries(plan, id, *gg, *accel, *options, *entry, /*refit=*/false);
      !s.ok()) {
    return s;
  }
  if (absl::Status s = Commit(entry->scene, what); !s.ok()) return s;
  entry->bounds = entry->geometries.empty() ? EmptyBox() : SceneBounds(entry->scene);
  ++built_;
  slot = std::move(entry);
  return slot.get();
}

namespace {

// The bounds of a triangle of the watertight test's user geometry (WatertightBox).
void WatertightBounds(const RTCBoundsFunctionArguments* args) {
  const auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
  const uint32_t* tri = info->indices + 3 * size_t{args->primID};
  float lo[3], hi[3];
  WatertightBox(info->vertices + 3 * size_t{tri[0]}, info->vertices + 3 * size_t{tri[1]},
                info->vertices + 3 * size_t{tri[2]}, lo, hi);
  *args->bounds_o = RTCBounds{lo[0], lo[1], lo[2], 0.f, hi[0], hi[1], hi[2], 0.f};
}

// Copies `source` into a new geometry for `info`: Embree's triangles, or the watertight test's
// user geometry over copies of its own.
absl::StatusOr<RTCGeometry> NewTriangles(RTCDevice device, const TriangleSource& source,
                                         bool watertight, GeometryInfo& info) {
  info.triangles = true;
  info.watertight = watertight;
  info.vertex_count = source.vertex_count;
  info.triangle_count = source.triangle_count;
  if (watertight) {
    info.own_vertices.assign(3 * source.vertex_count, 0.f);
    info.own_indices.assign(3 * source.triangle_count, 0);
    if (absl::Status s = source.copy(info.own_vertices.data(), info.own_indices.data()); !s.ok()) {
      return s;
    }
    info.vertices = info.own_vertices.data();
    info.indices = info.own_indices.data();
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(source.triangle_count));
    rtcSetGeometryBoundsFunction(geom, &WatertightBounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, &IntersectWatertight);
    // Its hits reach the same filter as a native triangle's (rtcFilterIntersection).
    if (info.filter) rtcSetGeometryIntersectFilterFunction(geom, &FilterTriangles);
    return geom;
  }
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads vertices 16 bytes at a time: a buffer of its own, padded, in any layout we get.
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, source.vertex_count));
  auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, source.triangle_count));
  if (absl::Status s = source.copy(v, idx); !s.ok()) {
    rtcReleaseGeometry(geom);
    return s;
  }
  info.vertices = v;
  info.indices = idx;
  if (info.filter) rtcSetGeometryIntersectFilterFunction(geom, &FilterTriangles);
  return geom;
}

// Copies `source` again into `info`'s arrays, for a refit.
absl::Status RefillTriangles(RTCGeometry geom, const TriangleSource& source, GeometryInfo& info) {
  if (!info.triangles || source.vertex_count != info.vertex_count ||
      source.triangle_count != info.triangle_count) {
    return absl::FailedPreconditionError("the triangles' counts changed: not a refit");
  }
  if (info.watertight) return source.copy(info.own_vertices.data(), info.own_indices.data());
  absl::Status s =
      source.copy(const_cast<float*>(info.vertices), const_cast<uint32_t*>(info.indices));
  rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcUpdateGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0);
  return s;
}

}  // namespace

absl::Status SceneCache::MakeGeometries(LaunchPlan& plan, uint64_t id, const GeometryGroupRec& gg,
                                        const AccelRec& accel, const SceneOptions& options,
                                        SceneEntry& entry, bool refit) {
  const Replica& r = *plan.replica;
  for (size_t child = 0; child < gg.children.size(); ++child) {
    const uint64_t gid = gg.children[child];
    const InstanceRec& gi = r.instances.at(gid);
    const GeometryRec& g = r.geometries.at(gi.geometry);
    InstancePlan& ip = plan.instances[gid];
    std::optional<TriangleSource> tris;
    if (g.builtin_triangles) {
      absl::StatusOr<TriangleSource> made = BuiltinTriangleSource(r, gi.geometry, g);
      if (!made.ok()) return made.status();
      tris = *std::move(made);
    } else {
      absl::StatusOr<std::optional<TriangleSource>> found =
          BufferTriangleSource(r, gg.acceleration, accel, gid, gi, g);
      if (!found.ok()) return found.status();
      tris = *std::move(found);
    }
    if (!tris && (ip.bounds == nullptr || ip.intersection == nullptr)) {
      return absl::FailedPreconditionError(absl::StrCat(
          "geometry #", gi.geometry, " needs an intersection and a bounding box program"));
    }
    if (refit) {
      GeometryInfo& info = *entry.geometries[child];
      RTCGeometry geom = rtcGetGeometry(entry.scene, static_cast<unsigned>(child));
      absl::Status s = tris ? RefillTriangles(geom, *tris, info)
                            : RunBounds(plan, *ip.bounds, gi.geometry, info.bounds);
      if (!s.ok()) return s;
      rtcCommitGeometry(geom);
      continue;
    }
    auto info = std::make_unique<GeometryInfo>();
    info->instance_id = gid;
    info->plan = &ip;
    info->filter = ip.has_any_hit;
    RTCGeometry geom;
    if (tris) {
      absl::StatusOr<RTCGeometry> made = NewTriangles(device_, *tris, options.watertight, *info);
      if (!made.ok()) return made.status();
      geom = *made;
    } else {
      // Bounds rtAccelerationSetData restored for this child are what its program gave when
      // they were saved: the same build without running it (the host checked the fingerprint).
      if (child < accel.cached_bounds.size() && accel.cached_bounds[child].has_bounds &&
          accel.cached_bounds[child].primitive_count == g.primitive_count) {
        info->bounds = accel.cached_bounds[child].bounds;
      } else {
        // Bounds a program leaves unwritten stay NaN: invalid, so that primitive is never hit.
        info->bounds.assign(size_t{g.primitive_count} * 6, std::numeric_limits<float>::quiet_NaN());
        if (absl::Status s = RunBounds(plan, *ip.bounds, gi.geometry, info->bounds); !s.ok()) {
          return s;
        }
      }
      geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(g.primitive_count));
      rtcSetGeometryBoundsFunction(geom, &BoundsFromArray, nullptr);
      rtcSetGeometryIntersectFunction(geom, &IntersectUserGeometry);
    }
    rtcSetGeometryUserData(geom, info.get());
    rtcSetGeometryBuildQuality(geom, options.refit ? RTC_BUILD_QUALITY_REFIT : options.quality);
    rtcCommitGeometry(geom);
    // Traversal finds a hit's GeometryInfo as geometries[geomID]: ids count from 0 in a new scene.
    const unsigned geom_id = rtcAttachGeometry(entry.scene, geom);
    rtcReleaseGeometry(geom);
    if (geom_id != entry.geometries.size()) {
      return absl::InternalError(absl::StrCat("Embree gave geometry group #", id, " geometry id ",
                                              geom_id, " for its geometry ",
                                              entry.geometries.size()));
    }
    entry.geometries.push_back(std::move(info));
  }
  return absl::OkStatus();
}

namespace {

// Bounding boxes of primitives [*next, count) into `bounds`, six floats each; *next is the
// primitive a cancel found.
__attribute__((noinline)) bool BoundsOf(const LaunchPlan& plan, const BoundProgram& program,
                                        std::vector<float>& bounds, const std::atomic<bool>* cancel,
                                        uint64_t* next) {
  const uint64_t count = bounds.size() / 6;
  for (uint64_t& p = *next; p < count; ++p) {
    if (p % 1024 == 0 && cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
      return false;
    }
    float* b = &bounds[p * 6];
    RunBoundsProgram(plan, program, static_cast<unsigned>(p), b);
    bool finite = true;
    for (int k = 0; k < 6; ++k) finite = finite && std::isfinite(b[k]);
    if (!finite || b[0] > b[3] || b[1] > b[4] || b[2] > b[5]) {
      // Invalid bounds: the primitive can never be hit (OptiX leaves this undefined).
      b[0] = b[1] = b[2] = 1.f;
      b[3] = b[4] = b[5] = -1.f;
    } else {
      ClampToEmbreeRange(b);
    }
  }
  return true;
}

// BoundsOf, jumped out of where a program never returns after a cancel (interrupt.h), as a
// launch index is.
bool InterruptibleBoundsOf(const LaunchPlan& plan, const BoundProgram& program,
                           std::vector<float>& bounds, const std::atomic<bool>& cancel,
                           uint64_t* next) {
  static const std::atomic<bool> kNever{false};
  InterruptibleTile interruptible(cancel, kNever);
  sigjmp_buf interrupted;
  if (sigsetjmp(interrupted, 0) != 0) {
    interruptible.Jumped();
    return false;
  }
  interruptible.Arm(&interrupted);
  return BoundsOf(plan, program, bounds, &cancel, next);
}

}  // namespace

absl::Status SceneCache::RunBounds(const LaunchPlan& plan, const BoundProgram& program,
                                   uint64_t geometry, std::vector<float>& bounds) {
  uint64_t next = 0;
  const bool done = cancel_ == nullptr
                        ? BoundsOf(plan, program, bounds, nullptr, &next)
                        : InterruptibleBoundsOf(plan, program, bounds, *cancel_, &next);
  if (done) return absl::OkStatus();
  return absl::CancelledError(
      absl::StrCat("launch cancelled while running the bounding box program of geometry #",
                   geometry, " (primitive ", next, " of ", bounds.size() / 6, ")"));
}

// Flattened groups. A Group's child whose subgraph holds only Groups, affine Transforms and
// GeometryGroups becomes Embree instances (Debian's Embree has one instance level) of the
// GeometryGroups' scenes, each with the transform the chain composes, so that traversal runs in
// Embree instead of a callback and a nested scene per level. The plan rebuilds a Group's scene
// when a transform or GeometryGroup below it changes (the stamp hashes every leaf), so a chain
// is static between launches. Other children (Selectors, projective matrices, subgraphs of more
// than kMaxFlatLeavesPerChild paths) stay one-primitive user geometries traversed by
// IntersectChild.
namespace {
constexpr size_t kMaxFlatLeavesPerChild = 4096;
constexpr size_t kMaxFlatInstances = 65536;
constexpr size_t kNotFlat = SIZE_MAX;

// Embree instances take affine matrices. Entries are bounded too: TraverseNode raises
// RT_EXCEPTION_INVALID_RAY for a ray a degenerate inverse moves out of Embree's range, which
// Embree's own transform of the ray cannot do, so such transforms keep that path.
bool Flattenable(const Mat& m) {
  constexpr float kMaxEntry = 1e8f;
  for (float x : m) {
    if (!(std::fabs(x) <= kMaxEntry)) return false;
  }
  return m[12] == 0.f && m[13] == 0.f && m[14] == 0.f && m[15] == 1.f;
}

// Whether `b` is the inverse of `a`: their product is the identity within a rounding bound of
// each entry's terms (a large translation under a rotation leaves more than a unit's error).
bool InverseOf(const Mat& a, const Mat& b) {
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      float sum = 0.f, magnitude = 0.f;
      for (int k = 0; k < 4; ++k) {
        sum += a[i * 4 + k] * b[k * 4 + j];
        magnitude += std::fabs(a[i * 4 + k] * b[k * 4 + j]);
      }
      if (!(std::fabs(sum - (i == j ? 1.f : 0.f)) <= 1e-4f * (1.f + magnitude))) return false;
    }
  }
  return true;
}
}  // namespace

size_t SceneCache::FlatLeafCount(const LaunchPlan& plan, NodeRef ref) {
  if (flat_serial_ != plan.serial) {
    flat_counts_.clear();
    flat_serial_ = plan.serial;
  }
  if (auto it = flat_counts_.find(ref.id); it != flat_counts_.end()) return it->second;
  const Replica& r = *plan.replica;
  size_t n = kNotFlat;
  if (ref.type == RT_OBJECTTYPE_GEOMETRY_GROUP) {
    n = 1;
  } else if (ref.type == RT_OBJECTTYPE_TRANSFORM) {
    const TransformRec* t = r.Find(r.transforms, ref.id);
    if (t != nullptr && t->child.id != 0 && Flattenable(t->matrix) && Flattenable(t->inverse)) {
      n = FlatLeafCount(plan, t->child);
    }
  } else if (ref.type == RT_OBJECTTYPE_GROUP) {
    if (const GroupRec* g = r.Find(r.groups, ref.id); g != nullptr) {
      n = 0;
      for (const NodeRef& c : g->children) {
        const size_t k = FlatLeafCount(plan, c);
        if (k == kNotFlat) {
          n = kNotFlat;
          break;
        }
        n = std::min(n + k, kMaxFlatInstances + 1);  // a shared subgraph's paths multiply
      }
    }
  }
  flat_counts_[ref.id] = n;
  return n;
}

bool SceneCache::Flatten(const LaunchPlan& plan, NodeRef ref, const Xform& above,
                         std::vector<FlatLeaf>& out, int* tnear) {
  const Replica& r = *plan.replica;
  switch (ref.type) {
    case RT_OBJECTTYPE_GEOMETRY_GROUP: {
      const SceneEntry* e = Find(ref.id);
      if (e == nullptr || e->scene == nullptr || e->plan_serial != plan.serial) return false;
      if (e->geometries.empty()) return true;  // nothing to hit
      // The traced ray's tnear is set once per scene (IntersectScene).
      if (*tnear >= 0 && *tnear != int{e->tnear_inclusive}) return false;
      // Embree drops an instance whose box reaches past its range (ClampToEmbreeRange); the
      // per-level path clamps a child's box instead.
      if (above.active) {
        const Box b = TransformBox(above.to_world, e->bounds);
        for (float x : b) {
          if (!(std::fabs(x) <= kMaxBoundsExtent)) return false;
        }
      }
      *tnear = e->tnear_inclusive;
      out.push_back(FlatLeaf{e, above});
      return true;
    }
    case RT_OBJECTTYPE_TRANSFORM: {
      const TransformRec& t = r.transforms.at(ref.id);
      // Composed as traversal composes (TraverseNode): from the top down.
      Xform x;
      x.to_world = above.active ? MulMat(above.to_world, t.matrix) : t.matrix;
      x.to_object = above.active ? MulMat(t.inverse, above.to_object) : t.inverse;
      // Each factor is bounded (Flattenable), but a chain's product can overflow, and Embree
      // inverts the instance's matrix itself: one whose inverse is not the bounded `to_object`
      // (singular, or an inverse that does not match) would move rays to infinities or NaN,
      // which Embree asserts on. Such a chain keeps the per-level path, which raises
      // RT_EXCEPTION_INVALID_RAY instead.
      if (!Flattenable(x.to_world) || !Flattenable(x.to_object) ||
          !InverseOf(x.to_world, x.to_object)) {
        return false;
      }
      // A path whose transforms come to the identity (an OBJ or a glTF node placed as it is)
      // moves nothing: its rays, hits, spawn points and rtTransform* calls skip the matrices.
      x.active = x.to_world != kIdentity || x.to_object != kIdentity;
      return Flatten(plan, t.child, x, out, tnear);
    }
    case RT_OBJECTTYPE_GROUP:
      for (const NodeRef& c : r.groups.at(ref.id).children) {
        if (!Flatten(plan, c, above, out, tnear)) return false;
      }
      return true;
    default:
      return false;
  }
}

absl::StatusOr<const SceneEntry*> SceneCache::BuildGroup(LaunchPlan& plan, uint64_t id, int depth) {
  const Replica& r = *plan.replica;
  const GroupRec* group = r.Find(r.groups, id);
  if (group == nullptr) return absl::NotFoundError(absl::StrCat("unknown group #", id));
  const AccelRec* accel = r.Find(r.accelerations, group->acceleration);
  if (accel == nullptr) {
    return absl::FailedPreconditionError(absl::StrCat("group #", id, " has no acceleration"));
  }
  // Acceleration property "flatten" "0" keeps every child behind IntersectChild (the path
  // flattening replaces, for comparisons: bench/specialize, flattened_graph_test).
  bool may_flatten = true;
  if (auto it = accel->properties.find("flatten"); it != accel->properties.end()) {
    if (it->second != "0" && it->second != "1") {
      return absl::InvalidArgumentError(absl::StrCat("acceleration #", group->acceleration,
                                                     ": property flatten is '", it->second,
                                                     "', not \"0\" or \"1\""));
    }
    may_flatten = it->second == "1";
  }
  std::vector<Box> bounds;
  int height = 0;
  size_t stamp = absl::HashOf(group->acceleration, accel->build_epoch, may_flatten);
  for (const NodeRef& child : group->children) {
    int child_height = 0;
    absl::StatusOr<Box> b = Bounds(plan, child, depth + 1, &child_height);
    if (!b.ok()) return b.status();
    height = std::max(height, child_height + 1);
    bounds.push_back(*b);
    stamp = absl::HashOf(stamp, child.id, child.type, (*b)[0], (*b)[1], (*b)[2], (*b)[3], (*b)[4],
                         (*b)[5]);
  }
  // Which children become instances: leaves[first[i] .. first[i + 1]) for child i, or none
  // (flat[i] false). The traced ray's tnear is one per scene: GeometryGroups that take t == tnear
  // (robust, watertight) are instanced only with others that do, and only when every child is.
  std::vector<FlatLeaf> leaves;
  std::vector<size_t> first(group->children.size() + 1, 0);
  std::vector<bool> flat(group->children.size(), false);
  int tnear = -1;
  for (int pass = 0; pass < 2; ++pass) {
    leaves.clear();
    bool all = true;
    for (size_t i = 0; i < group->children.size(); ++i) {
      first[i] = leaves.size();
      const size_t n = FlatLeafCount(plan, group->children[i]);
      flat[i] = may_flatten && n <= kMaxFlatLeavesPerChild &&
                leaves.size() + n <= kMaxFlatInstances &&
                Flatten(plan, group->children[i], Xform{}, leaves, &tnear);
      if (!flat[i]) leaves.resize(first[i]);
      all = all && flat[i];
    }
    first[group->children.size()] = leaves.size();
    if (all || tnear != 1) break;
    tnear = 0;  // a child traversed by IntersectChild must see the ray's own tnear
  }
  for (size_t i = 0; i < group->children.size(); ++i) {
    stamp = absl::HashOf(stamp, bool{flat[i]}, first[i]);
  }
  for (const FlatLeaf& leaf : leaves) {
    stamp = absl::HashOf(stamp, reinterpret_cast<uintptr_t>(leaf.scene),
                         reinterpret_cast<uintptr_t>(leaf.scene->scene), leaf.scene->stamp,
                         leaf.xform.active, leaf.xform.to_world, leaf.xform.to_object);
  }
  // A child rebuilt elsewhere changes its bounds or leaves them; traversal looks the child's
  // scene up at trace time, so equal bounds need no rebuild here (instanced GeometryGroups are
  // in the stamp).
  auto& slot = entries_[id];
  if (slot && slot->stamp == stamp) {
    slot->plan_serial = plan.serial;
    slot->height = height;
    return slot.get();
  }

  auto entry = std::make_unique<SceneEntry>();
  entry->stamp = stamp;
  entry->plan_serial = plan.serial;
  entry->height = height;
  entry->tnear_inclusive = tnear == 1;
  entry->scene = rtcNewScene(device_);
  rtcSetSceneBuildQuality(entry->scene, RTC_BUILD_QUALITY_MEDIUM);
  auto attach = [&](RTCGeometry geom, FlatInstance instance) -> absl::Status {
    rtcCommitGeometry(geom);
    const unsigned geom_id = rtcAttachGeometry(entry->scene, geom);
    rtcReleaseGeometry(geom);
    // Traversal finds an instance as instances[instID]: ids count from 0 in a new scene.
    if (geom_id != entry->instances.size()) {
      return absl::InternalError(absl::StrCat("Embree gave group #", id, " geometry id ", geom_id,
                                              " for its geometry ", entry->instances.size()));
    }
    entry->instances.push_back(std::move(instance));
    return absl::OkStatus();
  };
  for (size_t i = 0; i < group->children.size(); ++i) {
    if (flat[i]) {
      for (size_t k = first[i]; k < first[i + 1]; ++k) {
        const FlatLeaf& leaf = leaves[k];
        RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, leaf.scene->scene);
        // The first three rows of the row-major 4x4: Embree's 3x4 row-major layout.
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, leaf.xform.to_world.data());
        if (absl::Status s = attach(geom, FlatInstance{leaf.scene, leaf.xform}); !s.ok()) return s;
      }
      continue;
    }
    auto info = std::make_unique<ChildInfo>();
    info->child = group->children[i];
    info->bounds = IsEmpty(bounds[i]) ? Box{1.f, 1.f, 1.f, -1.f, -1.f, -1.f} : bounds[i];
    ClampToEmbreeRange(info->bounds.data());  // a Transform can scale a child's box past it
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, 1);
    rtcSetGeometryUserData(geom, info.get());
    rtcSetGeometryBoundsFunction(geom, &ChildBounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, &IntersectChild);
    if (absl::Status s = attach(geom, FlatInstance{}); !s.ok()) return s;
    entry->children.push_back(std::move(info));
  }
  if (leaves.empty()) entry->instances.clear();  // IntersectScene: no instances to look up
  entry->single_instance = entry->instances.size() == 1 && entry->children.empty();
  if (absl::Status s = Commit(entry->scene, absl::StrCat("group #", id)); !s.ok()) return s;
  entry->bounds = EmptyBox();
  for (const Box& b : bounds) {
    if (IsEmpty(b)) continue;
    Grow(entry->bounds, b[0], b[1], b[2]);
    Grow(entry->bounds, b[3], b[4], b[5]);
  }
  ++built_;
  slot = std::move(entry);
  return slot.get();
}

absl::StatusOr<const SceneEntry*> SceneCache::BuildSelector(LaunchPlan& plan, uint64_t id,
                                                            int depth) {
  const Replica& r = *plan.replica;
  const SelectorRec* selector = r.Find(r.selectors, id);
  if (selector == nullptr) return absl::NotFoundError(absl::StrCat("unknown selector #", id));
  auto entry = std::make_unique<SceneEntry>();
  entry->plan_serial = plan.serial;
  entry->bounds = EmptyBox();
  for (size_t i = 0; i < selector->children.size(); ++i) {
    const NodeRef& child = selector->children[i];
    if (child.id == 0) {
      return absl::FailedPreconditionError(
          absl::StrCat("selector #", id, ": child ", i, " is not set"));
    }
    int child_height = 0;
    absl::StatusOr<Box> b = Bounds(plan, child, depth + 1, &child_height);
    if (!b.ok()) return b.status();
    entry->height = std::max(entry->height, child_height + 1);
    if (IsEmpty(*b)) continue;
    Grow(entry->bounds, (*b)[0], (*b)[1], (*b)[2]);
    Grow(entry->bounds, (*b)[3], (*b)[4], (*b)[5]);
  }
  auto& slot = entries_[id];
  slot = std::move(entry);
  return slot.get();
}

}  // namespace tessera::worker
