// Built-in triangles (v1::TriangleMesh) in malformed deltas: unknown buffers, bad formats, counts,
// offsets and strides that do not fit, whatever their size. Each launch fails with a status that
// names the geometry, nothing crashes or hangs.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "tessera/rt.h"
#include "tessera/worker/inproc_device.h"
#include "testdata/replica_fuzz_scene.h"

namespace tessera::fuzz {
namespace {

// The fuzz scene with its triangle geometry as built-in triangles on the same buffers.
v1::StateDelta BuiltinScene() {
  v1::StateDelta d = SceneDelta();
  v1::Geometry* g = ObjectById(d, kTriangleGeometry)->mutable_geometry();
  g->set_intersection_program(0);
  g->set_bounding_box_program(0);
  v1::TriangleMesh* m = g->mutable_triangles();
  m->set_vertex_buffer(kVertices);
  m->set_vertex_count(3);
  m->set_vertex_stride(12);
  m->set_vertex_format(RT_FORMAT_FLOAT3);
  m->set_index_buffer(kIndices);
  m->set_index_stride(12);
  m->set_index_format(RT_FORMAT_UNSIGNED_INT3);
  m->set_material_count(1);
  return d;
}

class TrianglesReplica : public ::testing::Test {
 protected:
  // Launches the scene changed by `change`: the launch must end with an error holding `names`.
  void ExpectFails(const std::function<void(v1::TriangleMesh&)>& change, const std::string& names) {
    SCOPED_TRACE(::testing::Message() << "case " << ++case_);
    v1::StateDelta d = BuiltinScene();
    change(*ObjectById(d, kTriangleGeometry)->mutable_geometry()->mutable_triangles());
    std::unique_ptr<Device> device = DeviceWith(d);
    ASSERT_NE(device, nullptr);
    LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
    EXPECT_FALSE(out.timed_out);
    EXPECT_FALSE(out.status.ok());
    EXPECT_NE(out.status.message().find(names), std::string::npos) << out.status;
  }
  int case_ = 0;
};

TEST_F(TrianglesReplica, ValidSceneRenders) {
  std::unique_ptr<Device> device = DeviceWith(BuiltinScene());
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_TRUE(out.status.ok()) << out.status;
}

TEST_F(TrianglesReplica, MalformedMeshesFailByName) {
  const uint64_t big = ~uint64_t{0};
  const std::string what = absl::StrCat("geometry triangles #", uint64_t{kTriangleGeometry});
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_buffer(999); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_buffer(0); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_buffer(kCamera); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_index_buffer(999); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_format(RT_FORMAT_INT3); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_index_format(RT_FORMAT_FLOAT3); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_count(uint64_t{1} << 60); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_count(big); }, what);
  ExpectFails([&](v1::TriangleMesh& m) { m.set_vertex_offset(big); }, what);
  ExpectFails([&](v1::TriangleMesh& m) { m.set_vertex_stride(big); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_stride(4); }, what);
  ExpectFails([&](v1::TriangleMesh& m) { m.set_index_offset(big - 4); }, what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_vertex_count(2); }, what);
  ExpectFails(
      [](v1::TriangleMesh& m) {
        m.set_index_buffer(0);
        m.set_vertex_count(2);
      },
      what);
  ExpectFails([](v1::TriangleMesh& m) { m.set_material_index_buffer(999); }, what);
  ExpectFails(
      [](v1::TriangleMesh& m) {
        m.set_material_index_buffer(kIndices);
        m.set_material_index_format(RT_FORMAT_FLOAT);
      },
      what);
  ExpectFails(
      [&](v1::TriangleMesh& m) {
        m.set_material_index_buffer(kIndices);
        m.set_material_index_format(RT_FORMAT_UNSIGNED_INT);
        m.set_material_index_offset(big);
      },
      what);
  ExpectFails(
      [&](v1::TriangleMesh& m) {
        m.set_material_index_buffer(kIndices);
        m.set_material_index_format(RT_FORMAT_UNSIGNED_INT);
        m.set_material_index_offset(4);  // index 1: the instance has one material
      },
      "material index 1");
  ExpectFails([](v1::TriangleMesh& m) { m.set_attribute_program(999); }, "attribute program");
}

}  // namespace
}  // namespace tessera::fuzz
