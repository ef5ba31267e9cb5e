// The OptiX 7 engine's calls and failures end to end: direct and continuation callables, user
// exceptions and trace depth overflow reaching the exception program (or, without one, the tile's
// reports), SBTs Prepare refuses naming the record, and output that does not depend on tiling or
// threads.
#include "engine_fixture.h"

namespace tessera::optix7_test {
namespace {

TEST_F(EngineTest, DirectAndContinuationCallables) {
  EngineParams p = DownZ(0.25f, 0.5f);
  p.step.x = 2.f;  // the continuation callable's ray: x = 0.25 hits, 2.25 and 4.25 miss
  p.handle = Build({Triangles(Triangle(), {0, 1, 2})});
  Sbt sbt;
  sbt.raygen = Raygen(calls_module(), "__raygen__callables");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe")};
  sbt.callables = {Callables(calls_module(), "__direct_callable__mul_add"),
                   Callables(calls_module(), "__direct_callable__square"),
                   Callables(calls_module(), "", "__continuation_callable__trace")};
  const Result r = Run(sbt, p, 3);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  for (uint32_t x = 0; x < 3; ++x) {
    SCOPED_TRACE(x);
    EXPECT_EQ(r.word(x, 0), x * 3 + Sbt::kCallablesBase);              // its own record's data
    EXPECT_EQ(r.word(x, 1), x * x + 3 + 0 * 0 + Sbt::kCallablesBase);  // which calls record 0
    EXPECT_EQ(r.word(x, 2), x == 0 ? 0xA0u : Sbt::kMissBase);          // traced from the callable
    EXPECT_EQ(r.word(x, 3), Sbt::kRaygenValue);  // the caller's record again after the calls
  }
  // Launch index 2 calls record 7 of 3: CALLABLE_INVALID_SBT, reported without an exception
  // program, and the index ends there.
  EXPECT_EQ(r.word(2, 4), 0u);
  ASSERT_EQ(r.tile.exceptions_size(), 1);
  const v1::ExceptionReport& e = r.tile.exceptions(0);
  EXPECT_EQ(static_cast<int>(e.code()), OPTIX_EXCEPTION_CODE_CALLABLE_INVALID_SBT);
  EXPECT_EQ(e.launch_index(0), 2u);
  EXPECT_NE(e.details().find("optixDirectCall(7) past the 3 callable records"), std::string::npos)
      << e.details();

  // A record without the kind of callable called: a direct call of a continuation callable.
  sbt.callables = {Callables(calls_module(), "__direct_callable__mul_add"),
                   Callables(calls_module(), "", "__continuation_callable__trace"),
                   Callables(calls_module(), "", "__continuation_callable__trace")};
  const Result no_dc = Run(sbt, p, 1);
  ASSERT_TRUE(no_dc.prepared.ok()) << no_dc.prepared;
  ASSERT_EQ(no_dc.tile.exceptions_size(), 1);
  EXPECT_EQ(static_cast<int>(no_dc.tile.exceptions(0).code()),
            OPTIX_EXCEPTION_CODE_CALLABLE_NO_DC_SBT_RECORD);
}

TEST_F(EngineTest, UserExceptionReachesTheExceptionProgram) {
  Sbt sbt;
  sbt.raygen = Raygen(calls_module(), "__raygen__throw");
  sbt.exception = Exception(calls_module(), "__exception__record");
  const Result r = Run(sbt, EngineParams{}, 3, 2, OPTIX_EXCEPTION_FLAG_USER);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 1u);
  EXPECT_EQ(r.word(1, 0), 42u);  // the code, its two details, the exception record's data
  EXPECT_EQ(r.word(1, 1), 7u);
  EXPECT_EQ(r.word(1, 2), 8u);
  EXPECT_EQ(r.word(1, 3), Sbt::kExceptionValue);
  EXPECT_EQ(r.word(2, 0), 1u);
  EXPECT_EQ(r.tile.exceptions_size(), 0);  // handled

