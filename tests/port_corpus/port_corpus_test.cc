// The port corpus from the host side: its shared headers compiled as host code (no __CUDACC__),
// and its programs, built with the README's g++ line, rendered on inproc, local:1 and local:3.
#include <optix.h>

#if defined(TESSERA_DEVICE_H_)
#error "optix.h gave host code the program-side API: OptiX's gives it only under __CUDACC__"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "intrinsic_cases.h"
#include "port_corpus_fixture.h"
#include "sample_common.h"

namespace tessera::testing {
namespace {

// ---- The shared headers as host code ------------------------------------------------------------

TEST(PortCorpusHostTest, SharedHeaderTakesItsHostBranch) {
  EXPECT_FALSE(in_program_module());
  const optix::float3 c = color_from_bgra8(0x00FF8000u);  // only the host branch defines it
  EXPECT_EQ(c.x, 1.0f);
  EXPECT_EQ(c.y, 128.0f / 255.0f);
  EXPECT_EQ(c.z, 0.0f);
  unsigned int seed = tea<4>(3u, 5u);
  const float r = rnd(seed);
  EXPECT_GE(r, 0.0f);
  EXPECT_LT(r, 1.0f);
}

// ---- The SDK-style scene ----------------------------------------------------------------------

constexpr size_t kWidth = 64, kHeight = 48;

class SceneTest : public PortCorpusTest {
 protected:
  // A unit sphere on a ground sphere, a pinhole camera, a Phong-like material with shadow rays
  // (ray type 1, with an any-hit program), and a miss program. Returns the BGRA8 pixels.
  std::vector<std::uint32_t> Render(const char* spec) {
    UseDevices(spec, 2);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("pinhole_camera", "pinhole_camera")));
    Ok(rtContextSetExceptionProgram(ctx_, 0, Program("pinhole_camera", "exception")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("materials", "miss")));
    Spheres({{0.f, 0.f, 0.f, 1.f}, {0.f, -101.f, 0.f, 100.f}});
    Instance i = MakeInstance(Program("sphere", "intersect"), Program("sphere", "bounds"), 2,
                              Program("materials", "closest_hit_radiance"));
    Ok(rtMaterialSetAnyHitProgram(i.material, 1, Program("materials", "any_hit_shadow")));
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    Ok(rtVariableSetObject(ContextVar("top_shadower"), i.group));
    SetFloat3("eye", kEye.x, kEye.y, kEye.z);
    SetFloat3("U", kU.x, kU.y, kU.z);
    SetFloat3("V", kV.x, kV.y, kV.z);
    SetFloat3("W", kW.x, kW.y, kW.z);
    SetFloat3("bad_color", 1.f, 0.f, 1.f);
    SetFloat3("light_pos", 3.f, 5.f, -3.f);
    SetFloat3("Kd", 0.7f, 0.5f, 0.3f);
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 1e-3f));
    Ok(rtVariableSet1ui(ContextVar("radiance_ray_type"), 0));
    Ok(rtVariableSet1ui(ContextVar("shadow_ray_type"), 1));
    RTbuffer out =
        Buffer2D("output_buffer", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE4, kWidth, kHeight);
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    return ReadAs<std::uint32_t>(out);
  }

  const optix::float3 kEye = optix::make_float3(0.f, 0.5f, -4.f);
  const optix::float3 kU = optix::make_float3(0.5f, 0.f, 0.f);
  const optix::float3 kV = optix::make_float3(0.f, 0.375f, 0.f);
  const optix::float3 kW = optix::make_float3(0.f, -0.125f, 1.f);
};

// What materials.cu's miss program and make_color give for launch index (0, kHeight - 1), the top
// left corner, which looks past the spheres: computed by host code with the same optixu header.
std::uint32_t MissPixel(optix::float3 U, optix::float3 V, optix::float3 W) {
  using namespace optix;
  const float2 d =
      make_float2(0.f, float(kHeight - 1)) / make_float2(float(kWidth), float(kHeight)) * 2.f - 1.f;
  const float3 dir = normalize(d.x * U + d.y * V + W);
  const float t = 0.5f + 0.5f * dir.y;
  const float3 c = temperature(t) * 0.5f + make_float3(luminanceCIE(make_float3(t)) * 0.1f);
  auto byte = [](float v) { return static_cast<std::uint32_t>(__saturatef(v) * 255.99f); };
  return byte(c.z) | byte(c.y) << 8 | byte(c.x) << 16 | 255u << 24;
}

