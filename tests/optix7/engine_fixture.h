// What the engine tests share: device memory (cudaMalloc, tracked as the device's allocations),
// accelerations built as optixAccelBuild builds them, program groups of the test modules (stored in
// a temporary module cache), SBT records packed as optixSbtRecordPackHeader packs them, and one
// launch run through Optix7Engine::Prepare and RunTile.
#ifndef TESSERA_TESTS_OPTIX7_ENGINE_FIXTURE_H_
#define TESSERA_TESTS_OPTIX7_ENGINE_FIXTURE_H_

#include <cuda_runtime.h>
#include <embree3/rtcore.h>
#include <gtest/gtest.h>
#include <optix_types.h>
#include <vector_types.h>

#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "optix7_engine.h"
#include "programs/engine_params.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::optix7_test {

// A module of the test, stored in the module cache.
struct TestModule {
  std::string hash;
  std::string path;
};

// The SBT of a launch by program group: record i of a section gets the value (RecordData) of its
// section's base plus i.
struct Sbt {
  static constexpr uint32_t kRaygenValue = 0xCAFE, kExceptionValue = 0xE0, kMissBase = 0x100,
                            kHitBase = 0xA0, kCallablesBase = 100;
  uint64_t raygen = 0;
  uint64_t exception = 0;  // 0: none
  std::vector<uint64_t> miss, hit, callables;
};

struct Result {
  absl::Status prepared;
  std::vector<uint32_t> out;  // ENGINE_WORDS per launch index
  v1::TileResult tile;
  uint32_t word(unsigned index, unsigned k) const { return out[index * ENGINE_WORDS + k]; }
  float real(unsigned index, unsigned k) const;
};

// One triangle of the z plane at x0, winding counter-clockwise seen from +z.
inline std::vector<float> Triangle(float x0 = 0.f, float z = 0.f) {
  return {x0, 0, z, x0 + 1, 0, z, x0, 1, z};
}

// An instance of `child` moved by tx along x, all visibility bits set.
inline OptixInstance Translated(float tx, unsigned id, OptixTraversableHandle child) {
  OptixInstance inst{};
  const float t[12] = {1, 0, 0, tx, 0, 1, 0, 0, 0, 0, 1, 0};
  std::memcpy(inst.transform, t, sizeof(t));
  inst.instanceId = id;
  inst.visibilityMask = 0xFF;
  inst.traversableHandle = child;
  return inst;
}

class EngineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  EngineTest();
  ~EngineTest() override;

  static const TestModule& trace_module() { return *trace_module_; }
  static const TestModule& calls_module() { return *calls_module_; }

  // Device memory, recorded as a live allocation of the device's state.
  CUdeviceptr Alloc(size_t bytes);
  template <typename T>
  CUdeviceptr Upload(const std::vector<T>& values) {
    const CUdeviceptr p = Alloc(values.size() * sizeof(T));
    EXPECT_EQ(cudaMemcpy(reinterpret_cast<void*>(p), values.data(), values.size() * sizeof(T),
                         cudaMemcpyHostToDevice),
              cudaSuccess);
    return p;
  }

  // Build inputs whose host arrays live as long as the test.
  OptixBuildInput Triangles(const std::vector<float>& vertices,
                            const std::vector<uint32_t>& indices, unsigned geometry_flags = 0,
                            unsigned primitive_index_offset = 0,
                            const std::vector<uint32_t>& sbt_index_offsets = {});
  OptixBuildInput Spheres(const std::vector<float4>& spheres);  // their boxes
  OptixBuildInput Instances(const std::vector<OptixInstance>& instances);
  OptixTraversableHandle Build(const std::vector<OptixBuildInput>& inputs,
                               const OptixMotionOptions& motion = {});
  // Device memory of `bytes` bytes at OPTIX_TRANSFORM_BYTE_ALIGNMENT holding `data`, and its
  // handle as optixConvertPointerToTraversableHandle makes it (the type in the low bits).
  OptixTraversableHandle Transform(const void* data, size_t bytes, OptixTransformType type);

  // Program groups of the pipeline (every group made so far), by kind.
  uint64_t Raygen(const TestModule& m, const std::string& fn);
  uint64_t Miss(const TestModule& m, const std::string& fn);
  uint64_t Exception(const TestModule& m, const std::string& fn);
  uint64_t HitGroup(const TestModule& m, const std::string& ch, const std::string& ah = "",
                    const std::string& is = "");
  uint64_t Callables(const TestModule& m, const std::string& dc, const std::string& cc = "");

  // Writes the SBT's records and launches `width` x 1 launch indices in one tile (or in tiles of
  // `tile_width`, on `threads` threads).
  Result Run(const Sbt& sbt, EngineParams params, unsigned width, unsigned max_trace_depth = 2,
             unsigned exception_flags = 0, unsigned tile_width = 0, unsigned threads = 1);
  // The launch request Run would make, its records written (for tests that break them).
  v1::Optix7Launch MakeLaunch(const Sbt& sbt, CUdeviceptr params);
  CUdeviceptr Records(const std::vector<uint64_t>& groups, uint32_t first_value);
  uint64_t Pipeline(unsigned max_trace_depth, unsigned exception_flags);
  // Params with a ray down -z from (x0, y, 1) stepping +1 in x per launch index, tmax 100.
  static EngineParams DownZ(float x0, float y);

  // The compile options Pipeline gives the launch's pipeline (by default what allows everything).
  unsigned graph_flags_ = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
  unsigned primitive_flags_ = ~0u;  // every OptixPrimitiveTypeFlags bit
  bool motion_blur_ = true;
  // Whether launches run in blocks of lanes with packets (Optix7Launch.batched).
  bool batched_ = false;

  worker::Optix7State state_;
  RTCDevice device_;
  std::unique_ptr<worker::Optix7Engine> engine_;

 private:
  uint64_t Group(uint32_t kind, const TestModule& m, const std::string& entry,
                 const std::string& continuation, const std::string& ch, const std::string& ah,
                 const std::string& is);

  static TestModule* trace_module_;
  static TestModule* calls_module_;
  uint64_t next_id_ = 1;
  std::deque<CUdeviceptr> buffers_;   // freed with the test
  std::deque<CUdeviceptr> pointers_;  // arrays of one buffer pointer, for build inputs
  std::deque<std::vector<unsigned>> flags_;
};

}  // namespace tessera::optix7_test

#endif  // TESSERA_TESTS_OPTIX7_ENGINE_FIXTURE_H_
