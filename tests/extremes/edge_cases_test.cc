// Edge cases of tracing (docs/accuracy.md, "Edge cases"): interval ends, invalid rays with the
// exception enabled and disabled, grazing rays down to denormal slopes, shared edges and fan
// vertices, degenerate, sliver and non-finite triangles, vertices beyond Embree's range, and launch
// sizes 1, 2^24 and 16384x16384. Each asserts the documented result; counts are printed.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include "extremes_scene.h"
#include "tessera/accuracy.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// One triangle, or a few, as a Mesh of their own vertices.
meshgen::Mesh Triangles(const std::vector<std::array<double, 9>>& tris) {
  meshgen::Mesh m;
  for (const auto& t : tris) {
    const auto base = static_cast<uint32_t>(m.vertices.size());
    for (int k = 0; k < 3; ++k) m.vertices.push_back({t[3 * k], t[3 * k + 1], t[3 * k + 2]});
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

const meshgen::Mesh& UnitSquareAtZ1() {
  static const meshgen::Mesh m =
      Triangles({{-1, -1, 1, 1, -1, 1, 1, 1, 1}, {-1, -1, 1, 1, 1, 1, -1, 1, 1}});
  return m;
}

Ray Along(float x, float y, float tmin, float tmax) {
  Ray r;
  r.origin = {x, y, 0.f};
  r.direction = {0.f, 0.f, 1.f};
  r.tmin = tmin;
  r.tmax = tmax;
  return r;
}

class EdgeCases : public ExtremesScene, public ::testing::WithParamInterface<MeshKind> {};

// GeometryTriangles take hits at t in (tmin, tmax]: a hit exactly at tmax counts, one exactly at
// tmin does not (Embree's default convention for its triangles; OptiX 3 programs pass
// scene_epsilon as tmin to leave their own surface), the same in every mode. An application's
// mesh has its intersection program's interval: optixu's intersect_triangle takes (tmin, tmax).
TEST_P(EdgeCases, IntervalIsOpenAtTminAndClosedAtTmax) {
  for (uint32_t flags :
       {0u, unsigned{TESSERA_ACCURACY_ROBUST}, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
    Build(UnitSquareAtZ1(), GetParam(), Placement{}, flags);
    const std::vector<RayResult> r =
        Trace({Along(0.3f, 0.2f, 0.f, 1.f), Along(0.3f, 0.2f, 1.f, 2.f),
               Along(0.3f, 0.2f, 0.f, std::nextafter(1.f, 0.f)),
               Along(0.3f, 0.2f, std::nextafter(1.f, 0.f), 2.f)});
    const char* mode = flags == 0                         ? "default"
                       : flags == TESSERA_ACCURACY_ROBUST ? "robust"
                                                          : "watertight";
    EXPECT_EQ(r[0].hit, GetParam() == MeshKind::kGeometryTriangles) << mode << ": t == tmax";
    EXPECT_FALSE(r[1].hit) << mode << ": t == tmin";
    EXPECT_FALSE(r[2].hit) << mode << ": tmax just short";
    EXPECT_TRUE(r[3].hit) << mode << ": tmin just short";
    for (const RayResult& h : r) {
      if (h.hit) {
        EXPECT_EQ(h.t, 1.f) << mode;
      }
    }
  }
}

// Grazing rays towards a large triangle in z = 0 with slopes 10^-1 ... 10^-45 (denormal below
// 1e-38), their origins as high above the plane as the slope makes them meet it at t ~ 1: every
// hit reaches the programs with a finite t in the interval, any-hit program attached or not.
TEST_P(EdgeCases, GrazingRaysDownToDenormalSlopesGiveFiniteT) {
  const meshgen::Mesh plane = Triangles({{-1e3, -1e3, 0, 1e3, -1e3, 0, 0, 1e3, 0}});
  for (bool any_hit : {false, true}) {
    for (uint32_t flags : {0u, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
      Build(plane, GetParam(), Placement{}, flags, any_hit);
      std::vector<Ray> rays;
      for (int e = 1; e <= 45; ++e) {
        const float slope = std::pow(10.f, static_cast<float>(-e));
        Ray r;
        r.origin = {-1.f, 0.f, slope};
        r.direction = {1.f, 0.f, -slope};
        rays.push_back(r);
      }
      const std::vector<RayResult> results = Trace(rays);
      size_t hits = 0;
      for (size_t i = 0; i < results.size(); ++i) {
        if (!results[i].hit) continue;
        ++hits;
        EXPECT_TRUE(std::isfinite(results[i].t) && results[i].t >= 0.f)
            << "slope 1e-" << i + 1 << ": t " << results[i].t;
      }
      std::printf("grazing, any-hit %d, %s: %zu of %zu slopes hit\n", any_hit,
                  flags ? "watertight" : "default", hits, results.size());
      // A slope whose height rounds to 0 starts on the plane: t 0, still a hit.
      EXPECT_GE(hits, 38u);
    }
  }
}

// How many candidates an any-hit program sees for a ray through a vertex six triangles share (a
// fan) and through an edge two share: at least one, at most all of them (Embree may report both
// triangles of an edge; docs/accuracy.md gives the counts).
TEST_P(EdgeCases, SharedEdgesAndFanVerticesOfferEachCandidateOnce) {
  const meshgen::Mesh cube = meshgen::SubdividedCube(2);  // face centres are 6-triangle fans
  for (uint32_t flags :
       {0u, unsigned{TESSERA_ACCURACY_ROBUST}, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
    Build(cube, GetParam(), Placement{}, flags, /*any_hit=*/true);
    Ray fan;
    fan.origin = {0.f, 0.f, 5.f};
    fan.direction = {0.f, 0.f, -1.f};  // through the centres of the faces z = 1 and z = -1
    fan.tmax = 5.5f;                   // only the z = 1 face
    Ray edge;  // through the middle of a cell's diagonal: an edge two triangles share
    edge.origin = {0.5f, 0.5f, 5.f};
    edge.direction = {0.f, 0.f, -1.f};
    edge.tmax = 5.5f;
    const std::vector<RayResult> r = Trace({fan, edge});
    const char* mode = flags == 0                         ? "default"
                       : flags == TESSERA_ACCURACY_ROBUST ? "robust"
                                                          : "watertight";
    std::printf("%s: fan vertex %u candidates, diagonal edge %u candidates\n", mode,
                r[0].candidates, r[1].candidates);
    if (flags == TESSERA_ACCURACY_WATERTIGHT) {
      EXPECT_TRUE(r[0].hit && r[1].hit) << mode;
    }
    for (const RayResult& h : r) {
      if (!h.hit) continue;
      EXPECT_GE(h.candidates, 1u) << mode;
      EXPECT_LE(h.candidates, 6u) << mode;
    }
  }
}

// Degenerate triangles (a point, a line) are never hit; a sliver is hit where it is; triangles
// with a NaN or infinite vertex are never hit and nothing fails.
TEST_P(EdgeCases, DegenerateSliverAndNonFiniteTriangles) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const meshgen::Mesh m = Triangles({{0, 0, 1, 0, 0, 1, 0, 0, 1},              // a point
                                     {0, 0, 2, 1, 0, 2, 2, 0, 2},              // a line
                                     {-1, -1e-7, 3, 1, -1e-7, 3, 0, 1e-7, 3},  // a sliver
                                     {nan, 0, 4, 1, 0, 4, 0, 1, 4},            // NaN
                                     {inf, -1, 5, 1, 0, 5, 0, 1, 5}});         // infinite
  for (uint32_t flags : {0u, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
    Build(m, GetParam(), Placement{}, flags);
    const std::vector<RayResult> r = Trace({Along(0.f, 0.f, 0.f, 1e30f)});
    const char* mode = flags ? "watertight" : "default";
    ASSERT_TRUE(r[0].hit) << mode;
    EXPECT_EQ(r[0].primitive, 2u) << mode << ": only the sliver is hit";
    EXPECT_EQ(r[0].t, 3.f) << mode;
  }
}

// A vertex Embree cannot build (beyond +-1.844e18) fails the launch naming it.
TEST_P(EdgeCases, VertexBeyondEmbreeRangeFailsNamingIt) {
  const meshgen::Mesh m = Triangles({{0, 0, 1, 1, 0, 1, 0, 3e18, 1}});
  for (uint32_t flags : {0u, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
    Build(m, GetParam(), Placement{}, flags);
    RTbuffer in = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &in));
    Ok(rtBufferSetFormat(in, RT_FORMAT_FLOAT4));
    Ok(rtBufferSetSize1D(in, 2));
    Ok(rtVariableSetObject(ContextVar("rays"), in));
    RTbuffer dirs = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &dirs));
    Ok(rtBufferSetFormat(dirs, RT_FORMAT_FLOAT4));
    Ok(rtBufferSetSize1D(dirs, 1));
    Ok(rtVariableSetObject(ContextVar("secondary_dirs"), dirs));
    RTbuffer out = nullptr;
    Ok(rtBufferCreate(ctx_, RT_BUFFER_OUTPUT, &out));
    Ok(rtBufferSetFormat(out, RT_FORMAT_UNSIGNED_INT4));
    Ok(rtBufferSetSize1D(out, 1));
    Ok(rtVariableSetObject(ContextVar("results"), out));
    Ok(rtVariableSet1ui(ContextVar("spawn_mode"), 0));
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 0.f));
    const RTresult code = rtContextLaunch1D(ctx_, 0, 1);
    ASSERT_NE(code, RT_SUCCESS);
    EXPECT_NE(Error(code).find("beyond +-1.844e18"), std::string::npos) << Error(code);
  }
}