TEST_F(SceneTest, BitIdenticalOnEveryDeviceSetAndAsTheHostComputesIt) {
  std::vector<std::uint32_t> reference;
  for (const char* spec : kDeviceSets) {
    SCOPED_TRACE(spec);
    std::vector<std::uint32_t> image = Render(spec);
    if (HasFatalFailure()) return;
    ASSERT_EQ(image.size(), kWidth * kHeight);
    if (reference.empty()) {
      reference = image;
      continue;
    }
    EXPECT_TRUE(image == reference) << "the image differs from inproc's";
  }
  const std::uint32_t corner = reference[(kHeight - 1) * kWidth];
  EXPECT_EQ(corner, MissPixel(kU, kV, kW)) << "the miss program's corner pixel";
  const std::uint32_t centre = reference[(kHeight / 2) * kWidth + kWidth / 2];
  EXPECT_NE(centre, corner) << "the sphere is in the middle of the image";
  EXPECT_NE(centre, 0xFFFF00FFu) << "no exception";
  // The sphere's shading varies, and its shadow darkens the ground under it.
  std::vector<std::uint32_t> distinct(reference);
  std::sort(distinct.begin(), distinct.end());
  EXPECT_GT(std::unique(distinct.begin(), distinct.end()) - distinct.begin(), 50);
}

// ---- OptiX 6 ray flags
// ---------------------------------------------------------------------------

struct Mode {
  unsigned mask, flags;
};
constexpr unsigned kDisableAnyHit = 1u << 0, kForceAnyHit = 1u << 1, kTerminate = 1u << 2,
                   kDisableClosestHit = 1u << 3, kCullBack = 1u << 4, kCullDisabledAnyHit = 1u << 6,
                   kCullEnabledAnyHit = 1u << 7;
const std::vector<Mode> kModes = {
    {0xFF, 0},                                     // 0: everything runs
    {0xFF, kDisableAnyHit},                        // 1
    {0xFF, kDisableClosestHit},                    // 2
    {0xFF, kTerminate},                            // 3
    {0x00, 0},                                     // 4: no mask bit: misses
    {0x100, 0},                                    // 5: bits above 8 see nothing either
    {0x01, 0},                                     // 6: one bit of the default mask is enough
    {0xFF, kCullEnabledAnyHit},                    // 7: every geometry runs any-hit: all culled
    {0xFF, kCullDisabledAnyHit | kDisableAnyHit},  // 8: all culled
    {0xFF, kCullDisabledAnyHit},                   // 9: none disabled: nothing culled
    {0xFF, kForceAnyHit},                          // 10
    {0xFF, kTerminate | kDisableAnyHit},           // 11
};

class RayFlagsTest : public PortCorpusTest {
 protected:
  // Three spheres on the +z axis (front faces at t = 2.5, 4.5, 6.5), each with closest-hit and
  // any-hit programs; one launch index per mode.
  void BuildScene(const char* spec, const std::vector<Mode>& modes) {
    UseDevices(spec, 1);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("ray_flags", "trace_modes")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("ray_flags", "miss")));
    Spheres({{0.f, 0.f, 3.f, 0.5f}, {0.f, 0.f, 5.f, 0.5f}, {0.f, 0.f, 7.f, 0.5f}});
    Instance i = MakeInstance(Program("sphere", "intersect"), Program("sphere", "bounds"), 3,
                              Program("ray_flags", "closest_hit"), Program("ray_flags", "any_hit"));
    Ok(rtVariableSetObject(ContextVar("top_object"), i.group));
    std::vector<unsigned> words;
    for (const Mode& m : modes) words.insert(words.end(), {m.mask, m.flags});
    Fill(Buffer1D("flags_modes", RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT2, modes.size()), words);
    result_ = Buffer1D("flags_result", RT_BUFFER_OUTPUT, RT_FORMAT_INT4, modes.size());
    t_ = Buffer1D("flags_t", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, modes.size());
  }
  RTbuffer result_ = nullptr, t_ = nullptr;
};

