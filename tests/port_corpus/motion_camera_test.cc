// The motion camera (motion_camera.cu) over the corpus's sphere scene (sphere.cu, materials.cu):
// rendered on inproc, local:1 and local:3, and each pixel's average checked against the samples
// the host says it took: the times from the shared tea/rnd (sample_common.h), each rendered alone
// with a shutter that opens and closes at that time.
#include <optix.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "port_corpus_fixture.h"
#include "sample_common.h"

namespace tessera::testing {
namespace {

using optix::float3;
using optix::make_float3;

constexpr unsigned kWidth = 64, kHeight = 48, kSamples = 4, kFrame = 7;
const float3 kEyeBegin = make_float3(-0.5f, 0.5f, -4.f), kEyeEnd = make_float3(0.5f, 0.5f, -4.f);

// The times motion_camera.cu gives the samples of pixel (x, y), computed by the same functions.
std::array<float, kSamples> SampleTimes(unsigned x, unsigned y, float begin, float end) {
  unsigned int seed = tea<16>(kWidth * y + x, kFrame);
  std::array<float, kSamples> times;
  for (float& t : times) t = begin + (end - begin) * rnd(seed);
  return times;
}

bool SameBits(const float3& a, const Float4& b) {
  return std::memcmp(&a.x, &b[0], sizeof(float)) == 0 &&
         std::memcmp(&a.y, &b[1], sizeof(float)) == 0 &&
         std::memcmp(&a.z, &b[2], sizeof(float)) == 0;
}

class MotionCameraTest : public PortCorpusTest {
 protected:
  // A unit sphere on a ground sphere with the corpus's Phong-like material and shadow rays, seen
  // by the motion camera moving from kEyeBegin (time 0) to kEyeEnd (time 1).
  void BuildScene(const char* spec) {
    UseDevices(spec, 2);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("motion_camera", "motion_camera")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("materials", "miss")));
    Spheres({{0.f, 0.f, 0.f, 1.f}, {0.f, -101.f, 0.f, 100.f}});
    Instance i = MakeInstance(Program("sphere", "intersect"), Program("sphere", "bounds"), 2,
                              Program("materials", "closest_hit_radiance"));
    Ok(rtMaterialSetAnyHitProgram(i.material, 1, Program("materials", "any_hit_shadow")));
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    Ok(rtVariableSetObject(ContextVar("top_shadower"), i.group));
    SetFloat3(ContextVar("eye_begin"), kEyeBegin);
    SetFloat3(ContextVar("eye_end"), kEyeEnd);
    SetFloat3("U", 0.5f, 0.f, 0.f);
    SetFloat3("V", 0.f, 0.375f, 0.f);
    SetFloat3("W", 0.f, -0.125f, 1.f);
    SetFloat3("light_pos", 3.f, 5.f, -3.f);
    SetFloat3("Kd", 0.7f, 0.5f, 0.3f);
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 1e-3f));
    Ok(rtVariableSet1ui(ContextVar("radiance_ray_type"), 0));
    Ok(rtVariableSet1ui(ContextVar("shadow_ray_type"), 1));
    Ok(rtVariableSet1ui(ContextVar("frame"), kFrame));
    accum_ = Float4Buffer("accum_buffer", RT_BUFFER_OUTPUT, kWidth, kHeight);
    output_ =
        Buffer2D("output_buffer", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE4, kWidth, kHeight);
  }
  // Launches with the shutter open over [begin, end] and `samples` samples a pixel; returns the
  // accumulation buffer and the output bytes.
  std::pair<std::vector<Float4>, std::vector<std::uint32_t>> Launch(float begin, float end,
                                                                    unsigned samples) {
    Ok(rtVariableSet1f(ContextVar("time_begin"), begin));
    Ok(rtVariableSet1f(ContextVar("time_end"), end));
    Ok(rtVariableSet1ui(ContextVar("samples_per_launch"), samples));
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    return {Read(accum_), ReadAs<std::uint32_t>(output_)};
  }

  RTbuffer accum_ = nullptr, output_ = nullptr;
};

TEST_F(MotionCameraTest, EachPixelAveragesTheSamplesAtItsOwnTimes) {
  const auto motion = OnEveryDeviceSet([&](const char* spec) {
    BuildScene(spec);
    return Launch(0.f, 1.f, kSamples);
  });
  ASSERT_EQ(motion.first.size(), size_t{kWidth} * kHeight);
  // The output bytes are make_color of the average.
  for (size_t p = 0; p < motion.first.size(); ++p) {
    const Float4& a = motion.first[p];
    EXPECT_EQ(motion.second[p], Bgra8(make_float3(a[0], a[1], a[2]))) << "pixel " << p;
  }

  // A shut shutter (every sample at time 0) is the static camera at kEyeBegin: the moving one
  // blurs the sphere's edges and the shadow.
  BuildScene("inproc");
  const std::vector<Float4> still = Launch(0.f, 0.f, kSamples).first;
  size_t differ = 0;
  for (size_t p = 0; p < still.size(); ++p) differ += still[p] != motion.first[p];
  EXPECT_GT(differ, still.size() / 10) << "pixels that the motion changes";

  // Pixels across the sphere's middle row (its edges move by about 8 pixels) and one on the
  // ground: each sample rendered alone, at the time the host says the pixel's sample had.
  const std::pair<unsigned, unsigned> pixels[] = {{12, 24}, {16, 24}, {20, 24}, {32, 24},
                                                  {44, 24}, {48, 24}, {52, 24}, {32, 6}};
  int blurred = 0;
  for (const auto& [x, y] : pixels) {
    SCOPED_TRACE(::testing::Message() << "pixel (" << x << ", " << y << ")");
    const size_t p = size_t{y} * kWidth + x;
    float3 sum = make_float3(0.f);
    bool all_equal = true;
    Float4 first{};
    const std::array<float, kSamples> times = SampleTimes(x, y, 0.f, 1.f);
    for (unsigned k = 0; k < kSamples; ++k) {
      const Float4 s = Launch(times[k], times[k], 1).first[p];
      sum += make_float3(s[0], s[1], s[2]);
      if (k == 0) first = s;
      all_equal = all_equal && s == first;
    }
    sum = sum / static_cast<float>(kSamples);
    EXPECT_TRUE(SameBits(sum, motion.first[p]))
        << "expected (" << sum.x << ", " << sum.y << ", " << sum.z << "), got ("
        << motion.first[p][0] << ", " << motion.first[p][1] << ", " << motion.first[p][2] << ")";
    blurred += !all_equal;
  }
  EXPECT_GE(blurred, 2) << "pixels whose samples saw different things";
}

}  // namespace
}  // namespace tessera::testing
