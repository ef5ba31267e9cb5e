// What the replica fuzz test (replica_fuzz_test.cc) found, each bug as its own case, so that it
// stays covered whatever a changed seed explores.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "absl/strings/str_cat.h"
#include "plan.h"
#include "replica.h"
#include "tessera/rt.h"
#include "tessera/worker/inproc_device.h"
#include "testdata/replica_fuzz_scene.h"

namespace tessera::fuzz {
namespace {

// ---- What the fuzzing found, each as its own case.

// The scene as its second delta: everything again, sequence 2, modules already on the device.
v1::StateDelta SecondDelta(const v1::StateDelta& scene) {
  v1::StateDelta d = scene;
  d.set_sequence(2);
  d.clear_modules();
  return d;
}

// A rejected delta names what it rejects, leaves the device as it was and its sequence unused.
void ExpectRejected(Device& device, const v1::StateDelta& bad, absl::StatusCode code,
                    const std::string& names, const std::string& scene_reference,
                    const v1::StateDelta& scene) {
  const absl::Status s = NoThrow("Apply", [&] { return device.Apply(bad); });
  EXPECT_EQ(s.code(), code) << s;
  EXPECT_NE(s.message().find(names), std::string::npos) << s;
  LaunchOutcome out = RunLaunch(device, ValidRequest(1, 77));
  EXPECT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == scene_reference);
  EXPECT_TRUE(device.Apply(SecondDelta(scene)).ok());
}

// Embree asserts on a ray it cannot trace (components past 1.8e18, NaN), which ended the process.
// A transform with an infinite inverse made every object-space ray such a ray.
TEST_F(ReplicaFuzz, TransformWithInfiniteInverseRaisesInvalidRayInsteadOfAborting) {
  for (bool enabled : {false, true}) {
    v1::StateDelta d = scene_;
    ObjectById(d, kTransform)->mutable_transform()->set_inverse(4, INFINITY);
    if (enabled) {
      d.mutable_context()->set_exception_mask(
          1u << (RT_EXCEPTION_INVALID_RAY - RT_EXCEPTION_PROGRAM_ID_INVALID));
    }
    std::unique_ptr<Device> device = DeviceWith(d);
    LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
    ASSERT_TRUE(out.status.ok()) << out.status;
    ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
    const float* center =
        reinterpret_cast<const float*>(out.output.data()) + 4 * (kHeight / 2 * kWidth + kWidth / 2);
    // Disabled, nothing below the transform is hit: the miss program's blue.
    EXPECT_EQ(center[0], enabled ? float(RT_EXCEPTION_INVALID_RAY) : 0.f);
    EXPECT_EQ(center[2], enabled ? 0.f : 1.f);
  }
}

// Embree inverts a flattened instance's matrix itself: a singular matrix (whose inverse, as sent,
// does not match it) moved every ray into NaN inside Embree, which asserted and ended the process.
// Such a chain is not flattened; the per-level path transforms rays with the inverse it was given.
TEST_F(ReplicaFuzz, SingularTransformMatrixIsNotAnEmbreeInstance) {
  v1::StateDelta d = scene_;
  v1::Transform* t = ObjectById(d, kTransform)->mutable_transform();
  t->set_matrix(10, 0.f);  // z collapses: rays cross the flattened sphere's box, now a sheet
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_EQ(out.output.size(), kWidth * kHeight * 16);
}

// Embree finds the triangle; its intersection program (the sphere's) never reports it. Traversal
// goes on past it, as past any hit an intersection program rejects, and the ray misses (the miss
// program's blue), in every launch: never shaded with zeroed attributes (the closest-hit program
// would normalize a zero normal, NaN) or with what an earlier hit of the thread left.
TEST_F(ReplicaFuzz, TriangleHitItsProgramDoesNotReportIsPassedOver) {
  v1::StateDelta d = scene_;
  const float far_away[4] = {100.f, 100.f, 100.f, 1.f};
  for (v1::Variable& v :
       *ObjectById(d, kTriangleGeometry)->mutable_geometry()->mutable_variables()) {
    if (v.name() == "sphere") v.set_data(far_away, sizeof(far_away));
  }
  std::unique_ptr<Device> device = DeviceWith(d);
  for (uint64_t launch = 1; launch <= 3; ++launch) {
    LaunchOutcome out = RunLaunch(*device, ValidRequest(1, launch));
    ASSERT_TRUE(out.status.ok()) << out.status;
    ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
    const float* triangle = reinterpret_cast<const float*>(out.output.data()) + 4 * (kWidth - 1);
    EXPECT_EQ(triangle[0], 0.f) << "launch " << launch;
    EXPECT_EQ(triangle[1], 0.f) << "launch " << launch;
    EXPECT_EQ(triangle[2], 1.f) << "launch " << launch;
  }
}

// Session 0 means "none yet" to a replica: one that took it would take any session after it.
TEST_F(ReplicaFuzz, SessionZeroIsRefused) {
  std::unique_ptr<Device> device = CreateInprocDevice(2, /*results_in_rounds=*/true);
  v1::StateDelta d = scene_;
  d.set_session_id(0);
  absl::Status s = device->Apply(d);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << s;
  EXPECT_NE(s.message().find("session 0"), std::string::npos) << s;
  EXPECT_TRUE(device->Apply(scene_).ok());
  d = scene_;
  d.set_session_id(scene_.session_id() + 1);
  d.set_sequence(scene_.sequence() + 1);
  EXPECT_EQ(device->Apply(d).code(), absl::StatusCode::kFailedPrecondition);
}

// Tile origins and sizes are 64-bit on the wire and launch indices 32-bit: an origin of 2^32 ran
// row 0, a size of 2^32 + 1 ran one column.
TEST_F(ReplicaFuzz, TileBeyondThirtyTwoBitsIsClippedNotWrapped) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::LaunchRequest request = ValidRequest(0, 1);
  request.clear_tiles();
  v1::Tile* outside = request.add_tiles();
  outside->add_origin(0);
  outside->add_origin(uint64_t{1} << 32);
  outside->add_size(4);
  outside->add_size(4);
  v1::Tile* wide = request.add_tiles();
  wide->set_index(1);
  wide->add_origin(4);
  wide->add_origin(0);
  wide->add_size((uint64_t{1} << 32) + 1);
  wide->add_size(2);
  LaunchOutcome out = RunLaunch(*device, request);
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_EQ(out.written, (std::set<uint64_t>{4, 5, 6, 7, 12, 13, 14, 15}));
}