// OptiX 6's rtGeometryTrianglesSetBuildFlags: NONE and RELEASE_BUFFERS are taken (Tessera keeps
// the buffers either way, and the triangles are traced as before); other bits are refused by name.
TEST_F(ExtremesScene, GeometryTrianglesBuildFlags) {
  Build(UnitSquareAtZ1(), MeshKind::kGeometryTriangles, Placement{}, 0);
  RTgeometrytriangles triangles = nullptr;
  Ok(rtGeometryTrianglesCreate(ctx_, &triangles));
  EXPECT_EQ(rtGeometryTrianglesSetBuildFlags(triangles, RT_GEOMETRY_BUILD_FLAG_NONE), RT_SUCCESS);
  EXPECT_EQ(rtGeometryTrianglesSetBuildFlags(triangles, RT_GEOMETRY_BUILD_FLAG_RELEASE_BUFFERS),
            RT_SUCCESS);
  const RTresult bad =
      rtGeometryTrianglesSetBuildFlags(triangles, static_cast<RTgeometrybuildflags>(0x3));
  EXPECT_EQ(bad, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(bad).find("build flags 0x3"), std::string::npos) << Error(bad);
  EXPECT_EQ(rtGeometryTrianglesSetBuildFlags(nullptr, RT_GEOMETRY_BUILD_FLAG_NONE),
            RT_ERROR_INVALID_VALUE);
  rtGeometryTrianglesDestroy(triangles);
  EXPECT_TRUE(Trace({Along(0.3f, 0.2f, 0.f, 2.f)})[0].hit);
}

