// Accelerations through the API: sizes, builds with emitted properties (the compacted size, the
// bounds), compaction and relocation as copies, an instance build over them, and transform
// handles.
#include <cuda_runtime.h>

#include <cstddef>
#include <cstring>
#include <vector>

#include "host_api_fixture.h"

namespace tessera_test {
namespace {

using AccelTest = OptixHostTest;

CUdeviceptr Alloc(size_t bytes) {
  void* p = nullptr;
  EXPECT_EQ(cudaMalloc(&p, bytes), cudaSuccess);
  return reinterpret_cast<CUdeviceptr>(p);
}

template <typename T>
CUdeviceptr Upload(const std::vector<T>& values) {
  const CUdeviceptr p = Alloc(values.size() * sizeof(T));
  EXPECT_EQ(cudaMemcpy(reinterpret_cast<void*>(p), values.data(), values.size() * sizeof(T),
                       cudaMemcpyHostToDevice),
            cudaSuccess);
  return p;
}

template <typename T>
T Download(CUdeviceptr p) {
  T value{};
  EXPECT_EQ(cudaMemcpy(&value, reinterpret_cast<void*>(p), sizeof(T), cudaMemcpyDeviceToHost),
            cudaSuccess);
  return value;
}

void ExpectBox(const OptixAabb& box, float x0, float y0, float z0, float x1, float y1, float z1) {
  EXPECT_EQ(box.minX, x0);
  EXPECT_EQ(box.minY, y0);
  EXPECT_EQ(box.minZ, z0);
  EXPECT_EQ(box.maxX, x1);
  EXPECT_EQ(box.maxY, y1);
  EXPECT_EQ(box.maxZ, z1);
}

TEST_F(AccelTest, BuildEmitCompactRelocateAndInstance) {
  // Two triangles; the vertex (9, 9, 9) is referenced by no index and bounds nothing.
  const std::vector<float> vertices = {0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 9, 9, 9};
  const std::vector<unsigned> indices = {0, 1, 2, 0, 1, 3};
  const CUdeviceptr vertex_buffer = Upload(vertices);
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  OptixBuildInput input{};
  input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  input.triangleArray.numVertices = 5;
  input.triangleArray.vertexBuffers = &vertex_buffer;
  input.triangleArray.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  input.triangleArray.numIndexTriplets = 2;
  input.triangleArray.indexBuffer = Upload(indices);
  input.triangleArray.flags = &flags;
  input.triangleArray.numSbtRecords = 1;
  OptixAccelBuildOptions options{};
  options.buildFlags = OPTIX_BUILD_FLAG_ALLOW_COMPACTION;
  options.operation = OPTIX_BUILD_OPERATION_BUILD;

  OptixAccelBufferSizes sizes{};
  ASSERT_EQ(optixAccelComputeMemoryUsage(context_, &options, &input, 1, &sizes), OPTIX_SUCCESS);
  EXPECT_GT(sizes.outputSizeInBytes, 64u);
  EXPECT_GT(sizes.tempSizeInBytes, 0u);
  const CUdeviceptr temp = Alloc(sizes.tempSizeInBytes);
  const CUdeviceptr output = Alloc(sizes.outputSizeInBytes);
  const CUdeviceptr emitted = Alloc(64);
  OptixAccelEmitDesc emit[2] = {{emitted, OPTIX_PROPERTY_TYPE_COMPACTED_SIZE},
                                {emitted + 8, OPTIX_PROPERTY_TYPE_AABBS}};
  OptixTraversableHandle gas = 0;
  EXPECT_EQ(optixAccelBuild(context_, 0, &options, &input, 1, 0, 0, output, sizes.outputSizeInBytes,
                            &gas, emit, 2),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "optixAccelBuild: tempBuffer 0x0 of 0 bytes"));
  EXPECT_EQ(optixAccelBuild(context_, 0, &options, &input, 1, temp, sizes.tempSizeInBytes,
                            output + 64, sizes.outputSizeInBytes, &gas, emit, 2),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "not 128-byte aligned"));
  OptixAccelEmitDesc bad_emit = {emitted + 4, OPTIX_PROPERTY_TYPE_COMPACTED_SIZE};
  EXPECT_EQ(optixAccelBuild(context_, 0, &options, &input, 1, temp, sizes.tempSizeInBytes, output,
                            sizes.outputSizeInBytes, &gas, &bad_emit, 1),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "emittedProperties[0].result"));
  ASSERT_EQ(optixAccelBuild(context_, 0, &options, &input, 1, temp, sizes.tempSizeInBytes, output,
                            sizes.outputSizeInBytes, &gas, emit, 2),
            OPTIX_SUCCESS);
  EXPECT_EQ(gas, output);
  const size_t compacted = Download<size_t>(emitted);
  EXPECT_EQ(compacted, sizes.outputSizeInBytes);  // compaction is a copy
  ExpectBox(Download<OptixAabb>(emitted + 8), 0, 0, 0, 1, 2, 3);

  // Compaction into a buffer of the compacted size: the same bytes elsewhere.
  const CUdeviceptr compact_buffer = Alloc(compacted);
  OptixTraversableHandle compact = 0;
  EXPECT_EQ(optixAccelCompact(context_, 0, gas, compact_buffer, compacted - 8, &compact),
            OPTIX_ERROR_INVALID_VALUE);
  ASSERT_EQ(optixAccelCompact(context_, 0, gas, compact_buffer, compacted, &compact),
            OPTIX_SUCCESS);
  EXPECT_EQ(compact, compact_buffer);
  std::vector<unsigned char> a(compacted), b(compacted);
  ASSERT_EQ(cudaMemcpy(a.data(), reinterpret_cast<void*>(gas), compacted, cudaMemcpyDefault),
            cudaSuccess);
  ASSERT_EQ(cudaMemcpy(b.data(), reinterpret_cast<void*>(compact), compacted, cudaMemcpyDefault),
            cudaSuccess);
  EXPECT_EQ(a, b);
  EXPECT_EQ(optixAccelCompact(context_, 0, vertex_buffer, compact_buffer, compacted, &compact),
            OPTIX_ERROR_INVALID_VALUE);  // not an acceleration

  // Relocation: the application copies, optixAccelRelocate accepts the copy.
  OptixRelocationInfo info{};
  ASSERT_EQ(optixAccelGetRelocationInfo(context_, gas, &info), OPTIX_SUCCESS);
  int compatible = -1;
  ASSERT_EQ(optixCheckRelocationCompatibility(context_, &info, &compatible), OPTIX_SUCCESS);
  EXPECT_EQ(compatible, 1);
  OptixRelocationInfo foreign = info;
  foreign.info[0] ^= 1;
  ASSERT_EQ(optixCheckRelocationCompatibility(context_, &foreign, &compatible), OPTIX_SUCCESS);
  EXPECT_EQ(compatible, 0);
  const CUdeviceptr moved = Alloc(compacted);
  ASSERT_EQ(cudaMemcpy(reinterpret_cast<void*>(moved), reinterpret_cast<void*>(gas), compacted,
                       cudaMemcpyDeviceToDevice),
            cudaSuccess);
  OptixTraversableHandle relocated = 0;
  EXPECT_EQ(optixAccelRelocate(context_, 0, &foreign, nullptr, 0, moved, compacted, &relocated),
            OPTIX_ERROR_NOT_COMPATIBLE);
  ASSERT_EQ(optixAccelRelocate(context_, 0, &info, nullptr, 0, moved, compacted, &relocated),
            OPTIX_SUCCESS);
  EXPECT_EQ(relocated, moved);

  // An instance of the GAS moved by (10, 0, 0): its bounds follow.
  OptixInstance instance{};
  const float transform[12] = {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0};
  std::memcpy(instance.transform, transform, sizeof(transform));
  instance.visibilityMask = 255;
  instance.traversableHandle = gas;
  const CUdeviceptr instances = Upload(std::vector<OptixInstance>{instance});
  OptixBuildInput ias_input{};
  ias_input.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  ias_input.instanceArray.instances = instances;
  ias_input.instanceArray.numInstances = 1;
  OptixAccelBufferSizes ias_sizes{};
  ASSERT_EQ(optixAccelComputeMemoryUsage(context_, &options, &ias_input, 1, &ias_sizes),
            OPTIX_SUCCESS);
  const CUdeviceptr ias_buffer = Alloc(ias_sizes.outputSizeInBytes);
  OptixTraversableHandle ias = 0;
  ASSERT_EQ(optixAccelBuild(context_, 0, &options, &ias_input, 1, temp, sizes.tempSizeInBytes,
                            ias_buffer, ias_sizes.outputSizeInBytes, &ias, &emit[1], 1),
            OPTIX_SUCCESS);
  ExpectBox(Download<OptixAabb>(emitted + 8), 10, 0, 0, 11, 2, 3);

  // Relocating the instance build replaces its child's handle with the relocated GAS.
  OptixRelocationInfo ias_info{};
  ASSERT_EQ(optixAccelGetRelocationInfo(context_, ias, &ias_info), OPTIX_SUCCESS);
  const CUdeviceptr ias_moved = Alloc(ias_sizes.outputSizeInBytes);
  ASSERT_EQ(cudaMemcpy(reinterpret_cast<void*>(ias_moved), reinterpret_cast<void*>(ias),
                       ias_sizes.outputSizeInBytes, cudaMemcpyDeviceToDevice),
            cudaSuccess);
  const CUdeviceptr new_children = Upload(std::vector<OptixTraversableHandle>{relocated});
  OptixRelocateInput relocate{};
  relocate.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  relocate.instanceArray.numInstances = 1;
  relocate.instanceArray.traversableHandles = new_children;
  EXPECT_EQ(optixAccelRelocate(context_, 0, &ias_info, nullptr, 0, ias_moved,
                               ias_sizes.outputSizeInBytes, &relocated),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "an instance build relocates with 1 relocate input"));
  OptixTraversableHandle ias_relocated = 0;
  ASSERT_EQ(optixAccelRelocate(context_, 0, &ias_info, &relocate, 1, ias_moved,
                               ias_sizes.outputSizeInBytes, &ias_relocated),
            OPTIX_SUCCESS);
  EXPECT_EQ(ias_relocated, ias_moved);
  // The descriptor's instances follow its 64-byte header; the child handle is at byte 64 of one.
  static_assert(offsetof(OptixInstance, traversableHandle) == 64);
  EXPECT_EQ(Download<OptixTraversableHandle>(ias_moved + 64 + 64), moved);
  EXPECT_EQ(Download<OptixTraversableHandle>(ias + 64 + 64), gas);
  OptixAccelEmitDesc box_of_moved = {emitted + 8, OPTIX_PROPERTY_TYPE_AABBS};
  ASSERT_EQ(optixAccelEmitProperty(context_, 0, ias_relocated, &box_of_moved), OPTIX_SUCCESS);
  ExpectBox(Download<OptixAabb>(emitted + 8), 10, 0, 0, 11, 2, 3);

  for (CUdeviceptr p : {vertex_buffer, input.triangleArray.indexBuffer, temp, output, emitted,
                        compact_buffer, moved, instances, ias_buffer, ias_moved, new_children}) {
    EXPECT_EQ(cudaFree(reinterpret_cast<void*>(p)), cudaSuccess);
  }
}

