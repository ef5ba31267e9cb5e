// optixAccelBuild's host side: the acceleration descriptor written into device memory from the
// application's build inputs (triangles in every vertex and index format, custom primitives,
// instances and instance pointers), read back as a worker reads it, and every input OptiX would
// refuse refused with the input and field named.
#include "accel_build.h"

#include <cuda_runtime.h>
#include <gtest/gtest.h>
#include <optix_types.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "accel_format.h"
#include "host_device_memory.h"

namespace {

using tessera::memory::AccelHeader;
using tessera::memory::AccelInput;
using tessera::memory::AccelKind;
using tessera::optix7::HostDeviceMemory;

HostDeviceMemory& Memory() { return **HostDeviceMemory::Get(); }

// Device memory holding `values`.
template <typename T>
CUdeviceptr Upload(const std::vector<T>& values) {
  void* p = nullptr;
  EXPECT_EQ(cudaMalloc(&p, values.size() * sizeof(T)), cudaSuccess);
  EXPECT_EQ(cudaMemcpy(p, values.data(), values.size() * sizeof(T), cudaMemcpyHostToDevice),
            cudaSuccess);
  return reinterpret_cast<CUdeviceptr>(p);
}

struct Built {
  OptixTraversableHandle handle = 0;
  const AccelHeader* header = nullptr;
  const unsigned char* bytes = nullptr;
  std::string error;
  const AccelInput& input(unsigned i) const {
    return reinterpret_cast<const AccelInput*>(bytes + header->inputs_offset)[i];
  }
  template <typename T>
  const T* at(uint64_t offset) const {
    return reinterpret_cast<const T*>(bytes + offset);
  }
};

// Sizes, allocates the output and builds; `error` holds the message of a refused build.
Built Build(const std::vector<OptixBuildInput>& inputs, unsigned flags = 0,
            const OptixMotionOptions& motion = {}) {
  OptixAccelBuildOptions options{};
  options.buildFlags = flags;
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  options.motionOptions = motion;
  Built b;
  auto sizes = tessera::optix7::AccelBufferSizes(Memory(), options, inputs.data(),
                                                 static_cast<unsigned>(inputs.size()));
  if (!sizes.ok()) {
    b.error = std::string(sizes.status().message());
    return b;
  }
  EXPECT_GT(sizes->tempSizeInBytes, 0u);
  void* out = nullptr;
  EXPECT_EQ(cudaMalloc(&out, sizes->outputSizeInBytes), cudaSuccess);
  (void)Memory().TakeWrittenChunks();
  auto handle = tessera::optix7::BuildAccel(
      Memory(), options, inputs.data(), static_cast<unsigned>(inputs.size()),
      reinterpret_cast<CUdeviceptr>(out), sizes->outputSizeInBytes);
  if (!handle.ok()) {
    b.error = std::string(handle.status().message());
    return b;
  }
  EXPECT_FALSE(Memory().TakeWrittenChunks().empty());  // the descriptor ships like any write
  b.handle = *handle;
  EXPECT_EQ(b.handle, reinterpret_cast<CUdeviceptr>(out));
  auto header = tessera::memory::ReadAccelHeader(out, sizes->outputSizeInBytes);
  EXPECT_TRUE(header.ok()) << header.status();
  b.header = header.ok() ? *header : nullptr;
  b.bytes = static_cast<const unsigned char*>(out);
  return b;
}

TEST(AccelBuildTest, IndexedTrianglesWithAPreTransformAndTwoSbtRecords) {
  // Four vertices 16 bytes apart (a float3 and padding), two triangles, uint3 indices.
  const std::vector<float> vertices = {0, 0, 0, -1, 1, 0, 0, -1, 0, 1, 0, -1, 1, 1, 0, -1};
  const std::vector<uint32_t> indices = {0, 1, 2, 1, 3, 2};
  const std::vector<float> transform = {2, 0, 0, 10, 0, 1, 0, 20, 0, 0, 1, 30};
  const std::vector<uint8_t> sbt_offsets = {1, 0};
  const CUdeviceptr v = Upload(vertices);
  const unsigned flags[2] = {OPTIX_GEOMETRY_FLAG_NONE, OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  OptixBuildInputTriangleArray& t = in.triangleArray;
  t.vertexBuffers = &v;
  t.numVertices = 4;
  t.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  t.vertexStrideInBytes = 16;
  t.indexBuffer = Upload(indices);
  t.numIndexTriplets = 2;
  t.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  t.preTransform = Upload(transform);
  t.transformFormat = OPTIX_TRANSFORM_FORMAT_MATRIX_FLOAT12;
  t.flags = flags;
  t.numSbtRecords = 2;
  t.sbtIndexOffsetBuffer = Upload(sbt_offsets);
  t.sbtIndexOffsetSizeInBytes = 1;
  t.primitiveIndexOffset = 7;
  const Built b = Build({in}, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE);
  ASSERT_TRUE(b.error.empty()) << b.error;
  EXPECT_EQ(b.header->kind, AccelKind::kTriangles);
  EXPECT_EQ(b.header->primitive_count, 2u);
  EXPECT_EQ(b.header->build_flags, static_cast<unsigned>(OPTIX_BUILD_FLAG_PREFER_FAST_TRACE));
  const AccelInput& r = b.input(0);
  EXPECT_EQ(r.primitive_count, 2u);
  EXPECT_EQ(r.vertex_count, 4u);
  EXPECT_EQ(r.primitive_index_offset, 7u);
  const float* p = b.at<float>(r.vertices_offset);
  // Vertex 3 (1, 1, 0) through the transform: (2 + 10, 1 + 20, 30).
  EXPECT_EQ(p[9], 12.f);
  EXPECT_EQ(p[10], 21.f);
  EXPECT_EQ(p[11], 30.f);
  const uint32_t* idx = b.at<uint32_t>(r.indices_offset);
  EXPECT_EQ(std::vector<uint32_t>(idx, idx + 6), indices);
  EXPECT_EQ(b.at<uint32_t>(r.flags_offset)[1], static_cast<uint32_t>(flags[1]));
  EXPECT_EQ(b.at<uint32_t>(r.sbt_index_offsets_offset)[0], 1u);
  EXPECT_EQ(b.at<uint32_t>(r.sbt_index_offsets_offset)[1], 0u);

  // The same inputs give the same content hash; another vertex gives another.
  const Built again = Build({in}, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE);
  EXPECT_EQ(again.header->content_hash, b.header->content_hash);
  std::vector<float> moved = vertices;
  moved[0] = 0.5f;
  const CUdeviceptr v2 = Upload(moved);
  t.vertexBuffers = &v2;
  EXPECT_NE(Build({in}, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE).header->content_hash,
            b.header->content_hash);
}

TEST(AccelBuildTest, EveryVertexFormatBecomesFloats) {
  // Three vertices, unindexed: one triangle whatever the format.
  const std::vector<uint16_t> halves = {0x3C00, 0x4000, 0xC200, 0, 0, 0, 0x3800, 0, 0};  // 1 2 -3
  const std::vector<int16_t> snorm = {32767, -32768, 16384, 0, 0, 0, 0, 0, 0};
  const std::vector<float> float2 = {1.5f, -2.f, 0, 0, 0, 1};
  struct Case {
    OptixVertexFormat format;
    CUdeviceptr data;
    float x, y, z;
  };
  const Case cases[] = {
      {OPTIX_VERTEX_FORMAT_HALF3, Upload(halves), 1.f, 2.f, -3.f},
      {OPTIX_VERTEX_FORMAT_SNORM16_3, Upload(snorm), 1.f, -1.f, 16384.f / 32767.f},
      {OPTIX_VERTEX_FORMAT_FLOAT2, Upload(float2), 1.5f, -2.f, 0.f},
  };
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  for (const Case& c : cases) {
    OptixBuildInput in{};
    in.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
    in.triangleArray.vertexBuffers = &c.data;
    in.triangleArray.numVertices = 3;
    in.triangleArray.vertexFormat = c.format;
    in.triangleArray.flags = &flags;
    in.triangleArray.numSbtRecords = 1;
    const Built b = Build({in});
    ASSERT_TRUE(b.error.empty()) << b.error;
    const float* p = b.at<float>(b.input(0).vertices_offset);
    EXPECT_EQ(p[0], c.x) << c.format;
    EXPECT_EQ(p[1], c.y) << c.format;
    EXPECT_EQ(p[2], c.z) << c.format;
    const uint32_t* idx = b.at<uint32_t>(b.input(0).indices_offset);
    EXPECT_EQ(idx[2], 2u);                               // unindexed: 0 1 2
    EXPECT_EQ(b.input(0).sbt_index_offsets_offset, 0u);  // one record: none
  }
}

TEST(AccelBuildTest, CustomPrimitivesAndInstances) {
  // Two boxes 32 bytes apart.
  const std::vector<float> boxes = {0, 0, 0, 1, 1, 1, 9, 9, 1, 1, 1, 2, 2, 2, 9, 9};
  const CUdeviceptr aabbs = Upload(boxes);
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  in.customPrimitiveArray.aabbBuffers = &aabbs;
  in.customPrimitiveArray.numPrimitives = 2;
  in.customPrimitiveArray.strideInBytes = 32;
  in.customPrimitiveArray.flags = &flags;
  in.customPrimitiveArray.numSbtRecords = 1;
  const Built gas = Build({in, in});  // two inputs
  ASSERT_TRUE(gas.error.empty()) << gas.error;
  EXPECT_EQ(gas.header->kind, AccelKind::kCustom);
  EXPECT_EQ(gas.header->input_count, 2u);
  EXPECT_EQ(gas.header->primitive_count, 4u);
  EXPECT_EQ(gas.at<float>(gas.input(1).aabbs_offset)[6], 1.f);   // box 1's min x
  EXPECT_EQ(gas.at<float>(gas.input(1).aabbs_offset)[11], 2.f);  // box 1's max z

  std::vector<OptixInstance> instances(2);
  for (unsigned k = 0; k < 2; ++k) {
    OptixInstance& i = instances[k];
    std::memset(&i, 0, sizeof(i));
    i.transform[0] = i.transform[5] = i.transform[10] = 1.f;
    i.transform[3] = static_cast<float>(k);
    i.instanceId = 100 + k;
    i.sbtOffset = k;
    i.visibilityMask = 0xFF;
    i.traversableHandle = gas.handle;
  }
  OptixBuildInput ias{};
  ias.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  ias.instanceArray.instances = Upload(instances);
  ias.instanceArray.numInstances = 2;
  const Built top = Build({ias});
  ASSERT_TRUE(top.error.empty()) << top.error;
  EXPECT_EQ(top.header->kind, AccelKind::kInstances);
  const auto* copied = top.at<OptixInstance>(top.header->inputs_offset);
  EXPECT_EQ(copied[1].instanceId, 101u);
  EXPECT_EQ(copied[1].traversableHandle, gas.handle);

  // Instance pointers, in reverse order: the descriptor holds the instances they point to.
  const std::vector<CUdeviceptr> pointers = {ias.instanceArray.instances + sizeof(OptixInstance),
                                             ias.instanceArray.instances};
  OptixBuildInput by_pointer{};
  by_pointer.type = OPTIX_BUILD_INPUT_TYPE_INSTANCE_POINTERS;
  by_pointer.instanceArray.instances = Upload(pointers);
  by_pointer.instanceArray.numInstances = 2;
  const Built top2 = Build({by_pointer});
  ASSERT_TRUE(top2.error.empty()) << top2.error;
  EXPECT_EQ(top2.at<OptixInstance>(top2.header->inputs_offset)[0].instanceId, 101u);
}

TEST(AccelBuildTest, InputsOptiXWouldRefuseAreNamed) {
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  const std::vector<float> vertices(9, 0.f);
  const CUdeviceptr v = Upload(vertices);
  auto triangles = [&] {
    OptixBuildInput in{};
    in.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
    in.triangleArray.vertexBuffers = &v;
    in.triangleArray.numVertices = 3;
    in.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
    in.triangleArray.flags = &flags;
    in.triangleArray.numSbtRecords = 1;
    return in;
  };
  auto refused = [&](OptixBuildInput in, const std::string& says) {
    const Built b = Build({in});
    EXPECT_NE(b.error.find(says), std::string::npos) << "got: " << b.error;
  };
  ASSERT_TRUE(Build({triangles()}).error.empty());

  OptixBuildInput in = triangles();
  const std::vector<float> host(9, 0.f);
  const CUdeviceptr host_pointer = reinterpret_cast<CUdeviceptr>(host.data());
  in.triangleArray.vertexBuffers = &host_pointer;
  refused(in, "does not lie in one cudaMalloc allocation");
  in = triangles();
  in.triangleArray.numVertices = 4;  // 48 bytes from a 36-byte allocation
  refused(in, "(48 bytes at 0x");
  const std::vector<float> four(12, 0.f);
  const CUdeviceptr v4 = Upload(four);
  in.triangleArray.vertexBuffers = &v4;  // four vertices and no indices: not triangles
  refused(in, "4 vertices without indices (a multiple of 3)");
  in = triangles();
  in.triangleArray.flags = nullptr;
  refused(in, "flags is null");
  in = triangles();
  in.triangleArray.numSbtRecords = 0;
  refused(in, "numSbtRecords is 0");
  in = triangles();
  const std::vector<uint32_t> bad_index = {0, 1, 3};
  in.triangleArray.indexBuffer = Upload(bad_index);
  in.triangleArray.numIndexTriplets = 1;
  in.triangleArray.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  refused(in, "triangle 0 uses vertex 3 of 3");
  in = triangles();
  in.triangleArray.vertexFormat = static_cast<OptixVertexFormat>(0x1234);
  refused(in, "vertexFormat 0x1234 is unknown");
  in = triangles();
  in.triangleArray.numSbtRecords = 2;
  const unsigned two_flags[2] = {0, 0};
  in.triangleArray.flags = two_flags;
  const std::vector<uint16_t> too_far = {2};
  in.triangleArray.sbtIndexOffsetBuffer = Upload(too_far);
  in.triangleArray.sbtIndexOffsetSizeInBytes = 2;
  refused(in, "SBT index offset 2 of 2 SBT records");

  OptixBuildInput curves{};
  curves.type = OPTIX_BUILD_INPUT_TYPE_CURVES;
  refused(curves, "curves are not supported yet");
  OptixBuildInput other = triangles();
  OptixBuildInput custom{};
  custom.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  const Built mixed = Build({other, custom});
  EXPECT_NE(mixed.error.find("build input 1: its type differs"), std::string::npos) << mixed.error;

  // The output: too small, misaligned.
  OptixAccelBuildOptions options{};
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  OptixBuildInput ok = triangles();
  void* small = nullptr;
  ASSERT_EQ(cudaMalloc(&small, 64), cudaSuccess);
  auto handle = tessera::optix7::BuildAccel(Memory(), options, &ok, 1,
                                            reinterpret_cast<CUdeviceptr>(small), 64);
  ASSERT_FALSE(handle.ok());
  EXPECT_NE(handle.status().message().find("optixAccelComputeMemoryUsage"), std::string::npos);
  handle = tessera::optix7::BuildAccel(Memory(), options, &ok, 1,
                                       reinterpret_cast<CUdeviceptr>(small) + 8, 56);
  ASSERT_FALSE(handle.ok());
  EXPECT_NE(handle.status().message().find("128-byte aligned"), std::string::npos);
}

TEST(AccelFormatTest, ADescriptorThatIsNotOneIsRefused) {
  std::vector<unsigned char> junk(256, 0);
  EXPECT_FALSE(tessera::memory::ReadAccelHeader(junk.data(), junk.size()).ok());
  EXPECT_FALSE(tessera::memory::ReadAccelHeader(junk.data(), 10).ok());
  EXPECT_FALSE(tessera::memory::ReadAccelHeader(nullptr, 0).ok());
  AccelHeader h{};
  std::memcpy(h.magic, tessera::memory::kAccelMagic, 8);
  h.version = tessera::memory::kAccelFormatVersion;
  h.kind = AccelKind::kTriangles;
  h.total_size = sizeof(h);
  h.input_count = 1;  // an input record past the end
  h.inputs_offset = sizeof(h);
  std::memcpy(junk.data(), &h, sizeof(h));
  auto read = tessera::memory::ReadAccelHeader(junk.data(), junk.size());
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.status().message().find("outside"), std::string::npos) << read.status();
  h.version = 99;
  std::memcpy(junk.data(), &h, sizeof(h));
  read = tessera::memory::ReadAccelHeader(junk.data(), junk.size());
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.status().message().find("format version 99"), std::string::npos);
}