TEST_F(ReplicaFuzz, TileOfAnotherDimensionalityIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::LaunchRequest request = ValidRequest(0, 1);
  request.mutable_tiles(2)->mutable_origin()->RemoveLast();
  request.mutable_tiles(2)->mutable_size()->RemoveLast();
  LaunchOutcome out = RunLaunch(*device, request);
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument) << out.status;
  EXPECT_NE(out.status.message().find("tile 2 has 1 origin"), std::string::npos) << out.status;
  EXPECT_TRUE(out.written.empty());
}

// Every level of rtTrace takes native stack: a large stack size let programs nest until a thread's
// stack ran out (SIGSEGV near 12,000 levels), and 2^40 bytes asked for 2^33 frames (length_error
// escaped Launch).
TEST_F(ReplicaFuzz, StackSizeNestsNoDeeperThanTheDeviceLimit) {
  v1::StateDelta d = scene_;
  d.mutable_context()->set_stack_size(uint64_t{1} << 40);
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == reference_[1]);

  // A sphere every 3 units along the camera rays, each hit tracing on: 16,000 levels.
  ObjectById(d, kClosestHit)->mutable_program()->set_function("recursive_hit");
  const int depth = 16000;
  AddValue(d.mutable_context()->mutable_variables(), "max_depth", RT_OBJECTTYPE_INT, &depth, 4);
  v1::GeometryInstance base = ObjectById(d, kInstance)->geometry_instance();
  v1::GeometryGroup* gg = ObjectById(d, kGeometryGroup)->mutable_geometry_group();
  for (int k = 1; k <= depth / 2; ++k) {
    v1::GeometryInstance* gi = d.add_objects()->mutable_geometry_instance();
    *gi = base;
    gi->set_id(1000 + k);
    const float sphere[4] = {0, 0, 3.f * k, 1};
    AddValue(gi->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, sphere, sizeof(sphere));
    gg->add_children(gi->id());
  }
  device = DeviceWith(d);
  out = RunLaunch(*device, ValidRequest(1, 1), std::chrono::seconds(60));
  ASSERT_TRUE(out.status.ok()) << out.status;
  const float* center =
      reinterpret_cast<const float*>(out.output.data()) + 4 * (kHeight / 2 * kWidth + kWidth / 2);
  EXPECT_EQ(center[0], float(RT_EXCEPTION_STACK_OVERFLOW));
}

// Buffer storage was allocated while the delta was being applied: std::bad_alloc escaped Apply
// with the sequence taken and the objects before the buffer applied.
TEST_F(ReplicaFuzz, BufferTooLargeForTheDeviceIsRejectedAndTheStateKept) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  ObjectById(bad, kOutput)->mutable_buffer()->set_dims(0, 0xFFFFFFFFu);
  ExpectRejected(*device, bad, absl::StatusCode::kResourceExhausted, "buffer #2", reference_[1],
                 scene_);
}