TEST_F(AccelTest, UnsupportedInputsAndTransformHandles) {
  OptixBuildInput curves{};
  curves.type = OPTIX_BUILD_INPUT_TYPE_CURVES;
  OptixAccelBuildOptions options{};
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  OptixAccelBufferSizes sizes{};
  EXPECT_EQ(optixAccelComputeMemoryUsage(context_, &options, &curves, 1, &sizes),
            OPTIX_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(optixAccelComputeMemoryUsage(context_, &options, nullptr, 1, &sizes),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "optixAccelComputeMemoryUsage: buildInputs is null"));

  const CUdeviceptr transform = Alloc(sizeof(OptixStaticTransform));
  OptixTraversableHandle handle = 0;
  ASSERT_EQ(optixConvertPointerToTraversableHandle(
                context_, transform, OPTIX_TRAVERSABLE_TYPE_STATIC_TRANSFORM, &handle),
            OPTIX_SUCCESS);
  EXPECT_EQ(handle, transform | OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM);  // the type in low bits
  EXPECT_EQ(optixConvertPointerToTraversableHandle(
                context_, transform + 16, OPTIX_TRAVERSABLE_TYPE_STATIC_TRANSFORM, &handle),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_EQ(optixConvertPointerToTraversableHandle(
                context_, transform, OPTIX_TRAVERSABLE_TYPE_SRT_MOTION_TRANSFORM, &handle),
            OPTIX_ERROR_INVALID_VALUE);  // 112 bytes allocated, an SRT motion transform has 160
  EXPECT_EQ(optixConvertPointerToTraversableHandle(
                context_, transform, static_cast<OptixTraversableType>(0x21C0), &handle),
            OPTIX_ERROR_INVALID_VALUE);
  EXPECT_TRUE(Logged(2, "traversableType 0x21c0 is no OptixTraversableType"));
  EXPECT_EQ(cudaFree(reinterpret_cast<void*>(transform)), cudaSuccess);
}

}  // namespace
}  // namespace tessera_test
