// Embree scenes for GeometryGroups and Groups. Groups hold their children as one-primitive user
// geometries whose callback traverses the child, so graphs deeper than Debian Embree's single
// instance level work; GeometryGroups use native triangles where the acceleration names vertex
// and index buffers and user geometry (intersection programs) otherwise.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "absl/hash/hash.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "callbacks.h"
#include "interrupt.h"
#include "plan.h"
#include "runtime.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"

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

// A triangle vertex Embree would leave out of the build with its triangles (never hit, without a
// word): finite but beyond its FLT_LARGE. Vertices cannot be clamped like bounds (the triangle
// would change), so the launch fails naming it. NaN vertices only make their triangles vanish,
// as degenerate triangles do in OptiX (so does a vertex with any infinite coordinate). OK
// otherwise.
absl::Status CheckVertexInRange(const std::string& what, const float* v, uint32_t vertex) {
  constexpr float kEmbreeLarge = 1.844e18f;
  if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    return absl::OkStatus();
  }
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(v[k]) > kEmbreeLarge) {
      return absl::OutOfRangeError(absl::StrCat(
          what, ": vertex ", vertex, " at (", v[0], ", ", v[1], ", ", v[2],
          ") lies beyond +-1.844e18, which Embree cannot build (scale the scene down)"));
    }
  }
  return absl::OkStatus();
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

// OptiX builder names → Embree build quality (docs/COMPATIBILITY.md "Accelerations").

bool TriangleBuilder(const AccelRec& a) {
  return a.builder == "Sbvh" || a.builder == "TriangleKdTree" || a.builder == "Trbvh" ||
         a.properties.count("vertex_buffer_name") > 0;
}

std::string Property(const AccelRec& a, const std::string& name, const std::string& fallback) {
  auto it = a.properties.find(name);
  return it == a.properties.end() ? fallback : it->second;
}

const BufferRec* FindBuffer(const Replica& r, const InstanceRec& gi, const GeometryRec& g,
                            const std::string& name, uint64_t* id) {
  for (const Scope* s : {&gi.vars, &g.vars}) {
    auto it = s->find(name);
    if (it != s->end() && it->second.type == RT_OBJECTTYPE_BUFFER) {
      *id = it->second.object_id;
      return r.Find(r.buffers, it->second.object_id);
    }
  }
  return nullptr;
}

struct TriangleSource {
  const BufferRec* vertices = nullptr;
  const BufferRec* indices = nullptr;
  uint64_t vertex_id = 0, index_id = 0;
  size_t vertex_stride = 12, index_stride = 12;
};

// Whether acceleration `accel_id` takes the geometry as native triangles, and from where.
absl::StatusOr<bool> FindTriangles(const Replica& r, uint64_t accel_id, const AccelRec& a,
                                   const InstanceRec& gi, const GeometryRec& g, TriangleSource& t) {
  if (!TriangleBuilder(a)) return false;
  t.vertices =
      FindBuffer(r, gi, g, Property(a, "vertex_buffer_name", "vertex_buffer"), &t.vertex_id);
  t.indices = FindBuffer(r, gi, g, Property(a, "index_buffer_name", "index_buffer"), &t.index_id);
  if (t.vertices == nullptr || t.indices == nullptr) return false;
  for (const auto& [name, stride] : {std::pair{"vertex_buffer_stride", &t.vertex_stride},
                                     std::pair{"index_buffer_stride", &t.index_stride}}) {
    const std::string text = Property(a, name, "0");
    if (!absl::SimpleAtoi(text, stride)) {
      return absl::InvalidArgumentError(absl::StrCat("acceleration #", accel_id, ": property ",
                                                     name, " is '", text, "', not a byte count"));
    }
  }
  if (t.vertex_stride == 0) t.vertex_stride = t.vertices->element_size;
  if (t.index_stride == 0) t.index_stride = t.indices->element_size;
  return t.vertex_stride >= 12 && t.index_stride >= 12;
}

}  // namespace

