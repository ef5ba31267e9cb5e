// OptionsOf: which Embree build each OptiX builder and property gets; and that the fast (LOW)
// build Lbvh gets resolves ties alike whatever the thread count.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "plan.h"
#include "tessera/accuracy.h"

namespace tessera::worker {
namespace {

SceneOptions Options(const AccelRec& a, bool has_filter, uint32_t flags = 0) {
  absl::StatusOr<SceneOptions> o = OptionsOf(7, a, has_filter, flags);
  EXPECT_TRUE(o.ok()) << o.status();
  return o.ok() ? *o : SceneOptions{};
}

TEST(SceneOptionsTest, BuildersMapToQualities) {
  const std::pair<const char*, RTCBuildQuality> expected[] = {
      {"NoAccel", RTC_BUILD_QUALITY_LOW},       {"Lbvh", RTC_BUILD_QUALITY_LOW},
      {"MedianBvh", RTC_BUILD_QUALITY_LOW},     {"Bvh", RTC_BUILD_QUALITY_MEDIUM},
      {"BvhCompact", RTC_BUILD_QUALITY_MEDIUM}, {"Sbvh", RTC_BUILD_QUALITY_HIGH},
      {"Trbvh", RTC_BUILD_QUALITY_HIGH},        {"TriangleKdTree", RTC_BUILD_QUALITY_HIGH}};
  for (const auto& [builder, quality] : expected) {
    AccelRec a;
    a.builder = builder;
    EXPECT_EQ(Options(a, false).quality, quality) << builder;
    EXPECT_FALSE(Options(a, false).refit) << builder;
  }
  // Spatial splits (HIGH) could show an any-hit program one candidate twice.
  AccelRec sbvh;
  sbvh.builder = "Sbvh";
  EXPECT_EQ(Options(sbvh, true).quality, RTC_BUILD_QUALITY_MEDIUM);
  AccelRec compact;
  compact.builder = "BvhCompact";
  EXPECT_TRUE(Options(compact, false).compact);
}

TEST(SceneOptionsTest, PropertiesAndContextFlags) {
  AccelRec a;
  a.builder = "Lbvh";
  a.properties["refine"] = "2";
  EXPECT_EQ(Options(a, false).quality, RTC_BUILD_QUALITY_MEDIUM);
  a.properties["refit"] = "1";
  const SceneOptions refit = Options(a, false);
  EXPECT_TRUE(refit.refit);
  EXPECT_TRUE(refit.flags() & RTC_SCENE_FLAG_DYNAMIC);
  a.properties["watertight"] = "1";
  EXPECT_TRUE(Options(a, false).watertight);
  EXPECT_TRUE(Options(a, false).flags() & RTC_SCENE_FLAG_ROBUST);  // watertight implies robust

  AccelRec plain;
  plain.builder = "Bvh";
  EXPECT_EQ(Options(plain, false).flags(), RTC_SCENE_FLAG_NONE);
  const SceneOptions all = Options(plain, false, TESSERA_ACCURACY_ALL);
  EXPECT_TRUE(all.robust && all.watertight && all.compact);
  EXPECT_EQ(all.flags(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_COMPACT);

  for (const auto& [name, value] :
       {std::pair{"robust", "yes"}, std::pair{"refine", "-1"}, std::pair{"compact", "2"}}) {
    AccelRec bad;
    bad.builder = "Bvh";
    bad.properties[name] = value;
    absl::StatusOr<SceneOptions> o = OptionsOf(7, bad, false, 0);
    ASSERT_FALSE(o.ok()) << name;
    EXPECT_NE(o.status().message().find("acceleration #7: property " + std::string(name)),
              std::string::npos)
        << o.status();
  }
}

// Which triangle of pairs of coincident ones (exact ties in t) rays hit, through a LOW build on a
// device of `threads` threads.
std::vector<unsigned> TiesResolved(int threads) {
  RTCDevice device = rtcNewDevice(("threads=" + std::to_string(threads)).c_str());
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> coord(0.f, 100.f);
  constexpr int kPairs = 50000;
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 6 * kPairs));
  auto* idx = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, 2 * kPairs));
  std::vector<float> corner(3 * kPairs);
  for (int i = 0; i < kPairs; ++i) {
    const float x = coord(rng), y = coord(rng), z = coord(rng);
    corner[3 * i] = x, corner[3 * i + 1] = y, corner[3 * i + 2] = z;
    for (int copy = 0; copy < 2; ++copy) {
      const float tri[9] = {x, y, z, x + 1, y, z, x, y + 1, z};
      const unsigned base = 3 * (2 * i + copy);
      for (int k = 0; k < 9; ++k) v[3 * base + k] = tri[k];
      for (unsigned k = 0; k < 3; ++k) idx[base + k] = base + k;
    }
  }
  rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_LOW);
  rtcCommitGeometry(g);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  std::vector<unsigned> hits;
  for (int i = 0; i < kPairs; i += 7) {
    RTCRayHit rh{};
    rh.ray.org_x = corner[3 * i] + 0.25f;
    rh.ray.org_y = corner[3 * i + 1] + 0.25f;
    rh.ray.org_z = corner[3 * i + 2] - 1.f;
    rh.ray.dir_z = 1.f;
    rh.ray.tfar = 1e30f;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcIntersect1(scene, &ctx, &rh);
    hits.push_back(rh.hit.primID);
  }
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return hits;
}

TEST(SceneOptionsTest, FastBuildResolvesTiesAlikeOnEveryThreadCount) {
  const std::vector<unsigned> one = TiesResolved(1);
  for (int threads : {2, 3, 8}) EXPECT_EQ(TiesResolved(threads), one) << threads << " threads";
}

}  // namespace
}  // namespace tessera::worker
