// Acceleration data caching (OptiX 3 guide 3.6.5, docs/acceleration_data.md): a build's data read
// with rtAccelerationGetData and restored with rtAccelerationSetData in a later context renders
// the same image without running the bounding-box programs again, on an in-process device and on
// 1 and 3 worker processes; bad or foreign data is refused and changes nothing.
#include <cstdint>
#include <string>
#include <vector>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "semantics_programs";
constexpr unsigned kW = 32;

class AccelerationDataTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    OnDevicesFixture::SetUp();
    Prepare();
  }

  // A fresh context on `spec`, as a later run of the application would have.
  void NewContext(const char* spec) {
    rtContextDestroy(ctx_);
    ASSERT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    Prepare();
  }

  void Prepare() {
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, kW);
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT_OUTPUT, &calls_));
    Ok(rtBufferSetFormat(calls_, RT_FORMAT_UNSIGNED_INT));
    Ok(rtBufferSetSize1D(calls_, 1));
    Ok(rtVariableSetObject(ContextVar("bounds_calls"), calls_));
    SetCalls(0);
    // Rays start at (x, y, -10), one per launch index, and go toward +z.
    Ok(rtVariableSet3f(ContextVar("ray_origin"), 0.f, 0.f, -10.f));
    Ok(rtVariableSet3f(ContextVar("ray_dir"), 0.f, 0.f, 1.f));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_camera")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_ray")));
  }

  void SetCalls(unsigned n) {
    void* p = nullptr;
    Ok(rtBufferMap(calls_, &p));
    *static_cast<unsigned*>(p) = n;
    Ok(rtBufferUnmap(calls_));
  }
  unsigned Calls() {
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(calls_, &p), RT_SUCCESS);
    const unsigned n = p != nullptr ? *static_cast<unsigned*>(p) : 0;
    EXPECT_EQ(rtBufferUnmap(calls_), RT_SUCCESS);
    return n;
  }

  // A GeometryGroup of one mesh of `triangles` overlapping triangles at many depths over the
  // launch grid (user geometry: intersection and counted bounding-box programs), as the top
  // object. `seed` varies their places.
  RTacceleration Mesh(unsigned triangles, uint32_t seed, const char* builder = "Bvh") {
    uint32_t state = seed;
    auto next = [&state] {
      state = state * 1664525u + 1013904223u;
      return static_cast<float>(state >> 8) / 16777216.f;  // [0, 1)
    };
    RTbuffer vertices = nullptr, indices = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &vertices));
    Ok(rtBufferSetFormat(vertices, RT_FORMAT_FLOAT3));
    Ok(rtBufferSetSize1D(vertices, 3 * triangles));
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &indices));
    Ok(rtBufferSetFormat(indices, RT_FORMAT_INT3));
    Ok(rtBufferSetSize1D(indices, triangles));
    void* pv = nullptr;
    void* pi = nullptr;
    Ok(rtBufferMap(vertices, &pv));
    Ok(rtBufferMap(indices, &pi));
    auto* v = static_cast<float*>(pv);
    auto* idx = static_cast<int*>(pi);
    for (unsigned t = 0; t < triangles; ++t) {
      const float x = next() * kW, y = next() * kW, z = next() * 8.f, s = 1.f + next() * 6.f;
      const float corners[3][3] = {{x, y, z}, {x + s, y, z + next()}, {x, y + s, z - next()}};
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) v[(3 * t + c) * 3 + k] = corners[c][k];
        idx[3 * t + c] = static_cast<int>(3 * t + c);
      }
    }
    Ok(rtBufferUnmap(vertices));
    Ok(rtBufferUnmap(indices));
    Instance i =
        MakeInstance(Program(kModule, "mesh_intersect"), Program(kModule, "counted_mesh_bounds"),
                     triangles, Program(kModule, "closest_hit_count"));
    RTvariable var = nullptr;
    Ok(rtGeometryDeclareVariable(i.geometry, "vertex_buffer", &var));
    Ok(rtVariableSetObject(var, vertices));
    Ok(rtGeometryDeclareVariable(i.geometry, "index_buffer", &var));
    Ok(rtVariableSetObject(var, indices));
    RTacceleration accel = nullptr;
    Ok(rtGeometryGroupGetAcceleration(i.group, &accel));
    Ok(rtAccelerationSetBuilder(accel, builder));
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    group_ = i.group;
    return accel;
  }

  std::vector<Float4> Render() {
    const RTresult code = rtContextLaunch2D(ctx_, 0, kW, kW);
    EXPECT_EQ(code, RT_SUCCESS) << Error(code);
    return Read(result_);
  }

  std::string GetData(RTacceleration accel) {
    RTsize size = 0;
    const RTresult code = rtAccelerationGetDataSize(accel, &size);
    EXPECT_EQ(code, RT_SUCCESS) << Error(code);
    std::string bytes(size, '\0');
    if (size > 0) Ok(rtAccelerationGetData(accel, bytes.data()));
    return bytes;
  }

  int Dirty(RTacceleration accel) {
    int dirty = -1;
    EXPECT_EQ(rtAccelerationIsDirty(accel, &dirty), RT_SUCCESS);
    return dirty;
  }

  std::string Builder(RTacceleration accel) {
    const char* s = nullptr;
    EXPECT_EQ(rtAccelerationGetBuilder(accel, &s), RT_SUCCESS);
    return s != nullptr ? s : "";
  }

  // Same bits, not only equal floats.
  static bool SameBits(const std::vector<Float4>& a, const std::vector<Float4>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Float4)) == 0;
  }

  // Hits that are not all the same: the image tells the primitives apart.
  static int Hits(const std::vector<Float4>& image) {
    int hits = 0;
    for (const Float4& p : image) hits += p[0] > 0.f ? 1 : 0;
    return hits;
  }

  RTbuffer result_ = nullptr;
  RTbuffer calls_ = nullptr;
  RTgeometrygroup group_ = nullptr;
};

