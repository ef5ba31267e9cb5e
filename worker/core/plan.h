// A launch plan: every program bound to its scopes, Embree scenes for the graph's accelerations,
// and launch-wide settings. Rebuilt when the replica changes; scenes are rebuilt only for
// accelerations whose inputs changed.
#ifndef TESSERA_WORKER_CORE_PLAN_H_
#define TESSERA_WORKER_CORE_PLAN_H_

#include <embree3/rtcore.h>

#include <array>
#include <atomic>
#include <deque>
#include <memory>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "binding.h"
#include "bindless.h"
#include "replica.h"
#include "texture_views.h"

namespace tessera::worker {

// A row-major 4x4 matrix, as OptiX gives transforms.
using Mat = std::array<float, 16>;
inline constexpr Mat kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// A transform from object to world space and back; identity unless `active`.
struct Xform {
  bool active = false;
  Mat to_world = kIdentity, to_object = kIdentity;
};

// a * b, row-major. One definition (plan.cc) for traversal and flattening, so that a chain
// composed either way gives the same bits.
Mat MulMat(const Mat& a, const Mat& b);

// Whether a program's machine code is a bare return, as g++ compiles an empty function at -O1 and
// above (`ret`, `rep ret`) and at -O0 (a frame set up and torn down), after CET's `endbr64` or
// not; false on other architectures. An empty any-hit program is dropped when the plan binds it.
bool EmptyProgramCode(const void* function);

struct HitGroup {
  const BoundProgram* closest_hit = nullptr;
  const BoundProgram* any_hit = nullptr;
};

struct InstancePlan {
  uint64_t id = 0;
  const BoundProgram* intersection = nullptr;
  const BoundProgram* bounds = nullptr;
  // [material index][ray type]; ray types past a material's end have no programs.
  std::vector<std::vector<HitGroup>> materials;
  bool has_any_hit = false;
  // Bit min(ray type, 63) of the ray types some material gives an any-hit program: a filter
  // callback returns at once for the others (AnyHitBit, trace.cc).
  uint64_t any_hit_types = 0;
  // Built-in triangles (GeometryTriangles): Embree intersects them; the attribute program, if
  // any, computes a hit's attributes from its barycentrics.
  bool builtin_triangles = false;
  const BoundProgram* attribute = nullptr;
  unsigned primitive_index_offset = 0;
  // Per-triangle material indices (rtGeometryTrianglesSetMaterialIndices), checked against the
  // material count when the plan is made and again at each hit, since a launch's programs may
  // write the buffer after that; null when every triangle takes material 0.
  const unsigned char* material_indices = nullptr;
  size_t material_index_stride = 0;
  unsigned material_index_bytes = 0;
  uint64_t geometry = 0, material_index_buffer = 0;  // ids, for messages
  // Why the instance cannot be traced (a program that does not bind, unknown objects, material
  // indices out of range), reported when a scene holds the instance: one that no graph reaches
  // any more stays on the device and must not fail launches.
  absl::Status problem;

