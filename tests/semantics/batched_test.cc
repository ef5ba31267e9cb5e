// Batched tracing of OptiX 3 launches (TESSERA_BATCHING=1, or =auto: chosen per entry point;
// docs/programs.md, "Batched tracing"):
// the first rays of each block of launch indices are traced as one Embree packet. Outputs must be
// those of single rays, bit for bit, on every device set, and what a ray generation program does
// before its first rtTrace (buffer writes, prints, exceptions) must happen once.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "triangles_fixture.h"

namespace tessera::testing {
namespace {

class BatchedTest : public TrianglesFixture {
 protected:
  static constexpr unsigned kW = 37, kH = 29;  // partial blocks on both edges

  void SetUp() override {
    TrianglesFixture::SetUp();
    wide_ = Float4Buffer("output", RT_BUFFER_OUTPUT, kW, kH);
    RTmaterial m = nullptr;
    Ok(rtMaterialCreate(ctx_, &m));
    Ok(rtMaterialSetClosestHitProgram(m, 0, B("closest")));
    material_ = m;
    Ok(rtContextSetMissProgram(ctx_, 0, B("miss")));
    Scene({material_});
  }
  RTprogram B(const char* function) { return Program("batched_programs", function); }

  std::vector<Float4> Run(const char* raygen, bool batched, unsigned w = kW, unsigned h = kH) {
    setenv("TESSERA_BATCHING", batched ? "1" : "0", 1);
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, B(raygen)));
    const RTresult r = rtContextLaunch2D(ctx_, 0, w, h);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    return Read(wide_);
  }

  // `raygen` batched gives what it gives with single rays, and hits both triangles.
  void ExpectSameAsSingleRays(const char* raygen) {
    const std::vector<Float4> single = Run(raygen, false);
    const std::vector<Float4> batched = Run(raygen, true);
    ASSERT_EQ(single.size(), batched.size());
    size_t first = 0, second = 0;
    for (size_t i = 0; i < single.size(); ++i) {
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(Bits(batched[i][c]), Bits(single[i][c]))
            << raygen << ": launch index " << i % kW << "," << i / kW << " component " << c;
      }
      first += single[i][0] == 0.f;
      second += single[i][0] == 1.f;
    }
    EXPECT_GT(first, 0u) << raygen;
    EXPECT_GT(second, 0u) << raygen;
  }
  // The `counts` buffer the count_* programs add one to per launch index, all zero.
  RTbuffer ZeroedCounts() {
    RTbuffer counts = Buffer2D("counts", RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, kW, kH);
    void* p = nullptr;
    Ok(rtBufferMap(counts, &p));
    std::memset(p, 0, sizeof(unsigned) * kW * kH);
    Ok(rtBufferUnmap(counts));
    return counts;
  }
  static uint32_t Bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof(u));
    return u;
  }

  RTbuffer wide_ = nullptr;
  RTmaterial material_ = nullptr;
  // Run and the Auto tests set TESSERA_BATCHING per launch; the run's own value comes back after.
  const test::ScopedEnv batching_{"TESSERA_BATCHING", nullptr};
};

TEST_P(BatchedTest, HitsAreThoseOfSingleRaysBitForBit) { ExpectSameAsSingleRays("plain"); }

// Only a launch's first trace of each index comes from a packet: a second one, and nested rays
// from the closest-hit program, trace alone and see the packet's hit kept.
TEST_P(BatchedTest, SecondAndNestedTracesTraceAlone) {
  ExpectSameAsSingleRays("trace_twice");
  RTmaterial nested = nullptr;
  Ok(rtMaterialCreate(ctx_, &nested));
  Ok(rtMaterialSetClosestHitProgram(nested, 0, B("closest_nested")));
  Ok(rtGeometryInstanceSetMaterial(instance_, 0, nested));
  ExpectSameAsSingleRays("plain");
}

// The geometry group below a Group (one flattened instance) takes packets too; an any-hit
// program (Embree calls the engine per candidate) makes every ray trace alone.
TEST_P(BatchedTest, GroupsAboveAndAnyHitProgramsGiveTheSameHits) {
  RTgroup top = nullptr;
  Ok(rtGroupCreate(ctx_, &top));
  Ok(rtGroupSetAcceleration(top, Accel("Bvh")));
  Ok(rtGroupSetChildCount(top, 1));
  Ok(rtGroupSetChild(top, 0, group_));
  Ok(rtVariableSetObject(ContextVar("top_object"), top));
  ExpectSameAsSingleRays("plain");
  Ok(rtMaterialSetAnyHitProgram(material_, 0, Prog("any_hit_skip_first")));
  const std::vector<Float4> single = Run("plain", false);
  const std::vector<Float4> batched = Run("plain", true);
  for (size_t i = 0; i < single.size(); ++i) EXPECT_EQ(batched[i], single[i]) << i;
}

