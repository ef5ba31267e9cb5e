// An invariant of docs/devices.md: for programs that depend only on their inputs
// and launch index, every output buffer is bit-identical for 1..7 devices, in-process or worker
// processes or both, for any tile size, and for 1D, 2D and 3D launches.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "multi_device_fixture.h"

namespace tessera::testing {
namespace {

constexpr size_t kN1 = 301;                   // 1D
constexpr size_t kW2 = 37, kH2 = 29;          // 2D
constexpr size_t kW3 = 11, kH3 = 7, kD3 = 5;  // 3D

// The buffers of one device set and tile size, as bytes.
struct Outputs {
  std::string det1, det2, det3, acc;
};

class DeterminismTest : public MultiDeviceFixture {
 protected:
  // Spheres on a 3x3 grid in front of the camera, with reflections between them.
  void BuildScene() {
    RTbuffer spheres = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, {9}, "spheres");
    std::vector<Float4> s;
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 3; ++x) {
        s.push_back({(x - 1) * 0.9f, (y - 1) * 0.9f, 3.f + 0.37f * ((x + 2 * y) % 3), 0.42f});
      }
    }
    Write(spheres, s);
    Instance i = MakeInstance(Program("sphere_intersect"), Program("sphere_bounds"), 9,
                              Program("shade_reflect"));
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("miss_sky")));
    det1_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kN1}, "det1");
    det2_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kW2, kH2}, "det2");
    det3_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kW3, kH3, kD3}, "det3");
    acc_ = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_FLOAT4, {kW2, kH2}, "det_acc");
    det_1d_ = Program("det_1d");
    det_2d_ = Program("det_2d");
    det_3d_ = Program("det_3d");
  }

  std::string Bytes(RTbuffer b) {
    std::vector<Float4> v = Contents<Float4>(b);
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(Float4));
  }

  // A 1D, two 2D (the second accumulates onto the first) and a 3D launch.
  Outputs Run() {
    Write(acc_, std::vector<Float4>(kW2 * kH2, Float4{0.f, 0.f, 0.f, 0.f}));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, det_1d_));
    Launch1D(kN1);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, det_2d_));
    Launch2D(kW2, kH2);
    Launch2D(kW2, kH2);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, det_3d_));
    Launch3D(kW3, kH3, kD3);
    return {Bytes(det1_), Bytes(det2_), Bytes(det3_), Bytes(acc_)};
  }

  RTbuffer det1_ = nullptr, det2_ = nullptr, det3_ = nullptr, acc_ = nullptr;
  RTprogram det_1d_ = nullptr, det_2d_ = nullptr, det_3d_ = nullptr;
};

// Checks that `bytes` (float4 elements) are finite and show both hits (t > 0) and misses.
void ExpectAScene(const std::string& bytes, const char* what) {
  std::vector<Float4> v(bytes.size() / sizeof(Float4));
  std::memcpy(v.data(), bytes.data(), bytes.size());
  size_t hits = 0;
  for (const Float4& p : v) {
    for (float f : p) ASSERT_TRUE(std::isfinite(f)) << what;
    hits += p[3] > 1.f;
  }
  EXPECT_GT(hits, v.size() / 20) << what;
  EXPECT_LT(hits, v.size() - v.size() / 20) << what;
}

TEST_F(DeterminismTest, BitIdenticalForEveryDeviceSetTileSizeAndDimensionality) {
  const char* const kSpecs[] = {"inproc",  "local:1", "local:2",       "local:3",
                                "local:4", "local:7", "inproc,local:2"};
  const std::vector<std::vector<RTsize>> kTileSizes = {{}, {1, 1}, {7, 5}, {16, 16}};
  auto tile_name = [](const std::vector<RTsize>& t) {
    return t.empty() ? std::string("automatic") : std::to_string(t[0]) + "x" + std::to_string(t[1]);
  };
  Outputs reference;
  bool have_reference = false;
  for (const char* spec : kSpecs) {
    UseDevices(spec);
    BuildScene();
    for (const std::vector<RTsize>& tile : kTileSizes) {
      SCOPED_TRACE(std::string(spec) + ", tiles " + tile_name(tile));
      TileSize(tile);
      Outputs out = Run();
      if (HasFatalFailure()) return;
      if (!have_reference) {  // inproc, automatic tiles
        reference = out;
        have_reference = true;
        ExpectAScene(reference.det1, "1D");
        ExpectAScene(reference.det2, "2D");
        ExpectAScene(reference.det3, "3D");
        ASSERT_NE(reference.acc, reference.det2) << "the accumulator holds two launches";
        continue;
      }
      // Byte comparisons: a mismatch prints sizes, not 20 KiB of bytes.
      EXPECT_TRUE(out.det1 == reference.det1) << "1D output differs";
      EXPECT_TRUE(out.det2 == reference.det2) << "2D output differs";
      EXPECT_TRUE(out.det3 == reference.det3) << "3D output differs";
      EXPECT_TRUE(out.acc == reference.acc) << "2D INPUT_OUTPUT accumulator differs";
    }
  }
}

}  // namespace
}  // namespace tessera::testing