  // Without an exception program: a report with the code, the launch index and the details.
  sbt.exception = 0;
  const Result unhandled = Run(sbt, EngineParams{}, 3, 2, OPTIX_EXCEPTION_FLAG_USER);
  ASSERT_TRUE(unhandled.prepared.ok()) << unhandled.prepared;
  EXPECT_EQ(unhandled.word(1, 0), 0u);  // the index ended at the throw
  ASSERT_EQ(unhandled.tile.exceptions_size(), 1);
  const v1::ExceptionReport& e = unhandled.tile.exceptions(0);
  EXPECT_EQ(e.code(), 42u);
  ASSERT_EQ(e.launch_index_size(), 3);
  EXPECT_EQ(e.launch_index(0), 1u);
  EXPECT_NE(e.details().find("user exception 42 with details 0x7, 0x8"), std::string::npos)
      << e.details();
  EXPECT_NE(e.details().find("__raygen__throw"), std::string::npos) << e.details();
}

TEST_F(EngineTest, TraceDepthOverflowReachesTheExceptionProgram) {
  // The closest-hit program traces again from every hit, until the depth is 5.
  EngineParams p = DownZ(0.25f, 0.5f);
  p.handle = Build({Triangles(Triangle(), {0, 1, 2})});
  p.recursion = 5;
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__recurse");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__recurse")};
  sbt.exception = Exception(calls_module(), "__exception__record");
  Result r = Run(sbt, p, 1, /*max_trace_depth=*/5, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 5u);  // deep enough: every level returned its depth
  EXPECT_EQ(r.tile.exceptions_size(), 0);

  r = Run(sbt, p, 1, /*max_trace_depth=*/2, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(static_cast<int>(r.word(0, 0)), OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED);
  EXPECT_EQ(r.word(0, 3), Sbt::kExceptionValue);

  sbt.exception = 0;
  r = Run(sbt, p, 1, /*max_trace_depth=*/2, OPTIX_EXCEPTION_FLAG_TRACE_DEPTH);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  ASSERT_EQ(r.tile.exceptions_size(), 1);
  EXPECT_EQ(static_cast<int>(r.tile.exceptions(0).code()),
            OPTIX_EXCEPTION_CODE_TRACE_DEPTH_EXCEEDED);
  EXPECT_NE(r.tile.exceptions(0).details().find("optixTrace 3 deep exceeds the pipeline's "
                                                "maxTraceDepth 2"),
            std::string::npos)
      << r.tile.exceptions(0).details();
}

