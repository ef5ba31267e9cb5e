// The pipeline compile options a trace's scene must fit (docs/programs.md, "OptiX 7 pipelines"):
// a scene beyond traversableGraphFlags, usesPrimitiveTypeFlags or usesMotionBlur fails the launch
// with a message naming the traversable and the option (OptiX leaves it undefined), and one
// within them is traced as under options that allow everything.
#include <atomic>
#include <string>

#include "engine_fixture.h"
#include "runtime.h"

namespace tessera::optix7_test {
namespace {

class CompileOptionsTest : public EngineTest {
 protected:
  CompileOptionsTest() {
    sbt_.raygen = Raygen(trace_module(), "__raygen__trace");
    sbt_.miss = {Miss(trace_module(), "__miss__probe")};
    sbt_.hit = {HitGroup(trace_module(), "__closesthit__probe")};
  }

  // Traces one ray down -z onto `handle` at (0.25, 0.25): "" when the launch ran and hit
  // (record 0xA0, front face), else the launch's error message.
  std::string TraceOnto(OptixTraversableHandle handle) {
    EngineParams p = DownZ(0.25f, 0.25f);
    const CUdeviceptr out = Upload(std::vector<uint32_t>(ENGINE_WORDS, 0));
    p.out = reinterpret_cast<unsigned int*>(out);
    p.handle = handle;
    v1::Optix7Launch launch = MakeLaunch(sbt_, Upload(std::vector<EngineParams>{p}));
    launch.set_pipeline(Pipeline(2, 0));
    const absl::Status prepared = engine_->Prepare(state_, launch, nullptr);
    if (!prepared.ok()) return absl::StrCat("Prepare: ", prepared.message());
    const std::atomic<bool> cancel{false}, stop{false};
    v1::TileResult tile;
    try {
      engine_->RunTile({0, 0, 0}, {1, 1, 1}, {1, 1, 1}, cancel, stop, tile);
    } catch (const worker::FatalError& e) {
      return std::string(e.status.message());
    }
    uint32_t words[ENGINE_WORDS];
    EXPECT_EQ(
        cudaMemcpy(words, reinterpret_cast<void*>(out), sizeof(words), cudaMemcpyDeviceToHost),
        cudaSuccess);
    EXPECT_EQ(words[0], 0xA0u);
    EXPECT_EQ(words[2], static_cast<uint32_t>(OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE));
    return "";
  }

  Sbt sbt_;
};

TEST_F(CompileOptionsTest, ScenesWithinTheOptionsAreTraced) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(), {0, 1, 2})});
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 0, gas)})});
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  primitive_flags_ = OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE;
  motion_blur_ = false;
  EXPECT_EQ(TraceOnto(gas), "");
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING;
  EXPECT_EQ(TraceOnto(ias), "");
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
  primitive_flags_ = 0;  // OptiX's default: custom primitives and triangles
  EXPECT_EQ(TraceOnto(ias), "");
}

TEST_F(CompileOptionsTest, AnInstanceAccelerationUnderSingleGasFailsTheLaunch) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(), {0, 1, 2})});
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 0, gas)})});
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS;
  const std::string error = TraceOnto(ias);
  EXPECT_NE(error.find("optixTrace"), std::string::npos) << error;
  EXPECT_NE(error.find("is an instance acceleration"), std::string::npos) << error;
  EXPECT_NE(error.find("allow a single GAS only"), std::string::npos) << error;
}

TEST_F(CompileOptionsTest, NestedInstancesUnderSingleLevelInstancingFailTheLaunch) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(), {0, 1, 2})});
  const OptixTraversableHandle inner = Build({Instances({Translated(0.f, 0, gas)})});
  const OptixTraversableHandle outer = Build({Instances({Translated(0.f, 0, inner)})});
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING;
  const std::string error = TraceOnto(outer);
  EXPECT_NE(error.find("single-level instancing"), std::string::npos) << error;
  graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
  EXPECT_EQ(TraceOnto(outer), "");
}

TEST_F(CompileOptionsTest, PrimitivesTheOptionsLeaveOutFailTheLaunch) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(), {0, 1, 2})});
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 0, gas)})});
  primitive_flags_ = OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM;
  for (const OptixTraversableHandle h : {gas, ias}) {
    const std::string error = TraceOnto(h);
    EXPECT_NE(error.find("usesPrimitiveTypeFlags are 0x1"), std::string::npos) << error;
    EXPECT_NE(error.find("types 0x80000000"), std::string::npos) << error;
  }
}

TEST_F(CompileOptionsTest, MotionUnderUsesMotionBlurZeroFailsTheLaunch) {
  // Two keys of the same triangle: it has motion, though nothing moves.
  const CUdeviceptr keys[2] = {Upload(Triangle()), Upload(Triangle())};
  OptixBuildInput in = Triangles(Triangle(), {0, 1, 2});
  in.triangleArray.vertexBuffers = keys;
  const OptixTraversableHandle moving = Build({in}, OptixMotionOptions{2, 0, 0.f, 1.f});
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 0, moving)})});
  motion_blur_ = false;
  for (const OptixTraversableHandle h : {moving, ias}) {
    const std::string error = TraceOnto(h);
    EXPECT_NE(error.find("has motion"), std::string::npos) << error;
    EXPECT_NE(error.find("usesMotionBlur 0"), std::string::npos) << error;
  }
  motion_blur_ = true;
  EXPECT_EQ(TraceOnto(ias), "");
}

}  // namespace
}  // namespace tessera::optix7_test