RTCBuildQuality BuildQuality(const AccelRec& a, bool has_filter) {
  auto refit = a.properties.find("refit");
  if (refit != a.properties.end() && refit->second != "0") return RTC_BUILD_QUALITY_REFIT;
  const std::string& b = a.builder;
  if (b == "Sbvh" || b == "TriangleKdTree" || b == "Trbvh") {
    // HIGH uses spatial splits, which can report one primitive twice to a filter callback;
    // any-hit programs must see each candidate once.
    return has_filter ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH;
  }
  // MedianBvh, Lbvh and NoAccel too: Embree's LOW quality (Morton) build, run on several threads,
  // orders primitives differently from run to run, and two hits at exactly the same t would go to
  // a different primitive from one run, or device, to the next.
  return RTC_BUILD_QUALITY_MEDIUM;
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
  // What the scene depends on: the acceleration's epoch and the geometry layout.
  size_t stamp = absl::HashOf(gg->acceleration, accel->build_epoch, accel->builder,
                              accel->properties.size(), gg->children);
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
    stamp = absl::HashOf(stamp, gi->geometry, g->primitive_count, ip->second.has_any_hit,
                         g->builtin_triangles, g->mesh_stamp);
  }
  auto& slot = entries_[id];
  if (slot && slot->stamp == stamp) {
    for (auto& info : slot->geometries) info->plan = &plan.instances[info->instance_id];
    slot->plan_serial = plan.serial;
    return slot.get();
  }

  auto entry = std::make_unique<SceneEntry>();
  entry->stamp = stamp;
  entry->plan_serial = plan.serial;
  entry->acceleration = gg->acceleration;
  entry->build_epoch = accel->build_epoch;
  entry->scene = rtcNewScene(device_);
  bool any_filter = false;
  for (uint64_t gid : gg->children) any_filter |= plan.instances[gid].has_any_hit;
  RTCBuildQuality quality = BuildQuality(*accel, any_filter);
  rtcSetSceneBuildQuality(entry->scene,
                          quality == RTC_BUILD_QUALITY_REFIT ? RTC_BUILD_QUALITY_MEDIUM : quality);
  if (quality == RTC_BUILD_QUALITY_REFIT) rtcSetSceneFlags(entry->scene, RTC_SCENE_FLAG_DYNAMIC);

  for (uint64_t gid : gg->children) {
    const InstanceRec& gi = r.instances.at(gid);
    const GeometryRec& g = r.geometries.at(gi.geometry);
    InstancePlan& ip = plan.instances[gid];
    auto info = std::make_unique<GeometryInfo>();
    info->instance_id = gid;
    info->plan = &ip;
    info->filter = ip.has_any_hit;
    RTCGeometry geom;
    TriangleSource tris;
    absl::StatusOr<bool> triangles =
        g.builtin_triangles ? false : FindTriangles(r, gg->acceleration, *accel, gi, g, tris);
    if (!triangles.ok()) return triangles.status();
    if (g.builtin_triangles) {
      info->triangles = true;
      absl::StatusOr<RTCGeometry> made = BuiltinTriangles(r, gi.geometry, g);
      if (!made.ok()) return made.status();
      geom = *made;
      if (info->filter) rtcSetGeometryIntersectFilterFunction(geom, &FilterTriangles);
    } else if (*triangles) {
      info->triangles = true;
      // An element's last vertex or triangle needs its 12 bytes, not a whole stride.
      const size_t vbytes = tris.vertices->data.size();
      const size_t nverts = vbytes < 12 ? 0 : (vbytes - 12) / tris.vertex_stride + 1;
      // Every primitive is a triangle of the index buffer: one it cannot hold would never be hit.
      const size_t ntris = g.primitive_count;
      if (!StridedFits(tris.indices->data.size(), 0, ntris, tris.index_stride, 12)) {
        return absl::OutOfRangeError(
            absl::StrCat("geometry instance #", gid, ": ", ntris, " triangles' indices every ",
                         tris.index_stride, " bytes (acceleration #", gg->acceleration,
                         ", property index_buffer_stride) do not fit index buffer #", tris.index_id,
                         " (", tris.indices->data.size(), " bytes)"));
      }
      geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(
          rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nverts));
      for (size_t i = 0; i < nverts; ++i) {
        std::memcpy(v + 3 * i, tris.vertices->data.data() + i * tris.vertex_stride, 12);
      }
      auto* idx = static_cast<uint32_t*>(
          rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, ntris));
      for (size_t i = 0; i < ntris; ++i) {
        std::memcpy(idx + 3 * i, tris.indices->data.data() + i * tris.index_stride, 12);
        for (int k = 0; k < 3; ++k) {
          // Read before the release below frees the index buffer.
          if (const uint32_t vertex = idx[3 * i + k]; vertex >= nverts) {
            rtcReleaseGeometry(geom);
            return absl::OutOfRangeError(absl::StrCat("geometry instance #", gid, ": triangle ", i,
                                                      " uses vertex ", vertex,
                                                      " but the vertex buffer holds ", nverts));
          } else if (absl::Status in_range = CheckVertexInRange(
                         absl::StrCat("geometry instance #", gid), v + 3 * vertex, vertex);
                     !in_range.ok()) {
            rtcReleaseGeometry(geom);
            return in_range;
          }
        }
      }
      if (info->filter) rtcSetGeometryIntersectFilterFunction(geom, &FilterTriangles);
    } else {
      if (ip.bounds == nullptr || ip.intersection == nullptr) {
        return absl::FailedPreconditionError(absl::StrCat(
            "geometry #", gi.geometry, " needs an intersection and a bounding box program"));
      }
      // Bounds rtAccelerationSetData restored for this child are what its program gave when
      // they were saved: the same build without running it (the host checked the fingerprint).
      const size_t child = entry->geometries.size();
      if (child < accel->cached_bounds.size() && accel->cached_bounds[child].has_bounds &&
          accel->cached_bounds[child].primitive_count == g.primitive_count) {
        info->bounds = accel->cached_bounds[child].bounds;
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
    if (info->triangles) {
      info->vertices =
          static_cast<const float*>(rtcGetGeometryBufferData(geom, RTC_BUFFER_TYPE_VERTEX, 0));
      info->indices =
          static_cast<const uint32_t*>(rtcGetGeometryBufferData(geom, RTC_BUFFER_TYPE_INDEX, 0));
    }
    rtcSetGeometryUserData(geom, info.get());
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    // Traversal finds a hit's GeometryInfo as geometries[geomID]: ids count from 0 in a new scene.
    const unsigned geom_id = rtcAttachGeometry(entry->scene, geom);
    rtcReleaseGeometry(geom);
    if (geom_id != entry->geometries.size()) {
      return absl::InternalError(absl::StrCat("Embree gave geometry group #", id, " geometry id ",
                                              geom_id, " for its geometry ",
                                              entry->geometries.size()));
    }
    entry->geometries.push_back(std::move(info));
  }
  if (absl::Status s = Commit(entry->scene, absl::StrCat("geometry group #", id)); !s.ok()) {
    return s;
  }
  entry->bounds = entry->geometries.empty() ? EmptyBox() : SceneBounds(entry->scene);
  ++built_;
  slot = std::move(entry);
  return slot.get();
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

absl::StatusOr<RTCGeometry> SceneCache::BuiltinTriangles(const Replica& r, uint64_t id,
                                                         const GeometryRec& g) {
  const v1::TriangleMesh& m = g.mesh;
  const std::string what = absl::StrCat("geometry triangles #", id);
  const BufferRec* vb = r.Find(r.buffers, m.vertex_buffer());
  if (vb == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat(what, ": vertex buffer #", m.vertex_buffer(), " is unknown"));
  }
  const unsigned components = m.vertex_format() == RT_FORMAT_FLOAT3   ? 3
                              : m.vertex_format() == RT_FORMAT_FLOAT2 ? 2
                                                                      : 0;
  if (components == 0) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": vertex format ", m.vertex_format(),
                                                   " is not RT_FORMAT_FLOAT3 or RT_FORMAT_FLOAT2"));
  }
  const uint64_t vbytes = components * sizeof(float);
  const uint64_t vstride = m.vertex_stride() != 0 ? m.vertex_stride() : vbytes;
  const uint64_t nverts = m.vertex_count();
  if (vstride < vbytes ||
      !StridedFits(vb->data.size(), m.vertex_offset(), nverts, vstride, vbytes)) {
    return absl::OutOfRangeError(absl::StrCat(
        what, ": ", nverts, " vertices every ", vstride, " bytes from byte ", m.vertex_offset(),
        " do not fit vertex buffer #", m.vertex_buffer(), " (", vb->data.size(), " bytes)"));
  }
  const BufferRec* ib = nullptr;
  uint64_t ibytes = 0, istride = 0;
  if (m.index_buffer() != 0) {
    ib = r.Find(r.buffers, m.index_buffer());
    if (ib == nullptr) {
      return absl::FailedPreconditionError(
          absl::StrCat(what, ": index buffer #", m.index_buffer(), " is unknown"));
    }
    ibytes = m.index_format() == RT_FORMAT_UNSIGNED_INT3     ? 12
             : m.index_format() == RT_FORMAT_UNSIGNED_SHORT3 ? 6
                                                             : 0;
    if (ibytes == 0) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, ": index format ", m.index_format(),
                       " is not RT_FORMAT_UNSIGNED_INT3 or RT_FORMAT_UNSIGNED_SHORT3"));
    }
    istride = m.index_stride() != 0 ? m.index_stride() : ibytes;
    if (istride < ibytes ||
        !StridedFits(ib->data.size(), m.index_offset(), g.primitive_count, istride, ibytes)) {
      return absl::OutOfRangeError(
          absl::StrCat(what, ": ", g.primitive_count, " triangles' indices every ", istride,
                       " bytes from byte ", m.index_offset(), " do not fit index buffer #",
                       m.index_buffer(), " (", ib->data.size(), " bytes)"));
    }
  } else if (g.primitive_count > nverts / 3) {
    return absl::OutOfRangeError(absl::StrCat(what, ": ", g.primitive_count,
                                              " triangles without an index buffer need ",
                                              3 * g.primitive_count, " vertices, not ", nverts));
  }

  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads vertices 16 bytes at a time: a buffer of its own, padded, in any layout we get.
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, nverts));
  const unsigned char* vsrc = vb->data.data() + m.vertex_offset();
  for (uint64_t i = 0; i < nverts; ++i) {
    v[3 * i + 2] = 0.f;
    std::memcpy(v + 3 * i, vsrc + i * vstride, vbytes);
  }
  auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, g.primitive_count));
  for (uint64_t t = 0; t < g.primitive_count; ++t) {
    for (unsigned k = 0; k < 3; ++k) {
      uint32_t vertex = static_cast<uint32_t>(3 * t + k);
      if (ib != nullptr) {
        const unsigned char* src = ib->data.data() + m.index_offset() + t * istride;
        if (ibytes == 12) {
          std::memcpy(&vertex, src + 4 * k, 4);
        } else {
          uint16_t s;
          std::memcpy(&s, src + 2 * k, 2);
          vertex = s;
        }
      }
      if (vertex >= nverts) {
        rtcReleaseGeometry(geom);
        return absl::OutOfRangeError(absl::StrCat(what, ": triangle ", t, " uses vertex ", vertex,
                                                  " but there are ", nverts, " vertices"));
      }
      if (absl::Status in_range = CheckVertexInRange(what, v + 3 * vertex, vertex);
          !in_range.ok()) {
        rtcReleaseGeometry(geom);
        return in_range;
      }
      idx[3 * t + k] = vertex;
    }
  }
  return geom;
}