TEST_F(RayFlagsTest, EachFlagDoesWhatOptiXSaysOnEveryDeviceSet) {
  std::vector<int> reference;
  std::vector<float> reference_t;
  for (const char* spec : kDeviceSets) {
    SCOPED_TRACE(spec);
    BuildScene(spec, kModes);
    if (HasFatalFailure()) return;
    Ok(rtContextLaunch1D(ctx_, 0, kModes.size()));
    std::vector<int> r = Get<int>(result_, kModes.size() * 4);
    std::vector<float> t = Get<float>(t_, kModes.size());
    if (reference.empty()) {
      reference = r;
      reference_t = t;
    } else {
      EXPECT_TRUE(r == reference) << "the counts differ from inproc's";
      EXPECT_TRUE(t == reference_t) << "the distances differ from inproc's";
    }
  }
  auto closest = [&](size_t m) { return reference[4 * m]; };
  auto any = [&](size_t m) { return reference[4 * m + 1]; };
  auto misses = [&](size_t m) { return reference[4 * m + 2]; };
  auto front_face = [&](size_t m) {
    return reference_t[m] == 2.5f || reference_t[m] == 4.5f || reference_t[m] == 6.5f;
  };
  for (size_t m : {0u, 6u, 9u, 10u}) {
    SCOPED_TRACE(m);
    EXPECT_EQ(closest(m), 1);
    EXPECT_GE(any(m), 1);
    EXPECT_EQ(misses(m), 0);
    EXPECT_EQ(reference_t[m], 2.5f);
  }
  EXPECT_EQ(any(1), 0);  // DISABLE_ANYHIT
  EXPECT_EQ(closest(1), 1);
  EXPECT_EQ(reference_t[1], 2.5f);
  EXPECT_EQ(closest(2), 0);  // DISABLE_CLOSESTHIT: a hit, but nothing shades it
  EXPECT_GE(any(2), 1);
  EXPECT_EQ(misses(2), 0);
  EXPECT_EQ(any(3), 1);  // TERMINATE_ON_FIRST_HIT: the first hit accepted is the one shaded
  EXPECT_EQ(closest(3), 1);
  EXPECT_TRUE(front_face(3)) << reference_t[3];
  EXPECT_EQ(any(11), 0);
  EXPECT_EQ(closest(11), 1);
  EXPECT_TRUE(front_face(11)) << reference_t[11];
  for (size_t m : {4u, 5u, 7u, 8u}) {
    SCOPED_TRACE(m);
    EXPECT_EQ(misses(m), 1);
    EXPECT_EQ(closest(m), 0);
    EXPECT_EQ(any(m), 0);
  }
}

TEST_F(RayFlagsTest, FaceCullingFailsTheLaunchNamingTheFlag) {
  BuildScene("inproc", {{0xFF, kCullBack}});
  const RTresult r = rtContextLaunch1D(ctx_, 0, 1);
  EXPECT_NE(r, RT_SUCCESS);
  EXPECT_NE(Error(r).find("RT_RAY_FLAG_CULL_BACK_FACING_TRIANGLES"), std::string::npos) << Error(r);
}

// ---- Intrinsics, math and atomics -----------------------------------------------------------