// Saved from an in-process build, restored on this test's devices: the bounding-box program does
// not run, the builder, traverser and properties come back, and the image and the data read back
// are bit for bit those of the fresh build.
TEST_P(AccelerationDataTest, RestoredDataRendersTheSameWithoutBoundsPrograms) {
  NewContext("inproc");
  RTacceleration accel = Mesh(300, 7, "Lbvh");
  Ok(rtAccelerationSetTraverser(accel, "BvhCompact"));
  Ok(rtAccelerationSetProperty(accel, "refine", "2"));
  EXPECT_EQ(Dirty(accel), 1);
  Ok(rtContextLaunch1D(ctx_, 0, 0));  // builds without tracing (guide 3.6.5)
  EXPECT_EQ(Dirty(accel), 0);
  EXPECT_EQ(Calls(), 300u);
  const std::string saved = GetData(accel);
  ASSERT_GT(saved.size(), 300u * 24);
  const std::vector<Float4> fresh = Render();
  EXPECT_GT(Hits(fresh), 100);

  NewContext(GetParam());
  accel = Mesh(300, 7);  // Bvh / Bvh, no properties
  Ok(rtAccelerationSetData(accel, saved.data(), saved.size()));
  EXPECT_EQ(Dirty(accel), 0);
  EXPECT_EQ(Builder(accel), "Lbvh");
  const char* s = nullptr;
  Ok(rtAccelerationGetTraverser(accel, &s));
  EXPECT_STREQ(s, "BvhCompact");
  Ok(rtAccelerationGetProperty(accel, "refine", &s));
  EXPECT_STREQ(s, "2");
  EXPECT_TRUE(SameBits(Render(), fresh));
  EXPECT_EQ(Calls(), 0u);  // the restored bounds stood in for the program
  EXPECT_EQ(GetData(accel), saved);
  // Marked dirty, it is built as usual again.
  Ok(rtAccelerationMarkDirty(accel));
  EXPECT_TRUE(SameBits(Render(), fresh));
  EXPECT_GT(Calls(), 0u);
  EXPECT_EQ(GetData(accel), saved);  // the bounds the programs gave are the saved ones
}