absl::StatusOr<const SceneEntry*> SceneCache::BuildGroup(LaunchPlan& plan, uint64_t id, int depth) {
  const Replica& r = *plan.replica;
  const GroupRec* group = r.Find(r.groups, id);
  if (group == nullptr) return absl::NotFoundError(absl::StrCat("unknown group #", id));
  const AccelRec* accel = r.Find(r.accelerations, group->acceleration);
  if (accel == nullptr) {
    return absl::FailedPreconditionError(absl::StrCat("group #", id, " has no acceleration"));
  }
  std::vector<Box> bounds;
  int height = 0;
  size_t stamp = absl::HashOf(group->acceleration, accel->build_epoch);
  for (const NodeRef& child : group->children) {
    int child_height = 0;
    absl::StatusOr<Box> b = Bounds(plan, child, depth + 1, &child_height);
    if (!b.ok()) return b.status();
    height = std::max(height, child_height + 1);
    bounds.push_back(*b);
    stamp = absl::HashOf(stamp, child.id, child.type, (*b)[0], (*b)[1], (*b)[2], (*b)[3], (*b)[4],
                         (*b)[5]);
  }
  // A child rebuilt elsewhere changes its bounds or leaves them; traversal looks the child's
  // scene up at trace time, so equal bounds need no rebuild here.
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
  entry->scene = rtcNewScene(device_);
  rtcSetSceneBuildQuality(entry->scene, RTC_BUILD_QUALITY_MEDIUM);
  for (size_t i = 0; i < group->children.size(); ++i) {
    auto info = std::make_unique<ChildInfo>();
    info->child = group->children[i];
    info->bounds = IsEmpty(bounds[i]) ? Box{1.f, 1.f, 1.f, -1.f, -1.f, -1.f} : bounds[i];
    ClampToEmbreeRange(info->bounds.data());  // a Transform can scale a child's box past it
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, 1);
    rtcSetGeometryUserData(geom, info.get());
    rtcSetGeometryBoundsFunction(geom, &ChildBounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, &IntersectChild);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(entry->scene, geom);
    rtcReleaseGeometry(geom);
    entry->children.push_back(std::move(info));
  }
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