TEST_F(EngineTest, PrepareNamesTheBadSbtRecord) {
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  const uint64_t miss = Miss(trace_module(), "__miss__probe");
  const uint64_t probe = HitGroup(trace_module(), "__closesthit__probe");
  sbt.miss = {miss};
  sbt.hit = {probe, probe, probe};
  EngineParams p = DownZ(0, 0);
  p.out = reinterpret_cast<unsigned int*>(Alloc(ENGINE_WORDS * 4));
  v1::Optix7Launch launch = MakeLaunch(sbt, Upload(std::vector<EngineParams>{p}));
  launch.set_pipeline(Pipeline(2, 0));
  ASSERT_TRUE(engine_->Prepare(state_, launch, nullptr).ok());

  // Record 1 never packed: its header is zeros.
  const CUdeviceptr record1 = launch.hitgroup_record_base() + launch.hitgroup_record_stride();
  ASSERT_EQ(cudaMemset(reinterpret_cast<void*>(record1), 0, 32), cudaSuccess);
  absl::Status s = engine_->Prepare(state_, launch, nullptr);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find(absl::StrCat("SBT hit group record 1 at 0x", absl::Hex(record1),
                                          ": the header was not packed")),
            std::string::npos)
      << s;

  // A miss record where a hit group record belongs.
  launch = MakeLaunch(Sbt{sbt.raygen, 0, {miss}, {probe, miss}, {}}, launch.params());
  launch.set_pipeline(Pipeline(2, 0));
  s = engine_->Prepare(state_, launch, nullptr);
  EXPECT_NE(s.message().find("SBT hit group record 1 at"), std::string::npos) << s;
  EXPECT_NE(s.message().find("whose kind is miss, not hit group"), std::string::npos) << s;

  // A stride that is no multiple of 16.
  launch = MakeLaunch(sbt, launch.params());
  launch.set_pipeline(Pipeline(2, 0));
  launch.set_miss_record_stride(40);
  s = engine_->Prepare(state_, launch, nullptr);
  EXPECT_NE(s.message().find("SBT miss records at 0x"), std::string::npos) << s;
  EXPECT_NE(s.message().find("stride 40"), std::string::npos) << s;

  // A program group of another pipeline.
  v1::Optix7Pipeline other = state_.pipelines.at(launch.pipeline());
  other.clear_program_groups();
  other.add_program_groups(sbt.raygen);
  other.add_program_groups(miss);
  state_.pipelines[other.id()] = other;
  launch.set_miss_record_stride(48);
  s = engine_->Prepare(state_, launch, nullptr);
  EXPECT_NE(s.message().find(absl::StrCat(
                "SBT hit group record 0 at 0x", absl::Hex(launch.hitgroup_record_base()),
                ": packed for program group ", probe, ", which is not in the launch's pipeline")),
            std::string::npos)
      << s;

  // An entry function the module does not define.
  const uint64_t missing = HitGroup(trace_module(), "__closesthit__nowhere");
  launch = MakeLaunch(Sbt{sbt.raygen, 0, {miss}, {missing}, {}}, launch.params());
  launch.set_pipeline(Pipeline(2, 0));
  s = engine_->Prepare(state_, launch, nullptr);
  EXPECT_EQ(s.code(), absl::StatusCode::kNotFound);
  EXPECT_NE(s.message().find(
                absl::StrCat("program group ", missing, " (hit group): __closesthit__nowhere")),
            std::string::npos)
      << s;
}

TEST_F(EngineTest, OutputDoesNotDependOnTilesOrThreads) {
  // Instances of a GAS of two inputs, with an any-hit program that ignores some hits.
  std::vector<float> grid;
  std::vector<uint32_t> indices;
  for (int k = 0; k < 8; ++k) {
    const float x = static_cast<float>(k);
    grid.insert(grid.end(), {x, 0, -0.1f * k, x + 1, 0, -0.1f * k, x, 1, -0.1f * k});
    for (uint32_t v = 0; v < 3; ++v) indices.push_back(3 * k + v);
  }
  const OptixTraversableHandle gas = Build({Triangles(grid, indices)});
  const float a[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const float b[12] = {0.5f, 0, 0, 0.3f, 0, 1, 0, 0, 0, 0, 1, -2};
  OptixInstance i0{}, i1{};
  std::memcpy(i0.transform, a, sizeof(a));
  std::memcpy(i1.transform, b, sizeof(b));
  i0.visibilityMask = i1.visibilityMask = 0xFF;
  i0.traversableHandle = i1.traversableHandle = gas;
  i1.instanceId = 7;
  EngineParams p = DownZ(-0.5f, 0.4f);
  p.step.x = 0.125f;
  p.handle = Build({Instances({i0, i1})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__ignore_even")};
  const Result one = Run(sbt, p, 80);
  const Result tiled = Run(sbt, p, 80, 2, 0, /*tile_width=*/7, /*threads=*/2);
  ASSERT_TRUE(one.prepared.ok()) << one.prepared;
  ASSERT_TRUE(tiled.prepared.ok()) << tiled.prepared;
  EXPECT_EQ(one.out, tiled.out);
  // Both instances and the miss program are in the picture.
  unsigned hits[2] = {0, 0}, misses = 0;
  for (unsigned i = 0; i < 80; ++i) {
    if (one.word(i, 0) == Sbt::kMissBase) {
      ++misses;
    } else {
      ++hits[one.word(i, 8)];
    }
  }
  EXPECT_GT(hits[0], 0u);
  EXPECT_GT(hits[1], 0u);
  EXPECT_GT(misses, 0u);
}

}  // namespace
}  // namespace tessera::optix7_test