// A write before the first trace happens once per launch: the engine's run of the ray generation
// program up to its trace ends at the first access to a buffer programs may write.
TEST_P(BatchedTest, BufferWritesBeforeTheFirstTraceHappenOnce) {
  RTbuffer counts = ZeroedCounts();
  const std::vector<Float4> plain = Run("plain", false);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(Run("count_then_trace", true), plain);
  for (unsigned c : ReadAs<unsigned>(counts)) ASSERT_EQ(c, 3u);
  // Through an id (rtBufferId), whose views programs read from a table without a call.
  int id = 0;
  Ok(rtBufferGetId(counts, &id));
  Ok(rtVariableSet1i(ContextVar("counts_by_id"), id));
  for (int k = 0; k < 2; ++k) EXPECT_EQ(Run("count_by_id_then_trace", true), plain);
  for (unsigned c : ReadAs<unsigned>(counts)) ASSERT_EQ(c, 5u);
}

TEST_P(BatchedTest, PrintsBeforeTheFirstTraceAppearOnce) {
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  constexpr unsigned kSide = 9;
  ::testing::internal::CaptureStdout();
  Run("print_then_trace", true, kSide, kSide);
  const std::string out = ::testing::internal::GetCapturedStdout();
  for (unsigned y = 0; y < kSide; ++y) {
    for (unsigned x = 0; x < kSide; ++x) {
      const std::string line = "index " + std::to_string(x) + " " + std::to_string(y) + "\n";
      const size_t at = out.find(line);
      ASSERT_NE(at, std::string::npos) << line << out;
      EXPECT_EQ(out.find(line, at + 1), std::string::npos) << "printed twice: " << line;
    }
  }
}

TEST_P(BatchedTest, ExceptionsBeforeTheFirstTraceReachTheExceptionProgramOnce) {
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  Ok(rtContextSetExceptionProgram(ctx_, 0, B("mark_exception")));
  const std::vector<Float4> single = Run("throw_then_trace", false);
  RTsize single_reports = 0;
  Ok(tesseraContextGetExceptionReportCount(ctx_, &single_reports));
  const std::vector<Float4> batched = Run("throw_then_trace", true);
  RTsize batched_reports = 0;
  Ok(tesseraContextGetExceptionReportCount(ctx_, &batched_reports));
  EXPECT_EQ(batched, single);
  EXPECT_EQ(batched_reports, single_reports);
  for (unsigned y = 0; y < kH; ++y) EXPECT_EQ(batched[y * kW + 2][0], -7.f) << y;
}

// With TESSERA_BATCHING=auto, an entry point chooses for itself (api/src/auto_batching.h): a
// program tracing one ray per launch index, which packets answer, runs its first launch on single
// rays, tries packets on the second and keeps them; every launch gives single rays' bits. The
// devices' counts reach the host from every device set, which therefore chooses alike.
TEST_P(BatchedTest, AutoTheFirstRaysOfPrimaryRayLaunchesBecomePacketsAndGiveTheSameBits) {
  const std::vector<Float4> single = Run("plain", false);
  setenv("TESSERA_BATCHING", "auto", 1);  // the launch with it at 0 measured nothing
  std::vector<int> batched;
  for (int k = 0; k < 3; ++k) {
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, kH);
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
    int b = -1;
    Ok(tesseraContextGetLastLaunchBatched(ctx_, &b));
    batched.push_back(b);
    const std::vector<Float4> out = Read(wide_);
    ASSERT_EQ(out.size(), single.size());
    for (size_t i = 0; i < out.size(); ++i) {
      for (int c = 0; c < 4; ++c) ASSERT_EQ(Bits(out[i][c]), Bits(single[i][c])) << k << " " << i;
    }
  }
  EXPECT_EQ(batched, (std::vector<int>{0, 1, 1}));
}

// A program that writes before its first trace cannot be answered by packets (its first run stops
// at the write): the try gives single rays' results and the entry point goes back to single rays.
TEST_P(BatchedTest, AutoAWriteBeforeTheTraceTriesPacketsOnceAndGoesBack) {
  RTbuffer counts = ZeroedCounts();
  const std::vector<Float4> plain = Run("plain", false);
  setenv("TESSERA_BATCHING", "auto", 1);
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, B("count_then_trace")));
  std::vector<int> batched;
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(rtContextLaunch2D(ctx_, 0, kW, kH), RT_SUCCESS);
    int b = -1;
    Ok(tesseraContextGetLastLaunchBatched(ctx_, &b));
    batched.push_back(b);
    EXPECT_EQ(Read(wide_), plain) << k;
  }
  EXPECT_EQ(batched, (std::vector<int>{0, 1, 0, 0}));
  for (unsigned c : ReadAs<unsigned>(counts)) ASSERT_EQ(c, 4u);
}

INSTANTIATE_TEST_SUITE_P(Devices, BatchedTest,
                         ::testing::Values("inproc", "local:2", "inproc,local:3"), DeviceName);

}  // namespace
}  // namespace tessera::testing