// An acceleration with "refit" "1" whose vertices move (the acceleration marked dirty) is
// refitted in place: every ray hits what a fresh build of the moved vertices hits, at the same t,
// by default and in watertight mode, on an in-process device and on a worker process.
TEST_P(EdgeCases, RefitFollowsMovedVertices) {
  const meshgen::Mesh sphere = meshgen::Icosphere(3);
  std::vector<Ray> rays;
  for (int i = 0; i < 400; ++i) {
    const float a = 0.1f * i, b = 0.037f * i;
    Ray r;
    r.origin = {0.1f, -0.05f, 0.02f};
    r.direction = {std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)};
    rays.push_back(r);
  }
  Placement moved;
  moved.scale = 1.5;
  moved.offset = {0.2, 0.0, -0.1};
  for (const char* devices : {"inproc", "local:1"}) {
    for (uint32_t flags : {0u, unsigned{TESSERA_ACCURACY_WATERTIGHT}}) {
      Build(sphere, GetParam(), moved, flags, false, "Bvh", {}, devices);
      const std::vector<RayResult> fresh = Trace(rays);
      Build(sphere, GetParam(), Placement{}, flags, false, "Bvh", {{"refit", "1"}}, devices);
      const std::vector<RayResult> before = Trace(rays);
      // Move the vertices in place, as an animation does, and mark the acceleration dirty.
      const std::vector<float> v = meshgen::Placed(sphere, moved.scale, moved.offset);
      RTvariable top = ContextVar("top_object");
      RTobject object = nullptr;
      Ok(rtVariableGetObject(top, &object));
      RTgeometrygroup group = static_cast<RTgeometrygroup>(object);
      RTacceleration accel = nullptr;
      Ok(rtGeometryGroupGetAcceleration(group, &accel));
      RTbuffer vb = vertex_buffer();
      void* p = nullptr;
      Ok(rtBufferMap(vb, &p));
      std::memcpy(p, v.data(), v.size() * sizeof(float));
      Ok(rtBufferUnmap(vb));
      Ok(rtAccelerationMarkDirty(accel));
      const std::vector<RayResult> after = Trace(rays);
      size_t differ = 0, moved_hits = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        differ += (after[i].hit != fresh[i].hit || after[i].t != fresh[i].t ||
                   after[i].primitive != fresh[i].primitive)
                      ? 1
                      : 0;
        moved_hits += after[i].t != before[i].t ? 1 : 0;
      }
      EXPECT_EQ(differ, 0u) << devices << (flags ? " watertight" : " default");
      EXPECT_GT(moved_hits, rays.size() / 2) << devices << ": the hits moved with the vertices";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, EdgeCases,
                         ::testing::Values(MeshKind::kGeometryTriangles,
                                           MeshKind::kApplicationMesh),
                         [](const auto& info) {
                           return info.param == MeshKind::kGeometryTriangles ? "GeometryTriangles"
                                                                             : "ApplicationMesh";
                         });