// The chunk passed the bounds check against the buffer the device held, then the delta removed
// that buffer and the copy went into an empty one (SIGSEGV).
TEST_F(ReplicaFuzz, ChunkForABufferTheDeltaRemovesIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  bad.add_removed(kInput);
  EraseObject(bad, kInput);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "buffer #17", reference_[1],
                 scene_);
  // Buffers the delta removes and sends again start afresh and take their chunks.
  v1::StateDelta again = SecondDelta(scene_);
  again.set_sequence(3);
  again.add_removed(kInput);
  again.add_removed(kOutput);
  ASSERT_TRUE(device->Apply(again).ok());
  EXPECT_TRUE(RunLaunch(*device, ValidRequest(0, 1)).output == reference_[0]);
}

// dlsym finds the module's dependencies' symbols and its data too: a program named `getpid` ran
// libc's, `close` closed a file descriptor of the process, `output` jumped into data (SIGSEGV).
TEST_F(ReplicaFuzz, ProgramsAreOnlyGlobalFunctionsOfTheModule) {
  for (const char* function :
       {"getpid", "output", "tessera_module_init", "_ZN5optix6bufferI6float4Li2EEC1Ev"}) {
    v1::StateDelta d = scene_;
    ObjectById(d, kWriteIndex)->mutable_program()->set_function(function);
    std::unique_ptr<Device> device = DeviceWith(d);
    LaunchOutcome out = RunLaunch(*device, ValidRequest(0, 1));
    EXPECT_EQ(out.status.code(), absl::StatusCode::kNotFound) << function << ": " << out.status;
    EXPECT_NE(out.status.message().find(absl::StrCat("'", function, "'")), std::string::npos)
        << out.status;
  }
}

// A scene kept from the last plan was reused without checking its geometries' programs: with the
// intersection program gone, traversal called through a null program (SIGSEGV).
TEST_F(ReplicaFuzz, KeptSceneWhoseGeometryLostItsIntersectionProgramFailsTheLaunch) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  ASSERT_TRUE(RunLaunch(*device, ValidRequest(1, 1)).status.ok());
  v1::StateDelta d = SecondDelta(scene_);
  ObjectById(d, kGeometry)->mutable_geometry()->set_intersection_program(0);
  ASSERT_TRUE(device->Apply(d).ok());
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 2));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kFailedPrecondition) << out.status;
  EXPECT_NE(out.status.message().find("geometry #9"), std::string::npos) << out.status;
}

// Scenes of destroyed nodes stayed in the scene cache for the device's life (ids are never
// reused): a host that replaced its GeometryGroup every launch grew by its BVH every launch.
TEST_F(ReplicaFuzz, ScenesOfRemovedNodesLeaveTheCache) {
  worker::Replica replica;
  ASSERT_TRUE(replica.Apply(scene_).ok());
  RTCDevice embree = rtcNewDevice(nullptr);
  {
    worker::SceneCache scenes(embree);
    auto plan = worker::MakePlan(replica, scenes);
    ASSERT_TRUE(plan.ok()) << plan.status();
    ASSERT_NE(scenes.Find(kTriangleGroup), nullptr);
    plan->reset();
    // The group drops the triangles' GeometryGroup, and the delta removes it.
    v1::StateDelta d;
    d.set_session_id(scene_.session_id());
    d.set_sequence(2);
    *d.mutable_context() = scene_.context();
    for (const v1::Object& o : scene_.objects()) {
      if (o.has_group() && o.group().id() == kGroup) {
        v1::Group* g = d.add_objects()->mutable_group();
        *g = o.group();
        g->set_version(2);
        g->mutable_children()->RemoveLast();
      }
    }
    for (uint64_t id : {kTriangleGroup, kTriangleInstance, kTriangleAccel}) d.add_removed(id);
    ASSERT_TRUE(replica.Apply(d).ok());
    plan = worker::MakePlan(replica, scenes);
    ASSERT_TRUE(plan.ok()) << plan.status();
    EXPECT_EQ(scenes.Find(kTriangleGroup), nullptr);
    EXPECT_NE(scenes.Find(kGeometryGroup), nullptr);
  }
  rtcReleaseDevice(embree);
}

// The plan gave every material a hit group per ray type of the context: 2^31 ray types threw
// std::bad_alloc out of Launch.
TEST_F(ReplicaFuzz, RayTypeCountCostsNothingPastTheMaterialsPrograms) {
  v1::StateDelta d = scene_;
  d.mutable_context()->set_ray_type_count(1u << 31);
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == reference_[1]);
}