TEST_F(PortCorpusTest, IntrinsicsAndMathAgreeWithHostCodeToTheBit) {
  constexpr size_t kW = 16, kH = 8, kN = kW * kH;
  UseDevices("inproc", 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("intrinsics", "run_cases")));
  RTbuffer cases = Buffer1D("cases", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kIntrinsicCases);
  RTbuffer hashes = Buffer1D("hashes", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, kN);
  const int kAllOnes = -1;
  RTbuffer ints = Buffer1D("atomic_int", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_INT, 10);
  Fill(ints, std::vector<int>{0, 0, 0, 0, 0, 0, kAllOnes, 0, 0, 0});
  RTbuffer uints = Buffer1D("atomic_uint", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, 9);
  Fill(uints, std::vector<unsigned>{0, 1000, 0xFFFFFFFFu, 0, 0, 0, 0xFFFFFFFFu, 0, 0});
  RTbuffer ulls = Buffer1D("atomic_ull", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_USER, 8, 8);
  Fill(ulls, std::vector<unsigned long long>{0, ~0ull, 0, 0, 0, ~0ull, 0, 0});
  RTbuffer floats = Buffer1D("atomic_float", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_FLOAT, 2);
  Fill(floats, std::vector<float>{0.f, 0.f});
  RTbuffer doubles = Buffer1D("atomic_double", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_USER, 1, 8);
  Fill(doubles, std::vector<double>{0.0});
  RTbuffer clocks = Buffer1D("clocks", RT_BUFFER_OUTPUT, RT_FORMAT_USER, 2, 8);
  const auto now = [] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  const long long before = now();
  Ok(rtContextLaunch2D(ctx_, 0, kW, kH));
  const long long after = now();
  // clock() in a program is the monotonic nanosecond counter (not the process's CPU time, which
  // is far below it), the one clock64() and the host's steady_clock read.
  const std::vector<long long> c = Get<long long>(clocks, 2);
  EXPECT_GE(c[0], before);
  EXPECT_LE(c[0], c[1]);
  EXPECT_LE(c[1], after);

  float expected[kIntrinsicCases];
  intrinsic_cases(expected);
  const std::vector<float> got = Get<float>(cases, kIntrinsicCases);
  for (unsigned k = 0; k < kIntrinsicCases; ++k) {
    EXPECT_EQ(std::memcmp(&got[k], &expected[k], sizeof(float)), 0)
        << "case " << k << ": program " << got[k] << ", host " << expected[k];
    EXPECT_TRUE(std::isfinite(got[k])) << "case " << k;
  }
  const std::vector<unsigned> h = Get<unsigned>(hashes, kN);
  for (unsigned y = 0; y < kH; ++y) {
    for (unsigned x = 0; x < kW; ++x) EXPECT_EQ(h[y * kW + x], tea<4>(x, y)) << x << "," << y;
  }

  const std::vector<int> i = Get<int>(ints, 10);
  EXPECT_EQ(i[0], 2 * static_cast<int>(kN));
  EXPECT_EQ(i[1], -static_cast<int>(kN));
  EXPECT_EQ(i[2], -static_cast<int>(kN - 1));
  EXPECT_EQ(i[3], static_cast<int>(kN - 1));
  EXPECT_EQ(i[4], 7);
  EXPECT_GE(i[5], 1);  // one index's CAS won
  EXPECT_LE(i[5], static_cast<int>(kN));
  EXPECT_EQ(static_cast<unsigned>(i[6]), 0x80000000u);  // bits 0..30 cleared
  EXPECT_EQ(i[7], 0x7FFFFFFF);
  EXPECT_EQ(i[8], 0);  // each bit flipped an even number of times
  EXPECT_EQ(i[9], 0) << "clock64() read before clock() in a program";
  const std::vector<unsigned> u = Get<unsigned>(uints, 9);
  EXPECT_EQ(u[0], 3 * kN);
  EXPECT_EQ(u[1], 1000 - kN);
  EXPECT_EQ(u[2], 5u);
  EXPECT_EQ(u[3], kN - 1);
  EXPECT_EQ(u[4], kN % 10);  // atomicInc(9) counts 0..9 and wraps
  EXPECT_EQ(u[5], 2u);       // atomicDec(9) from 0: 9, 8, ...; 128 steps end on 2
  EXPECT_EQ(u[6], 0u);
  EXPECT_EQ(u[7], 0xFFFFFFFFu);
  EXPECT_EQ(u[8], 0u);
  const std::vector<unsigned long long> l = Get<unsigned long long>(ulls, 8);
  EXPECT_EQ(l[0], static_cast<unsigned long long>(kN) << 33);
  EXPECT_EQ(l[1], 100ull);
  EXPECT_EQ(l[2], static_cast<unsigned long long>(kN - 1) << 40);
  EXPECT_EQ(l[3], 5ull);
  EXPECT_GE(l[4], 1ull);
  EXPECT_LE(l[4], static_cast<unsigned long long>(kN));
  EXPECT_EQ(l[5], 0ull);
  EXPECT_EQ(l[6], ~0ull);
  EXPECT_EQ(l[7], 0ull);
  const std::vector<float> f = Get<float>(floats, 2);
  EXPECT_EQ(f[0], 0.5f * kN);
  EXPECT_EQ(f[1], 2.5f);
  EXPECT_EQ(Get<double>(doubles, 1)[0], 0.25 * kN);
}