TEST_P(AccelerationDataTest, DirtyAccelerationsHaveNoData) {
  RTacceleration accel = Mesh(20, 3);
  RTsize size = 0;
  RTresult code = rtAccelerationGetDataSize(accel, &size);
  EXPECT_EQ(code, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(code).find("is dirty"), std::string::npos) << Error(code);
  EXPECT_NE(Error(code).find("rtContextLaunch1D(context, 0, 0)"), std::string::npos);
  char byte = 0;
  EXPECT_EQ(rtAccelerationGetData(accel, &byte), RT_ERROR_INVALID_VALUE);
  Ok(rtContextLaunch1D(ctx_, 0, 0));
  EXPECT_FALSE(GetData(accel).empty());
  Ok(rtAccelerationMarkDirty(accel));
  EXPECT_EQ(rtAccelerationGetDataSize(accel, &size), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(rtAccelerationGetData(accel, nullptr), RT_ERROR_INVALID_VALUE);
}

// Truncated, corrupted, another format version, garbage, null: refused with a message saying
// which, the acceleration left as it was; the guide's fallback (mark dirty) then builds it.
TEST_P(AccelerationDataTest, BadDataIsRefusedAndChangesNothing) {
  RTacceleration accel = Mesh(40, 5);
  Ok(rtContextLaunch1D(ctx_, 0, 0));
  const std::string good = GetData(accel);
  const std::vector<Float4> fresh = Render();
  ASSERT_GT(good.size(), 40u);

  NewContext(GetParam());
  accel = Mesh(40, 5, "MedianBvh");
  std::string corrupt = good;
  corrupt[good.size() - 100] ^= 0x10;
  std::string version = good;
  version[8] = 9;
  const struct {
    std::string bytes;
    const char* says;
  } cases[] = {{good.substr(0, good.size() - 3), "truncated"},
               {corrupt, "checksum"},
               {version, "format version 9"},
               {std::string(64, 'x'), "magic"}};
  for (const auto& c : cases) {
    const RTresult code = rtAccelerationSetData(accel, c.bytes.data(), c.bytes.size());
    EXPECT_EQ(code, RT_ERROR_INVALID_VALUE) << c.says;
    EXPECT_NE(Error(code).find(c.says), std::string::npos) << Error(code);
    EXPECT_EQ(Dirty(accel), 1) << c.says;
    EXPECT_EQ(Builder(accel), "MedianBvh") << c.says;
  }
  EXPECT_EQ(rtAccelerationSetData(accel, nullptr, 16), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(Dirty(accel), 1);
  if (rtAccelerationSetData(accel, corrupt.data(), corrupt.size()) != RT_SUCCESS) {
    Ok(rtAccelerationMarkDirty(accel));
  }
  EXPECT_TRUE(SameBits(Render(), fresh));
  EXPECT_EQ(Calls(), 40u * 1);
}

// Data restored over other geometry (more primitives) is taken, but the launch finds it was not
// built over this graph: it says so once and builds as usual, with the right image.
TEST_P(AccelerationDataTest, DataOfOtherGeometryIsRebuiltWithAMessage) {
  RTacceleration accel = Mesh(50, 11);
  Ok(rtContextLaunch1D(ctx_, 0, 0));
  const std::string other = GetData(accel);

  NewContext(GetParam());
  accel = Mesh(60, 12);
  const std::vector<Float4> fresh = Render();
  NewContext(GetParam());
  accel = Mesh(60, 12);
  Ok(rtAccelerationSetData(accel, other.data(), other.size()));
  EXPECT_EQ(Dirty(accel), 0);
  ::testing::internal::CaptureStderr();
  const std::vector<Float4> first = Render();
  const std::vector<Float4> second = Render();
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(SameBits(first, fresh));
  EXPECT_TRUE(SameBits(second, fresh));
  EXPECT_GT(Calls(), 0u);
  const std::string line = "was not built over the graph it is on";
  ASSERT_NE(said.find(line), std::string::npos) << said;
  EXPECT_EQ(said.find(line, said.find(line) + 1), std::string::npos) << "said twice: " << said;
  EXPECT_NE(said.find("had 50 primitives, now 60"), std::string::npos) << said;
}

// A Group's data holds its settings and children (no bounds: its build is over its children's
// boxes) and restores like any other.
TEST_P(AccelerationDataTest, GroupDataRestoresItsSettings) {
  Mesh(10, 2);
  RTgroup top = nullptr;
  Ok(rtGroupCreate(ctx_, &top));
  RTacceleration accel = Accel("NoAccel");
  Ok(rtGroupSetAcceleration(top, accel));
  Ok(rtGroupSetChildCount(top, 1));
  Ok(rtGroupSetChild(top, 0, group_));
  Ok(rtVariableSetObject(ContextVar("top_object"), top));
  Ok(rtContextLaunch1D(ctx_, 0, 0));
  const std::vector<Float4> fresh = Render();
  const std::string saved = GetData(accel);
  ASSERT_FALSE(saved.empty());
  RTacceleration other = Accel("Bvh");
  Ok(rtGroupSetAcceleration(top, other));
  Ok(rtAccelerationSetData(other, saved.data(), saved.size()));
  EXPECT_EQ(Dirty(other), 0);
  EXPECT_EQ(Builder(other), "NoAccel");
  EXPECT_TRUE(SameBits(Render(), fresh));
}

INSTANTIATE_TEST_SUITE_P(Devices, AccelerationDataTest,
                         ::testing::Values("inproc", "local:1", "local:3"), DeviceName);

}  // namespace
}  // namespace tessera::testing