  // The material of triangle `primitive`. Throws FatalError when the index stored for it is out
  // of range. Inline: it runs for every hit on built-in triangles.
  unsigned TriangleMaterial(unsigned primitive) const;
  // The index stored for triangle `primitive`, unchecked.
  unsigned StoredMaterial(unsigned primitive) const {
    return material_indices == nullptr ? 0 : IndexedMaterial(primitive);
  }
  // The same read from the material indices (set), out of line: three widths.
  unsigned IndexedMaterial(unsigned primitive) const;
};

[[noreturn]] __attribute__((noinline, cold)) void MaterialOutOfRange(const InstancePlan& ip,
                                                                     unsigned primitive,
                                                                     unsigned material);

inline unsigned InstancePlan::TriangleMaterial(unsigned primitive) const {
  const unsigned k = StoredMaterial(primitive);
  if (__builtin_expect(k >= materials.size(), 0)) MaterialOutOfRange(*this, primitive, k);
  return k;
}

// User data of one Embree geometry in a GeometryGroup's scene.
struct GeometryInfo {
  uint64_t instance_id = 0;
  bool triangles = false;  // native Embree triangles; the intersection program only reports
  // An any-hit program exists for some ray type: Embree calls our filter per candidate, which
  // returns at once for ray types without one (plan->any_hit_types).
  bool filter = false;
  std::vector<float> bounds;     // user geometry: 6 floats per primitive
  InstancePlan* plan = nullptr;  // refreshed with every plan
  // Triangles: the vertices (3 floats each) and indices (3 each) the scene was built from, for
  // hit points with error bounds (tesseraSpawnPoint) and the watertight test: Embree's buffers,
  // or `own_*` for the watertight test's user geometry.
  const float* vertices = nullptr;
  const uint32_t* indices = nullptr;
  bool watertight = false;
  uint64_t vertex_count = 0, triangle_count = 0;  // triangles: what a refit must find again
  std::vector<float> own_vertices;
  std::vector<uint32_t> own_indices;
};

// User data of one child of a Group's scene.
struct NodeInfo;
struct ChildInfo {
  NodeRef child;
  std::array<float, 6> bounds{};
  const NodeInfo* node = nullptr;  // the child in the plan that last checked the scene
};

struct SceneEntry;
// A GeometryGroup a Group's scene holds as an Embree instance (a flattened chain of Groups and
// Transforms): its scene, and the chain's composed transform (inactive when the chain has no
// Transform).
struct FlatInstance {
  const SceneEntry* scene = nullptr;
  Xform xform;
};

struct SceneEntry {
  RTCScene scene = nullptr;
  uint64_t stamp = 0;
  // The last plan that built or checked this scene: its geometries point into that plan, so no
  // other plan may traverse it.
  uint64_t plan_serial = 0;
  // Levels of nodes below this one (a Transform counts as one): a node that several parents
  // share is checked against the depth limit without walking its subgraph again.
  int height = 0;
  // GeometryGroups: the acceleration and build epoch the scene was built for, by which
  // rtAccelerationGetData finds the bounds in `geometries` (AccelerationBounds).
  uint64_t acceleration = 0;
  uint64_t build_epoch = 0;
  std::vector<std::unique_ptr<GeometryInfo>> geometries;
  std::vector<std::unique_ptr<ChildInfo>> children;
  // Groups: by Embree geometry id, the GeometryGroup a geometry instances (scene null for a
  // child traversed through IntersectChild); empty when the scene holds no instances.
  std::vector<FlatInstance> instances;
  // A Group flattened into one instance and nothing else: traversal transforms the ray and traces
  // the GeometryGroup's scene itself (IntersectSingleInstance, trace.cc).
  bool single_instance = false;
  // GeometryGroups: a hash of what a refit keeps (the children, their geometries' kinds and
  // counts, the acceleration's builder and properties, the accuracy settings), and whether the
  // acceleration refits ("refit" "1"): a change of data alone then refits this scene in place.
  size_t layout = 0;
  bool refit = false;
  // Robust or watertight: the traversal takes t == tnear, so rays enter with the float after
  // their tmin (the default takes t > tnear; trace.cc).
  bool tnear_inclusive = false;
  // Whether a ray that only asks "hit or not" (terminate on first hit, no closest hit, and no
  // any-hit program for its type among `any_hit_types`) may take Embree's occlusion query: every
  // geometry below is built-in triangles, which Embree tests alone (SummarizeTraversal,
  // scene.cc). `occluder` is the plan of one of them, which such a ray's hit names.
  bool occludable = false;
  // Whether Embree calls nothing of the engine's while it traverses this scene (every geometry
  // below is triangles without an any-hit filter or the watertight test, every child an Embree
  // instance or the one flattened instance without a transform), so that a ray's hit may come
  // from an Embree packet traced with other launch indices' rays (packet_trace.h).
  bool packets = false;
  uint64_t any_hit_types = 0;
  const InstancePlan* occluder = nullptr;
  std::array<float, 6> bounds{};
  ~SceneEntry();
};

class SceneCache;

// Slot values every binding of one module agrees on in a plan (context variables, static
// initializers): loaded once per thread and plan, not per program.
struct ModuleInvariants {
  std::vector<BoundProgram::Copy> copies;
  // Copies made invariant because their values were equal though they came from different
  // variables: `kept` is the source the invariant copies, `other` one that had the same bytes.
  // A delta of values alone may make them differ (RefreshValues).
  struct Merged {
    const void* kept;
    const void* other;
    size_t size;
  };
  std::vector<Merged> merged;
};

// A graph node as traversal needs it.
struct NodeInfo {
  uint32_t type = 0;                        // RTobjecttype
  const SceneEntry* scene = nullptr;        // Group, GeometryGroup
  const TransformRec* transform = nullptr;  // Transform
  const NodeInfo* child = nullptr;          // Transform
  // Selector: its visit program (null when it could not be bound: node_problems says why) and
  // its children, which the visit program chooses among with rtIntersectChild.
  const BoundProgram* visit = nullptr;
  std::vector<NodeRef> children;
  std::vector<const NodeInfo*> child_nodes;
};

struct LaunchPlan {
  uint64_t serial = 0;      // unique per plan in this process, and per refresh of its values
  uint64_t generation = 0;  // the replica's generation it was made or refreshed for
  uint64_t structure_generation = 0;  // the replica's structure generation it was made for
  uint64_t bindings_generation = 0;   // the replica's bindings generation it was made for
  const Replica* replica = nullptr;
  std::deque<BoundProgram> programs;  // owns every bound program
  std::vector<const BoundProgram*> ray_generation, exception, miss;
  std::unordered_map<uint64_t, InstancePlan> instances;
  AttributeLayout attributes;
  std::vector<ModuleInvariants> invariants;  // by module index
  size_t attribute_bytes = 0;                // attribute bytes a hit carries
  long barycentrics_offset = -1;  // of attribute rtTriangleBarycentrics, -1 if none declares it
  std::unordered_map<uint64_t, NodeInfo> nodes;              // every graph node (stable addresses)
  std::unordered_map<uint64_t, const BoundProgram*> visits;  // by selector
  // Why the scene of a root node (one an object variable names) could not be built. Reported
  // when a program traces it, not when the plan is made: a variable of an unreachable object (a
  // program no longer attached, say) still lives on the device and must not fail launches.
  std::unordered_map<uint64_t, absl::Status> node_problems;
  // Those of node_problems that binding found (selectors' visit programs), and the nodes object
  // variables name: what RefreshGraph starts from.
  std::unordered_map<uint64_t, absl::Status> bind_problems;
  std::vector<uint64_t> roots;
  TextureTable textures;   // every sampler the replica holds, by id (texture_views.h)
  BindlessTable bindless;  // buffers and programs by id (bindless.h)
  SceneCache* scenes = nullptr;
  size_t max_depth = 8;
  uint32_t ray_type_count = 0;
  uint32_t exception_mask = 0;
  uint32_t accuracy_flags = 0;  // the context's TESSERA_ACCURACY_* (tessera/accuracy.h)
  bool user_exceptions = false;
  bool print_enabled = false;
  std::array<int32_t, 3> print_index{-1, -1, -1};
  uint64_t print_buffer_size = UINT64_MAX;

