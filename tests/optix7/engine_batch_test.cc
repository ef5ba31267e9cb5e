// Batched tracing (optix7_batch.h): launch indices run as lanes in blocks whose rays go to Embree
// as 16-wide packets must see what they see one ray at a time: hits, payloads, instances,
// recursion from closest-hit programs, exceptions raised in a lane, and traces that need a
// callback per hit (any-hit programs), which a lane traces alone.
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "engine_fixture.h"

namespace tessera::optix7_test {
namespace {

class BatchTest : public EngineTest {
 protected:
  // The launch run one ray at a time and in lanes (one thread, then two with tiles of one
  // block): every word the programs wrote must be the same. `ties`: the scene has hits at
  // exactly the same t, which Embree's packet and single-ray kernels may resolve differently
  // (Embree issue 387): then lanes need only agree with lanes, whatever the threads and tiles.
  void ExpectSameAsSingleRays(const Sbt& sbt, const EngineParams& p, unsigned width,
                              unsigned max_depth = 2, unsigned exception_flags = 0,
                              bool ties = false) {
    batched_ = false;
    const Result single = Run(sbt, p, width, max_depth, exception_flags);
    ASSERT_TRUE(single.prepared.ok()) << single.prepared;
    batched_ = true;
    const Result lanes = Run(sbt, p, width, max_depth, exception_flags);
    ASSERT_TRUE(lanes.prepared.ok()) << lanes.prepared;
    const Result threads = Run(sbt, p, width, max_depth, exception_flags, 16, 2);
    ASSERT_TRUE(threads.prepared.ok()) << threads.prepared;
    if (!ties) {
      EXPECT_EQ(single.out, lanes.out);
    }
    EXPECT_EQ(lanes.out, threads.out);
    EXPECT_EQ(single.tile.exceptions_size(), lanes.tile.exceptions_size());
  }
};

TEST_F(BatchTest, TrianglesAndInstancesSeeWhatSingleRaysSee) {
  std::vector<float> row;
  for (int k = 0; k < 12; ++k) {
    const std::vector<float> t = Triangle(2.f * k);
    row.insert(row.end(), t.begin(), t.end());
  }
  std::vector<uint32_t> indices(36);
  for (uint32_t i = 0; i < 36; ++i) indices[i] = i;
  const OptixTraversableHandle gas = Build({Triangles(row, indices)});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe")};
  EngineParams p = DownZ(0.25f, 0.5f);
  p.step.x = 0.75f;  // hits and misses alternate irregularly over 40 indices: 3 blocks, one part
  p.handle = gas;
  ExpectSameAsSingleRays(sbt, p, 40);
  p.handle = Build({Instances({Translated(0.f, 7, gas), Translated(24.f, 9, gas)})});
  p.step.x = 1.5f;  // over both instances
  ExpectSameAsSingleRays(sbt, p, 40);
  // Two instances in the same place: every hit is a tie between them.
  p.handle = Build({Instances({Translated(0.f, 7, gas), Translated(0.f, 9, gas)})});
  ExpectSameAsSingleRays(sbt, p, 40, 2, 0, /*ties=*/true);
}

TEST_F(BatchTest, ClosestHitRecursionAndExceptionsInLanes) {
  EngineParams p = DownZ(0.25f, 0.5f);
  p.step.x = 0.f;
  p.handle = Build({Triangles(Triangle(0), {0, 1, 2})});
  p.recursion = 5;
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__recurse");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__recurse")};
  sbt.exception = Exception(calls_module(), "__exception__record");
  ExpectSameAsSingleRays(sbt, p, 20, /*max_depth=*/5, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  batched_ = true;
  Result r = Run(sbt, p, 20, 5, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  EXPECT_EQ(r.word(19, 0), 5u);  // every level of every lane returned its depth
  // Too deep: every lane raises TRACE_DEPTH_EXCEEDED, which its exception program records.
  ExpectSameAsSingleRays(sbt, p, 20, /*max_depth=*/2, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  r = Run(sbt, p, 20, 2, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  EXPECT_EQ(static_cast<int>(r.word(17, 0)), OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED);
  // Without an exception program one report goes out and the rest are counted, as per thread.
  sbt.exception = 0;
  r = Run(sbt, p, 20, 2, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  ASSERT_GE(r.tile.exceptions_size(), 1);
  EXPECT_EQ(r.tile.exceptions(0).launch_index(0), 0u);
}

TEST_F(BatchTest, AnyHitTracesRunAloneInTheirLanes) {
  std::vector<float> two = Triangle(0);
  const std::vector<float> behind = {0, 0, -1, 1, 0, -1, 0, 1, -1};
  two.insert(two.end(), behind.begin(), behind.end());
  const OptixTraversableHandle gas = Build({Triangles(two, {0, 1, 2, 3, 4, 5})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__ignore_even")};
  EngineParams p = DownZ(0.05f, 0.05f);
  p.step.x = 0.05f;
  p.handle = gas;
  ExpectSameAsSingleRays(sbt, p, 24);
}

// Recursion without end in a lane's programs raises STACK_OVERFLOW at the lane's own stack budget,
// as on the thread's stack: reported without an exception program, handled by one, and the
// worker goes on with the next launch index either way.
TEST_F(BatchTest, StackOverflowInLanes) {
  Sbt sbt;
  sbt.raygen = Raygen(calls_module(), "__raygen__deep");
  sbt.callables = {Callables(calls_module(), "__direct_callable__forever")};
  for (bool batched : {false, true}) {
    SCOPED_TRACE(batched ? "lanes" : "single rays");
    batched_ = batched;
    sbt.exception = 0;
    Result r = Run(sbt, EngineParams{}, 4);
    ASSERT_TRUE(r.prepared.ok()) << r.prepared;
    for (uint32_t x = 0; x < 4; ++x) {
      EXPECT_EQ(r.word(x, 0), 1u) << x;
      EXPECT_EQ(r.word(x, 2), 0u) << x;  // the index ended at the overflow
    }
    ASSERT_GE(r.tile.exceptions_size(), 1);
    EXPECT_EQ(static_cast<int>(r.tile.exceptions(0).code()), OPTIX_EXCEPTION_CODE_STACK_OVERFLOW);
    sbt.exception = Exception(calls_module(), "__exception__record");
    r = Run(sbt, EngineParams{}, 4);
    ASSERT_TRUE(r.prepared.ok()) << r.prepared;
    for (uint32_t x = 0; x < 4; ++x) {
      EXPECT_EQ(static_cast<int>(r.word(x, 0)), OPTIX_EXCEPTION_CODE_STACK_OVERFLOW) << x;
      EXPECT_EQ(r.word(x, 3), Sbt::kExceptionValue) << x;
    }
    EXPECT_EQ(r.tile.exceptions_size(), 0);
  }
}

// A cancelled launch ends a lane whose program never returns (the signal lands in program code on
// the lane's stack and jumps back to the tile), and the thread's lanes trace the next launch.
TEST_F(BatchTest, CancelEndsEndlessLanes) {
  Sbt sbt;
  sbt.raygen = Raygen(calls_module(), "__raygen__endless");
  for (bool batched : {false, true}) {
    SCOPED_TRACE(batched ? "lanes" : "single rays");
    batched_ = batched;
    EngineParams p;
    p.out = reinterpret_cast<unsigned int*>(Upload(std::vector<uint32_t>(16 * ENGINE_WORDS, 0)));
    v1::Optix7Launch launch = MakeLaunch(sbt, Upload(std::vector<EngineParams>{p}));
    launch.set_pipeline(Pipeline(2, 0));
    const absl::Status prepared = engine_->Prepare(state_, launch, nullptr);
    ASSERT_TRUE(prepared.ok()) << prepared;
    std::atomic<bool> cancel{false};
    const std::atomic<bool> stop{false};
    std::thread canceller([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      cancel = true;
    });
    const auto start = std::chrono::steady_clock::now();
    v1::TileResult tile;
    EXPECT_FALSE(engine_->RunTile({0, 0, 0}, {16, 1, 1}, {16, 1, 1}, cancel, stop, tile));
    const auto took = std::chrono::steady_clock::now() - start;
    canceller.join();
    EXPECT_LT(took, std::chrono::seconds(10));

    // The same thread traces a whole launch afterwards.
    Sbt trace;
    trace.raygen = Raygen(trace_module(), "__raygen__trace");
    trace.miss = {Miss(trace_module(), "__miss__probe")};
    trace.hit = {HitGroup(trace_module(), "__closesthit__probe")};
    EngineParams down = DownZ(0.25f, 0.5f);
    down.step.x = 0.f;
    down.handle = Build({Triangles(Triangle(0), {0, 1, 2})});
    const Result r = Run(trace, down, 16);
    ASSERT_TRUE(r.prepared.ok()) << r.prepared;
    EXPECT_EQ(r.word(15, 0), Sbt::kHitBase);  // every launch index hits the triangle's record
  }
}

}  // namespace
}  // namespace tessera::optix7_test