// primitive_count * 6 bounds overflowed (std::length_error escaped Launch); Embree counts
// primitives in 32 bits.
TEST_F(ReplicaFuzz, PrimitiveCountPastThirtyTwoBitsIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  for (uint64_t count : {uint64_t{1} << 32, ~uint64_t{0}}) {
    v1::StateDelta bad = SecondDelta(scene_);
    ObjectById(bad, kGeometry)->mutable_geometry()->set_primitive_count(count);
    ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "geometry #9", reference_[1],
                   scene_);
    device = DeviceWith(scene_);
  }
}

// Ids name objects for references and removals; one id for two kinds of object, or id 0 (none),
// is an inconsistent delta.
TEST_F(ReplicaFuzz, OneIdNamesOneObject) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  ObjectById(bad, kInput)->mutable_buffer()->set_id(kCamera);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument,
                 "buffer #3 has the id of a program", reference_[1], scene_);
  device = DeviceWith(scene_);
  bad = SecondDelta(scene_);
  ObjectById(bad, kGroup)->mutable_group()->set_id(0);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "group with id 0", reference_[1],
                 scene_);
  // The same id as another kind is fine once the delta removes the old object.
  device = DeviceWith(scene_);
  v1::StateDelta reuse = SecondDelta(scene_);
  EraseObject(reuse, kMiss);
  ObjectById(reuse, kInput)->mutable_buffer()->set_id(kMiss);
  reuse.add_removed(kMiss);
  reuse.mutable_context()->clear_miss();
  reuse.clear_chunks();
  const absl::Status reused = device->Apply(reuse);
  EXPECT_TRUE(reused.ok()) << reused;
}

// Scenes stay cached across plans, pointing into the plan that built or checked them; a node that
// no object variable reaches is not checked, and a program that traced it anyway (its id passed
// as a plain 8-byte value) used the freed plan of an earlier launch. Now an rtObject takes only a
// graph node: the 8-byte value is refused when the program is bound.
TEST_F(ReplicaFuzz, NodeNoObjectVariableReachesIsNotTraced) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  ASSERT_TRUE(RunLaunch(*device, ValidRequest(1, 1)).status.ok());
  v1::StateDelta d = SecondDelta(scene_);
  for (v1::Variable& v : *d.mutable_context()->mutable_variables()) {
    if (v.name() != "top_object") continue;
    const uint64_t id = kGroup;
    v.set_type(RT_OBJECTTYPE_USER);
    v.set_object_id(0);
    v.set_data(&id, sizeof(id));
  }
  ASSERT_TRUE(device->Apply(d).ok());
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 2));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument) << out.status;
  EXPECT_NE(out.status.message().find("declared as rtObject but was set as user data"),
            std::string::npos)
      << out.status;
}

// The message read the offending index from Embree's index buffer after releasing the geometry
// that held it (heap-use-after-free: it named a vertex no buffer had).
TEST_F(ReplicaFuzz, TriangleUsingAVertexPastTheVertexBufferNamesIt) {
  v1::StateDelta d = scene_;
  (*ObjectById(d, kTriangleAccel)
        ->mutable_acceleration()
        ->mutable_properties())["vertex_buffer_name"] =
      "indices";  // one "vertex" of 12 bytes: the indices 0, 1, 2
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kOutOfRange) << out.status;
  EXPECT_NE(out.status.message().find("geometry instance #21: triangle 0 uses vertex 1 but the "
                                      "vertex buffer holds 1"),
            std::string::npos)
      << out.status;
}

// std::stoul threw std::invalid_argument out of Launch for a stride property that is no number.
TEST_F(ReplicaFuzz, StridePropertyThatIsNoNumberFailsTheLaunch) {
  v1::StateDelta d = scene_;
  (*ObjectById(d, kTriangleAccel)
        ->mutable_acceleration()
        ->mutable_properties())["vertex_buffer_stride"] = "twelve";
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument) << out.status;
  EXPECT_NE(out.status.message().find("acceleration #22"), std::string::npos) << out.status;
  EXPECT_NE(out.status.message().find("vertex_buffer_stride"), std::string::npos) << out.status;
}

// Triangles the index buffer cannot hold (a stride or a primitive count past it) were dropped
// silently, so the image changed with the builder: now the launch fails naming the property and
// the buffer.
TEST_F(ReplicaFuzz, IndexStridePastTheIndexBufferFailsTheLaunch) {
  v1::StateDelta d = scene_;
  (*ObjectById(d, kTriangleAccel)
        ->mutable_acceleration()
        ->mutable_properties())["index_buffer_stride"] = "4096";
  ObjectById(d, kTriangleGeometry)->mutable_geometry()->set_primitive_count(2);  // 1 triangle held
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kOutOfRange) << out.status;
  EXPECT_NE(out.status.message().find("index_buffer_stride"), std::string::npos) << out.status;
  EXPECT_NE(out.status.message().find("do not fit index buffer #"), std::string::npos)
      << out.status;
}

}  // namespace
}  // namespace tessera::fuzz