  bool ExceptionEnabled(unsigned code) const;
  // RTobjecttype of a graph node id, or 0 if none.
  uint32_t NodeType(uint64_t id) const;
  const NodeInfo* Node(uint64_t id) const {
    auto it = nodes.find(id);
    return it == nodes.end() ? nullptr : &it->second;
  }
};

// How a GeometryGroup's scene is built (docs/accuracy.md, "Acceleration knobs").
struct SceneOptions {
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;  // the scene's; never REFIT
  bool refit = false;   // geometries take RTC_BUILD_QUALITY_REFIT, the scene RTC_SCENE_FLAG_DYNAMIC
  bool robust = false;  // RTC_SCENE_FLAG_ROBUST
  bool watertight = false;  // triangles through the watertight test (watertight.h)
  bool compact = false;     // RTC_SCENE_FLAG_COMPACT
  RTCSceneFlags flags() const;
};

// The options for an acceleration's builder and properties and the context's accuracy flags;
// `has_filter`: an any-hit program will see its candidates. Invalid property values fail naming
// the acceleration.
absl::StatusOr<SceneOptions> OptionsOf(uint64_t accel_id, const AccelRec& a, bool has_filter,
                                       uint32_t accuracy_flags);

class SceneCache {
 public:
  explicit SceneCache(RTCDevice device) : device_(device) {}
  // Builds or refreshes the scenes of every node reachable from `roots`. When `cancel` becomes
  // true, bounding box programs and Embree's builds stop within moments and Update returns
  // CANCELLED; scenes finished before that stay cached, the interrupted one is dropped.
  absl::Status Update(LaunchPlan& plan, const std::vector<uint64_t>& roots,
                      const std::atomic<bool>* cancel = nullptr);
  // Scenes checked by the plan of serial `from` are now checked by that of serial `to` (the same
  // plan, refreshed).
  void Reserial(uint64_t from, uint64_t to) {
    for (auto& [id, entry] : entries_) {
      if (entry != nullptr && entry->plan_serial == from) entry->plan_serial = to;
    }
  }
  const SceneEntry* Find(uint64_t id) const {
    auto it = entries_.find(id);
    return it == entries_.end() ? nullptr : it->second.get();
  }
  // Device::AccelerationBounds over the scenes kept (acceleration_bounds.cc).
  absl::StatusOr<v1::AccelerationBoundsReply> AccelerationBounds(
      const v1::AccelerationBoundsRequest& request) const;