// Invalid rays of every kind: with RT_EXCEPTION_INVALID_RAY enabled the exception program runs
// with that code; disabled, the ray is traced as a miss (its miss program runs), on every device.
class InvalidRays : public RtFixture, public ::testing::WithParamInterface<const char*> {};

TEST_P(InvalidRays, RaiseWhenEnabledAndMissWhenDisabled) {
  struct Case {
    const char* what;
    float o[3], d[3], tmin, tmax;
  };
  const Case cases[] = {
      {"NaN origin", {kNaN, 0, 0}, {0, 0, 1}, 0, 1e30f},
      {"infinite origin", {0, kInf, 0}, {0, 0, 1}, 0, 1e30f},
      {"origin beyond 1.844e18", {0, 0, 3e18f}, {0, 0, 1}, 0, 1e30f},
      {"NaN direction", {0, 0, 0}, {0, kNaN, 1}, 0, 1e30f},
      {"infinite direction", {0, 0, 0}, {0, 0, -kInf}, 0, 1e30f},
      {"negative tmin", {0, 0, 0}, {0, 0, 1}, -1.f, 1e30f},
      {"tmin past tmax", {0, 0, 0}, {0, 0, 1}, 2.f, 1.f},
      {"NaN tmin", {0, 0, 0}, {0, 0, 1}, kNaN, 1e30f},
      {"NaN tmax", {0, 0, 0}, {0, 0, 1}, 0.f, kNaN},
  };
  const size_t n = sizeof(cases) / sizeof(cases[0]);
  for (bool enabled : {true, false}) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ASSERT_EQ(rtContextCreate(&ctx_), RT_SUCCESS);
    Ok(tesseraContextSetDeviceSpec(ctx_, GetParam()));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, 1));
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("extremes_programs", "shoot_marked")));
    Ok(rtContextSetExceptionProgram(ctx_, 0,
                                    Program("extremes_programs", "invalid_ray_exception")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("extremes_programs", "marking_miss")));
    Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_INVALID_RAY, enabled ? 1 : 0));
    // An empty group: a valid ray would miss as well, so only the exception tells them apart.
    RTgroup group = nullptr;
    Ok(rtGroupCreate(ctx_, &group));
    Ok(rtGroupSetAcceleration(group, Accel()));
    Ok(rtVariableSetObject(ContextVar("top_object"), group));
    RTbuffer rays = Buffer2D("rays", RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, 2 * n, 1);
    Ok(rtBufferSetSize1D(rays, 2 * n));
    float* r = nullptr;
    Ok(rtBufferMap(rays, reinterpret_cast<void**>(&r)));
    for (size_t i = 0; i < n; ++i) {
      const Case& c = cases[i];
      const float words[8] = {c.o[0], c.o[1], c.o[2], c.tmin, c.d[0], c.d[1], c.d[2], c.tmax};
      std::memcpy(r + 8 * i, words, sizeof(words));
    }
    Ok(rtBufferUnmap(rays));
    RTbuffer out = Buffer2D("outcomes", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, n, 1);
    Ok(rtBufferSetSize1D(out, n));
    Ok(rtContextLaunch1D(ctx_, 0, n));
    const std::vector<std::array<unsigned, 4>> got = ReadAs<std::array<unsigned, 4>>(out);
    for (size_t i = 0; i < n; ++i) {
      if (enabled) {
        EXPECT_EQ(got[i][0], 2u) << cases[i].what << ": the exception program runs";
        EXPECT_EQ(got[i][1], unsigned{RT_EXCEPTION_INVALID_RAY}) << cases[i].what;
      } else {
        EXPECT_EQ(got[i][0], 1u) << cases[i].what << ": traced as a miss";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, InvalidRays, ::testing::Values("inproc", "local:2"),
                         [](const auto& info) {
                           return std::string(info.param) == "inproc" ? "Inproc" : "Local2";
                         });

long MaxRssKiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// Launches of 1, 2^24 and 16384 x 16384 indices run every index once; the host's peak memory is
// printed (the output buffer itself is a byte per index).
class LaunchSizes : public RtFixture {};

TEST_F(LaunchSizes, OneTwoToTheTwentyFourAndSixteenKSquared) {
  Ok(tesseraContextSetDeviceSpec(ctx_, "inproc"));
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  Ok(rtContextSetRayTypeCount(ctx_, 1));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("launch_size_programs", "write_byte")));
  for (const auto& [w, h] :
       {std::pair<size_t, size_t>{1, 1}, {size_t{1} << 24, 1}, {16384, 16384}}) {
    const long before = MaxRssKiB();
    RTbuffer bytes = Buffer2D("bytes", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE, w, h);
    const RTresult launched = rtContextLaunch2D(ctx_, 0, w, h);
    ASSERT_EQ(launched, RT_SUCCESS) << Error(launched);
    const unsigned char* p = nullptr;
    Ok(rtBufferMap(bytes, reinterpret_cast<void**>(const_cast<unsigned char**>(&p))));
    size_t wrong = 0;
    for (size_t y = 0; y < h; y += (h > 1 ? 97 : 1)) {
      for (size_t x = 0; x < w; ++x) {
        wrong += p[y * w + x] != static_cast<unsigned char>((x ^ y) & 0xFF) ? 1 : 0;
      }
    }
    Ok(rtBufferUnmap(bytes));
    EXPECT_EQ(wrong, 0u) << w << "x" << h;
    std::printf("launch %zux%zu: peak host memory %.1f MiB (was %.1f MiB)\n", w, h,
                MaxRssKiB() / 1024.0, before / 1024.0);
    rtBufferDestroy(bytes);
  }
}

}  // namespace
}  // namespace tessera::testing