TEST(AccelBuildTest, MotionKeysAndSpheresAreHeldKeyAfterKey) {
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  // Three keys of one triangle, moving +10 in x per key.
  std::vector<CUdeviceptr> keys;
  for (int k = 0; k < 3; ++k) {
    const float x = 10.f * k;
    keys.push_back(Upload(std::vector<float>{x, 0, 0, x + 1, 0, 0, x, 1, 0}));
  }
  OptixBuildInput tri{};
  tri.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  tri.triangleArray.vertexBuffers = keys.data();
  tri.triangleArray.numVertices = 3;
  tri.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  tri.triangleArray.flags = &flags;
  tri.triangleArray.numSbtRecords = 1;
  const Built moving =
      Build({tri}, 0, OptixMotionOptions{3, OPTIX_MOTION_FLAG_END_VANISH, -1.f, 2.f});
  ASSERT_TRUE(moving.error.empty()) << moving.error;
  ASSERT_NE(moving.header->motion_offset, 0u);
  const auto* motion = moving.at<tessera::memory::AccelMotion>(moving.header->motion_offset);
  EXPECT_EQ(motion->keys, 3u);
  EXPECT_EQ(motion->flags, static_cast<uint32_t>(OPTIX_MOTION_FLAG_END_VANISH));
  EXPECT_EQ(motion->time_begin, -1.f);
  EXPECT_EQ(motion->time_end, 2.f);
  const float* v = moving.at<float>(moving.input(0).vertices_offset);
  EXPECT_EQ(v[0], 0.f);    // key 0, vertex 0
  EXPECT_EQ(v[9], 10.f);   // key 1, vertex 0
  EXPECT_EQ(v[21], 21.f);  // key 2, vertex 1
  // One key, or none, builds without motion whatever the times say.
  const Built still = Build({tri}, 0, OptixMotionOptions{1, 0, 5.f, 1.f});
  ASSERT_TRUE(still.error.empty()) << still.error;
  EXPECT_EQ(still.header->motion_offset, 0u);
  // What a motion build refuses.
  std::vector<CUdeviceptr> short_keys = {keys[0], 0};
  tri.triangleArray.vertexBuffers = short_keys.data();
  EXPECT_NE(
      Build({tri}, 0, OptixMotionOptions{2, 0, 0.f, 1.f}).error.find("vertexBuffers[1] is null"),
      std::string::npos);
  tri.triangleArray.vertexBuffers = keys.data();
  EXPECT_NE(Build({tri}, 0, OptixMotionOptions{2, 0, 1.f, 0.f}).error.find("timeBegin 1 is after"),
            std::string::npos);

  // Custom primitives: boxes per key.
  const std::vector<OptixAabb> box0 = {{0, 0, 0, 1, 1, 1}}, box1 = {{5, 0, 0, 6, 1, 1}};
  std::vector<CUdeviceptr> boxes = {Upload(box0), Upload(box1)};
  OptixBuildInput custom{};
  custom.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  custom.customPrimitiveArray.aabbBuffers = boxes.data();
  custom.customPrimitiveArray.numPrimitives = 1;
  custom.customPrimitiveArray.flags = &flags;
  custom.customPrimitiveArray.numSbtRecords = 1;
  const Built moving_boxes = Build({custom}, 0, OptixMotionOptions{2, 0, 0.f, 1.f});
  ASSERT_TRUE(moving_boxes.error.empty()) << moving_boxes.error;
  EXPECT_EQ(moving_boxes.at<float>(moving_boxes.input(0).aabbs_offset)[6], 5.f);

  // Spheres: centre and radius as float[4]; one radius for all with singleRadius.
  const CUdeviceptr centres = Upload(std::vector<float>{1, 2, 3, 4, 5, 6});
  const CUdeviceptr radii = Upload(std::vector<float>{0.5f, 0.25f});
  OptixBuildInput spheres{};
  spheres.type = OPTIX_BUILD_INPUT_TYPE_SPHERES;
  spheres.sphereArray.vertexBuffers = &centres;
  spheres.sphereArray.numVertices = 2;
  spheres.sphereArray.radiusBuffers = &radii;
  spheres.sphereArray.flags = &flags;
  spheres.sphereArray.numSbtRecords = 1;
  spheres.sphereArray.primitiveIndexOffset = 7;
  const Built built = Build({spheres});
  ASSERT_TRUE(built.error.empty()) << built.error;
  EXPECT_EQ(built.header->kind, AccelKind::kSpheres);
  EXPECT_EQ(built.input(0).primitive_index_offset, 7u);
  const float* s = built.at<float>(built.input(0).vertices_offset);
  EXPECT_EQ(std::vector<float>(s, s + 8), (std::vector<float>{1, 2, 3, 0.5f, 4, 5, 6, 0.25f}));
  spheres.sphereArray.singleRadius = 1;
  const Built single = Build({spheres});
  ASSERT_TRUE(single.error.empty()) << single.error;
  EXPECT_EQ(single.at<float>(single.input(0).vertices_offset)[7], 0.5f);
  const CUdeviceptr negative = Upload(std::vector<float>{-1.f});
  spheres.sphereArray.radiusBuffers = &negative;
  EXPECT_NE(Build({spheres}).error.find("sphere 0 has radius -1"), std::string::npos);
}

}  // namespace