 private:
  absl::StatusOr<const SceneEntry*> Node(LaunchPlan& plan, NodeRef ref, int depth);
  // The bounds of `ref`'s subgraph; `height` receives its levels of nodes below `ref`.
  absl::StatusOr<std::array<float, 6>> Bounds(LaunchPlan& plan, NodeRef ref, int depth,
                                              int* height);
  absl::StatusOr<const SceneEntry*> BuildGeometryGroup(LaunchPlan& plan, uint64_t id);
  absl::Status RunBounds(const LaunchPlan& plan, const BoundProgram& program, uint64_t geometry,
                         std::vector<float>& bounds);
  // Makes the Embree geometry of each of `gg`'s children into `entry` (refit: copies their data
  // again into the geometries `entry` holds).
  absl::Status MakeGeometries(LaunchPlan& plan, uint64_t id, const GeometryGroupRec& gg,
                              const AccelRec& accel, const SceneOptions& options, SceneEntry& entry,
                              bool refit);
  absl::StatusOr<const SceneEntry*> BuildGroup(LaunchPlan& plan, uint64_t id, int depth);
  static void SummarizeTraversal(SceneEntry& entry);
  // Flattening a Group's children into Embree instances (scene.cc, "Flattened groups").
  struct FlatLeaf {
    const SceneEntry* scene;
    Xform xform;
  };
  // The GeometryGroups below `ref` through Groups and affine Transforms alone (counted once per
  // path, saturating past kMaxFlatInstances), or SIZE_MAX when something else lies below.
  size_t FlatLeafCount(const LaunchPlan& plan, NodeRef ref);
  // Appends the leaves below `ref`, `above` the transform from `ref`'s space to the Group's.
  // False when a GeometryGroup's tnear rule differs from *tnear (-1: not chosen yet).
  bool Flatten(const LaunchPlan& plan, NodeRef ref, const Xform& above, std::vector<FlatLeaf>& out,
               int* tnear);
  // A selector has no Embree scene: its entry holds the bounds and height of its children, whose
  // scenes it builds.
  absl::StatusOr<const SceneEntry*> BuildSelector(LaunchPlan& plan, uint64_t id, int depth);

  bool Cancelled() const { return cancel_ != nullptr && cancel_->load(std::memory_order_relaxed); }
  // Embree's progress monitor: returning false stops the build (RTC_ERROR_CANCELLED).
  static bool KeepBuilding(void* cache, double progress);
  // Commits `scene` of `what` ("geometry group #3"), reporting a cancel or an Embree error.
  absl::Status Commit(RTCScene scene, const std::string& what);

  RTCDevice device_;
  const std::atomic<bool>* cancel_ = nullptr;  // during Update only
  std::unordered_map<uint64_t, std::unique_ptr<SceneEntry>> entries_;
  uint64_t built_ = 0;        // scenes (re)built, for tests and logs
  uint64_t refitted_ = 0;     // GeometryGroup scenes refitted in place
  uint64_t flat_serial_ = 0;  // the plan whose counts flat_counts_ holds
  std::unordered_map<uint64_t, size_t> flat_counts_;

 public:
  uint64_t built_count() const { return built_; }
  uint64_t refitted_count() const { return refitted_; }
};

// Builds the plan for `replica`: binds every program, then updates the scenes (CANCELLED when
// `cancel` becomes true meanwhile).
// Takes in a plan the variable values deltas of values alone wrote in place since the plan was
// made (Replica::structure_generation unchanged): a new serial makes every thread load its
// modules' slots again. False when the plan cannot be kept (values that were equal, and so
// shared, now differ): make a new one.
bool RefreshValues(LaunchPlan& plan, SceneCache& scenes);

// Takes in a plan the graph changes (groups, geometry groups, transforms, accelerations) made
// since (Replica::bindings_generation unchanged): builds the scenes they touch and indexes the
// nodes again, keeping every binding. Call RefreshValues first. On an error (a cancel) the plan
// must not be used.
absl::Status RefreshGraph(LaunchPlan& plan, SceneCache& scenes, const std::atomic<bool>* cancel);

absl::StatusOr<std::unique_ptr<LaunchPlan>> MakePlan(const Replica& replica, SceneCache& scenes,
                                                     const std::atomic<bool>* cancel = nullptr);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_PLAN_H_