// Globals named index, time, gamma, random, select and rindex, and library headers included after
// them, in a module that runs.
TEST_F(PortCorpusTest, ProgramsNamingGlibcFunctionsRun) {
  UseDevices("inproc", 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("libc_names", "shade_names")));
  Ok(rtVariableSet1f(ContextVar("time"), 4.0f));
  Ok(rtVariableSet1f(ContextVar("gamma"), 2.0f));
  Ok(rtVariableSet1ui(ContextVar("random"), 3u));
  Ok(rtVariableSet1i(ContextVar("select"), 5));
  Ok(rtVariableSet1i(ContextVar("rindex"), 7));
  RTbuffer out = Float4Buffer("output_buffer", RT_BUFFER_OUTPUT, 4, 3);
  Ok(rtContextLaunch2D(ctx_, 0, 4, 3));
  for (const Float4& p : Read(out)) {
    EXPECT_EQ(p[0], 2.0f + 3.0f + 5.0f + 7.0f);  // powf(4, 1/2) + random + select + rindex
    EXPECT_EQ(p[1], 1.0f + 3.0f);                // the map's size and "  1"
    EXPECT_EQ(p[2], 3.0f);
    EXPECT_EQ(p[3], 1.0f);
  }
}

// A .cu source compiled by the host at run time (rtProgramCreateFromPTXString) gets the same line:
// __CUDACC__ (its program helpers and the program-side API), optixu/ on the include path, and
// glibc's names out of the way.
TEST_F(PortCorpusTest, SourcesCompiledAtRunTimeGetTheReadmeLine) {
  UseDevices("inproc", 1);
  const char* source = R"(
#include <optixu_math_namespace.h>
#include <optix.h>
#ifndef __CUDACC__
#error "no __CUDACC__"
#endif
rtDeclareVariable(optix::uint2, index, rtLaunchIndex, );
rtBuffer<float4, 2> output_buffer;
#ifdef __CUDACC__
static __device__ __inline__ float4 shade(optix::uint2 i) {
  return optix::make_float4(optix::make_float3(float(i.x), float(i.y), 0.0f), 1.0f);
}
#endif
RT_PROGRAM void at_run_time() { output_buffer[index] = shade(index); }
)";
  RTprogram p = nullptr;
  ASSERT_EQ(rtProgramCreateFromPTXString(ctx_, source, "at_run_time", &p), RT_SUCCESS)
      << Error(RT_ERROR_INVALID_SOURCE);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, p));
  RTbuffer out = Float4Buffer("output_buffer", RT_BUFFER_OUTPUT, 3, 2);
  Ok(rtContextLaunch2D(ctx_, 0, 3, 2));
  const std::vector<Float4> pixels = Read(out);
  EXPECT_EQ(pixels[5][0], 2.0f);
  EXPECT_EQ(pixels[5][1], 1.0f);
}

// OptiX 3 idioms (sm_1x stubs, optix_math.h, callable programs) in a module that runs.
TEST_F(PortCorpusTest, LegacyStyleProgramRuns) {
  UseDevices("inproc", 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("legacy_style", "checker_gen")));
  Ok(rtVariableSetObject(ContextVar("get_color"), Program("legacy_style", "checker_color")));
  RTbuffer out = Float4Buffer("output_buffer", RT_BUFFER_OUTPUT, 16, 16);
  Ok(rtContextLaunch2D(ctx_, 0, 16, 16));
  const std::vector<Float4> pixels = Read(out);
  // Launch index (x, y) is the point (x / 64, y / 64): 8 squares per unit, so squares of 8x8
  // indices, the first dark (0.1), tinted by 0.9, 1.0 and 1.1.
  EXPECT_EQ(pixels[0][0], 0.1f * 0.9f);
  EXPECT_EQ(pixels[0][1], 0.1f);
  EXPECT_EQ(pixels[0][2], 0.1f * 1.1f);
  EXPECT_EQ(pixels[8][0], 0.9f);
  EXPECT_EQ(pixels[8 * 16 + 8][1], 0.1f);
}

}  // namespace
}  // namespace tessera::testing
