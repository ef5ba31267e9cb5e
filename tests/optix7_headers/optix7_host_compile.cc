// Host code as an OptiX 7 SDK sample starts (optixTriangle, optixSphere, optixDynamicGeometry),
// compiled against Tessera's OptiX 7 include root (api/include7) with -Wall -Wextra -Werror.
// Tessera does not implement the API yet (the next part of issue 25), so this translation unit is
// compiled and never linked or run (an OBJECT library that a ctest builds): what it checks is that
// SDK-style code compiles unchanged and that the structs have OptiX 7.7's layout
// (static_asserts below, values from the OptiX 7.7 ABI).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stack_size.h>
#include <optix_stubs.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

// ---- Layouts --------------------------------------------------------------------------------
static_assert(OPTIX_VERSION == 70700, "an application that defines nothing gets OptiX 7.7");
static_assert(OPTIX_ABI_VERSION == 84, "OptiX 7.7's function table ABI");
static_assert(OPTIX_SBT_RECORD_HEADER_SIZE == 32);
static_assert(OPTIX_SBT_RECORD_ALIGNMENT == 16);
static_assert(OPTIX_ACCEL_BUFFER_BYTE_ALIGNMENT == 128);
static_assert(OPTIX_INSTANCE_BYTE_ALIGNMENT == 16);
static_assert(OPTIX_AABB_BUFFER_BYTE_ALIGNMENT == 8);
static_assert(OPTIX_GEOMETRY_TRANSFORM_BYTE_ALIGNMENT == 16);
static_assert(OPTIX_TRANSFORM_BYTE_ALIGNMENT == 64);

static_assert(sizeof(CUdeviceptr) == 8 && sizeof(OptixTraversableHandle) == 8);
static_assert(sizeof(OptixAabb) == 24);
static_assert(sizeof(OptixInstance) == 80);
static_assert(offsetof(OptixInstance, instanceId) == 48);
static_assert(offsetof(OptixInstance, sbtOffset) == 52);
static_assert(offsetof(OptixInstance, visibilityMask) == 56);
static_assert(offsetof(OptixInstance, flags) == 60);
static_assert(offsetof(OptixInstance, traversableHandle) == 64);
static_assert(sizeof(OptixBuildInput) == 8 + 1024);
static_assert(offsetof(OptixBuildInput, triangleArray) == 8);
static_assert(offsetof(OptixBuildInput, instanceArray) == 8);
static_assert(sizeof(OptixBuildInputOpacityMicromap) == 48);
static_assert(sizeof(OptixBuildInputDisplacementMicromap) == 96);
static_assert(sizeof(OptixBuildInputTriangleArray) == 240);
static_assert(offsetof(OptixBuildInputTriangleArray, indexBuffer) == 24);
static_assert(offsetof(OptixBuildInputTriangleArray, preTransform) == 48);
static_assert(offsetof(OptixBuildInputTriangleArray, flags) == 56);
static_assert(offsetof(OptixBuildInputTriangleArray, sbtIndexOffsetBuffer) == 72);
static_assert(offsetof(OptixBuildInputTriangleArray, transformFormat) == 92);
static_assert(offsetof(OptixBuildInputTriangleArray, opacityMicromap) == 96);
static_assert(offsetof(OptixBuildInputTriangleArray, displacementMicromap) == 144);
static_assert(sizeof(OptixBuildInputCustomPrimitiveArray) == 56);
static_assert(offsetof(OptixBuildInputCustomPrimitiveArray, sbtIndexOffsetBuffer) == 32);
static_assert(sizeof(OptixBuildInputInstanceArray) == 16);
static_assert(sizeof(OptixBuildInputCurveArray) == 80);
static_assert(sizeof(OptixBuildInputSphereArray) == 72);
static_assert(sizeof(OptixShaderBindingTable) == 64);
static_assert(offsetof(OptixShaderBindingTable, missRecordBase) == 16);
static_assert(offsetof(OptixShaderBindingTable, hitgroupRecordBase) == 32);
static_assert(offsetof(OptixShaderBindingTable, callablesRecordBase) == 48);
static_assert(sizeof(OptixProgramGroupDesc) == 56);
static_assert(offsetof(OptixProgramGroupDesc, raygen) == 8);
static_assert(offsetof(OptixProgramGroupDesc, hitgroup) == 8);
static_assert(sizeof(OptixProgramGroupHitgroup) == 48);
static_assert(sizeof(OptixProgramGroupOptions) == 8);
static_assert(sizeof(OptixDeviceContextOptions) == 24);
static_assert(sizeof(OptixModuleCompileOptions) == 40);
static_assert(offsetof(OptixModuleCompileOptions, boundValues) == 16);
static_assert(offsetof(OptixModuleCompileOptions, payloadTypes) == 32);
static_assert(sizeof(OptixPipelineCompileOptions) == 40);
static_assert(offsetof(OptixPipelineCompileOptions, pipelineLaunchParamsVariableName) == 24);
static_assert(offsetof(OptixPipelineCompileOptions, allowOpacityMicromaps) == 36);
static_assert(sizeof(OptixPipelineLinkOptions) == 4);
static_assert(sizeof(OptixMotionOptions) == 12);
static_assert(sizeof(OptixAccelBuildOptions) == 20);
static_assert(sizeof(OptixAccelBufferSizes) == 24);
static_assert(sizeof(OptixAccelEmitDesc) == 16);
static_assert(sizeof(OptixRelocationInfo) == 32);
static_assert(sizeof(OptixStaticTransform) == 112 &&
              offsetof(OptixStaticTransform, transform) == 16);
static_assert(sizeof(OptixMatrixMotionTransform) == 128);
static_assert(offsetof(OptixMatrixMotionTransform, transform) == 32);
static_assert(sizeof(OptixSRTData) == 64);
static_assert(sizeof(OptixSRTMotionTransform) == 160);
static_assert(sizeof(OptixStackSizes) == 28);
static_assert(sizeof(OptixImage2D) == 32);
static_assert(sizeof(OptixDenoiserParams) == 40);
static_assert(sizeof(OptixDenoiserSizes) == 56);
static_assert(sizeof(OptixFunctionTable) == 48 * sizeof(void*), "48 entries in OptiX 7.7");
static_assert(offsetof(OptixFunctionTable, optixModuleCreate) == 12 * sizeof(void*));
static_assert(offsetof(OptixFunctionTable, optixAccelBuild) == 25 * sizeof(void*));
static_assert(offsetof(OptixFunctionTable, optixSbtRecordPackHeader) == 38 * sizeof(void*));
static_assert(offsetof(OptixFunctionTable, optixLaunch) == 39 * sizeof(void*));
static_assert(offsetof(OptixFunctionTable, optixDenoiserCreateWithUserModel) == 47 * sizeof(void*));

// ---- Enumerator values ----------------------------------------------------------------------
static_assert(OPTIX_SUCCESS == 0 && OPTIX_ERROR_INVALID_VALUE == 7001 &&
              OPTIX_ERROR_INVALID_INPUT == 7200 && OPTIX_ERROR_NOT_SUPPORTED == 7800 &&
              OPTIX_ERROR_CUDA_ERROR == 7900 && OPTIX_ERROR_UNKNOWN == 7999);
static_assert(OPTIX_BUILD_INPUT_TYPE_TRIANGLES == 0x2141 &&
              OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES == 0x2142 &&
              OPTIX_BUILD_INPUT_TYPE_INSTANCES == 0x2143 &&
              OPTIX_BUILD_INPUT_TYPE_SPHERES == 0x2146);
static_assert(OPTIX_VERTEX_FORMAT_FLOAT3 == 0x2121 && OPTIX_INDICES_FORMAT_UNSIGNED_INT3 == 0x2103);
static_assert(OPTIX_PROGRAM_GROUP_KIND_RAYGEN == 0x2421 &&
              OPTIX_PROGRAM_GROUP_KIND_CALLABLES == 0x2425);
static_assert(OPTIX_BUILD_OPERATION_BUILD == 0x2161 &&
              OPTIX_PROPERTY_TYPE_COMPACTED_SIZE == 0x2181);
static_assert(OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE == 0xFE);
static_assert(OPTIX_PRIMITIVE_TYPE_TRIANGLE == 0x2531 && OPTIX_PRIMITIVE_TYPE_SPHERE == 0x2506);
static_assert(static_cast<unsigned>(OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE) == 1u << 31);
static_assert(OPTIX_COMPILE_DEBUG_LEVEL_MODERATE == 0x2353 &&
              OPTIX_COMPILE_OPTIMIZATION_LEVEL_3 == 0x2343);
static_assert(OPTIX_EXCEPTION_CODE_STACK_OVERFLOW == -1 &&
              OPTIX_EXCEPTION_CODE_PAYLOAD_TYPE_MISMATCH == -33);
static_assert(OPTIX_TRAVERSABLE_TYPE_STATIC_TRANSFORM == 0x21C1);
static_assert(cudaSuccess == 0 && cudaErrorInvalidValue == 1 && cudaErrorMemoryAllocation == 2 &&
              cudaErrorNotSupported == 801 && cudaErrorUnknown == 999);
static_assert(cudaMemcpyHostToDevice == 1 && cudaMemcpyDeviceToHost == 2 && cudaMemcpyDefault == 4);

// ---- CUDA types -----------------------------------------------------------------------------
static_assert(sizeof(float2) == 8 && alignof(float2) == 8);
static_assert(sizeof(float3) == 12 && alignof(float3) == 4);
static_assert(sizeof(float4) == 16 && alignof(float4) == 16);
static_assert(sizeof(uint3) == 12 && sizeof(int2) == 8 && sizeof(uchar4) == 4 &&
              alignof(uchar4) == 4);
static_assert(sizeof(double2) == 16 && alignof(double2) == 16);
static_assert(sizeof(cudaTextureObject_t) == 8);
static_assert(sizeof(cudaChannelFormatDesc) == 20);
static_assert(sizeof(cudaResourceDesc) == 64);
static_assert(sizeof(cudaTextureDesc) == 72);
static_assert(sizeof(cudaMemcpy3DParms) == 160);

// ---- An SDK sample's host code --------------------------------------------------------------
template <typename T>
struct __align__(OPTIX_SBT_RECORD_ALIGNMENT) SbtRecord {
  __align__(OPTIX_SBT_RECORD_ALIGNMENT) char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  T data;
};

struct RayGenData {};
struct MissData {
  float3 bg_color;
};
struct HitGroupData {
  float3 center;
  float radius;
};
using RayGenSbtRecord = SbtRecord<RayGenData>;
using MissSbtRecord = SbtRecord<MissData>;
using HitGroupSbtRecord = SbtRecord<HitGroupData>;
static_assert(alignof(MissSbtRecord) == OPTIX_SBT_RECORD_ALIGNMENT);
static_assert(sizeof(MissSbtRecord) == 48 && offsetof(MissSbtRecord, data) == 32);

struct Params {
  uchar4* image;
  unsigned int image_width;
  unsigned int image_height;
  float3 cam_eye;
  OptixTraversableHandle handle;
};

#define CUDA_CHECK(call)                                                      \
  do {                                                                        \
    cudaError_t error = call;                                                 \
    if (error != cudaSuccess) {                                               \
      std::fprintf(stderr, "%s: %s (%s)\n", #call, cudaGetErrorString(error), \
                   cudaGetErrorName(error));                                  \
      return 1;                                                               \
    }                                                                         \
  } while (0)

#define OPTIX_CHECK(call)                                                    \
  do {                                                                       \
    OptixResult res = call;                                                  \
    if (res != OPTIX_SUCCESS) {                                              \
      std::fprintf(stderr, "%s: %s (%s)\n", #call, optixGetErrorString(res), \
                   optixGetErrorName(res));                                  \
      return 1;                                                              \
    }                                                                        \
  } while (0)

static void context_log_cb(unsigned int level, const char* tag, const char* message, void*) {
  std::fprintf(stderr, "[%2u][%12s]: %s\n", level, tag, message);
}

int RenderTriangleAndSphere(const char* program_source, size_t program_size) {
  // Initialize CUDA and create the OptiX context.
  CUDA_CHECK(cudaFree(0));
  int device_count = 0;
  CUDA_CHECK(cudaGetDeviceCount(&device_count));
  CUDA_CHECK(cudaSetDevice(0));
  cudaDeviceProp prop;
  CUDA_CHECK(cudaGetDeviceProperties(&prop, 0));
  std::printf("%s %d.%d\n", prop.name, prop.major, prop.minor);
  OPTIX_CHECK(optixInit());
  OptixDeviceContextOptions options = {};
  options.logCallbackFunction = &context_log_cb;
  options.logCallbackLevel = 4;
  options.validationMode = OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_ALL;
  CUcontext cu_ctx = 0;
  if (cuCtxGetCurrent(&cu_ctx) != CUDA_SUCCESS) return 1;
  OptixDeviceContext context = nullptr;
  OPTIX_CHECK(optixDeviceContextCreate(cu_ctx, &options, &context));

  // Triangle GAS.
  OptixAccelBuildOptions accel_options = {};
  accel_options.buildFlags = OPTIX_BUILD_FLAG_ALLOW_COMPACTION;
  accel_options.operation = OPTIX_BUILD_OPERATION_BUILD;
  const float3 vertices[3] = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.0f}};
  CUdeviceptr d_vertices = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_vertices), sizeof(vertices)));
  CUDA_CHECK(cudaMemcpy(reinterpret_cast<void*>(d_vertices), vertices, sizeof(vertices),
                        cudaMemcpyHostToDevice));
  const uint32_t triangle_input_flags[1] = {OPTIX_GEOMETRY_FLAG_NONE};
  OptixBuildInput build_inputs[3] = {};
  build_inputs[0].type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  build_inputs[0].triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  build_inputs[0].triangleArray.numVertices = 3;
  build_inputs[0].triangleArray.vertexBuffers = &d_vertices;
  build_inputs[0].triangleArray.flags = triangle_input_flags;
  build_inputs[0].triangleArray.numSbtRecords = 1;

  // Custom primitive: one sphere's box.
  OptixAabb aabb = {-1.5f, -1.5f, -1.5f, 1.5f, 1.5f, 1.5f};
  CUdeviceptr d_aabb = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_aabb), sizeof(OptixAabb)));
  CUDA_CHECK(cudaMemcpyAsync(reinterpret_cast<void*>(d_aabb), &aabb, sizeof(aabb),
                             cudaMemcpyHostToDevice));
  const uint32_t aabb_input_flags[1] = {OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT};
  build_inputs[1].type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  build_inputs[1].customPrimitiveArray.aabbBuffers = &d_aabb;
  build_inputs[1].customPrimitiveArray.numPrimitives = 1;
  build_inputs[1].customPrimitiveArray.flags = aabb_input_flags;
  build_inputs[1].customPrimitiveArray.numSbtRecords = 1;

  OptixAccelBufferSizes gas_buffer_sizes;
  OPTIX_CHECK(
      optixAccelComputeMemoryUsage(context, &accel_options, build_inputs, 1, &gas_buffer_sizes));
  CUdeviceptr d_temp = 0, d_gas = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_temp), gas_buffer_sizes.tempSizeInBytes));
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_gas), gas_buffer_sizes.outputSizeInBytes));
  CUdeviceptr d_compacted_size = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_compacted_size), sizeof(size_t)));
  OptixAccelEmitDesc emit = {};
  emit.type = OPTIX_PROPERTY_TYPE_COMPACTED_SIZE;
  emit.result = d_compacted_size;
  OptixTraversableHandle gas_handle = 0;
  OPTIX_CHECK(optixAccelBuild(context, 0, &accel_options, build_inputs, 2, d_temp,
                              gas_buffer_sizes.tempSizeInBytes, d_gas,
                              gas_buffer_sizes.outputSizeInBytes, &gas_handle, &emit, 1));
  OPTIX_CHECK(optixAccelCompact(context, 0, gas_handle, d_gas, gas_buffer_sizes.outputSizeInBytes,
                                &gas_handle));

  // Instances.
  OptixInstance instance = {};
  const float transform[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  for (int i = 0; i < 12; ++i) instance.transform[i] = transform[i];
  instance.instanceId = 0;
  instance.visibilityMask = 255;
  instance.sbtOffset = 0;
  instance.flags = OPTIX_INSTANCE_FLAG_NONE;
  instance.traversableHandle = gas_handle;
  CUdeviceptr d_instances = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_instances), sizeof(instance)));
  CUDA_CHECK(cudaMemcpy(reinterpret_cast<void*>(d_instances), &instance, sizeof(instance),
                        cudaMemcpyHostToDevice));
  build_inputs[2].type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  build_inputs[2].instanceArray.instances = d_instances;
  build_inputs[2].instanceArray.numInstances = 1;
  OptixTraversableHandle ias_handle = 0;
  OPTIX_CHECK(optixAccelBuild(context, 0, &accel_options, &build_inputs[2], 1, d_temp,
                              gas_buffer_sizes.tempSizeInBytes, d_gas,
                              gas_buffer_sizes.outputSizeInBytes, &ias_handle, nullptr, 0));

  // Module, program groups, pipeline.
  OptixModuleCompileOptions module_compile_options = {};
  module_compile_options.maxRegisterCount = OPTIX_COMPILE_DEFAULT_MAX_REGISTER_COUNT;
  module_compile_options.optLevel = OPTIX_COMPILE_OPTIMIZATION_DEFAULT;
  module_compile_options.debugLevel = OPTIX_COMPILE_DEBUG_LEVEL_MINIMAL;
  OptixPipelineCompileOptions pipeline_compile_options = {};
  pipeline_compile_options.usesMotionBlur = false;
  pipeline_compile_options.traversableGraphFlags =
      OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING;
  pipeline_compile_options.numPayloadValues = 3;
  pipeline_compile_options.numAttributeValues = 4;
  pipeline_compile_options.exceptionFlags =
      OPTIX_EXCEPTION_FLAG_STACK_OVERFLOW | OPTIX_EXCEPTION_FLAG_TRACE_DEPTH;
  pipeline_compile_options.pipelineLaunchParamsVariableName = "params";
  pipeline_compile_options.usesPrimitiveTypeFlags =
      OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE | OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM;
  char log[2048];
  size_t sizeof_log = sizeof(log);
  OptixModule module = nullptr;
  OPTIX_CHECK(optixModuleCreate(context, &module_compile_options, &pipeline_compile_options,
                                program_source, program_size, log, &sizeof_log, &module));

  OptixProgramGroupOptions program_group_options = {};
  OptixProgramGroupDesc descs[4] = {};
  descs[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  descs[0].raygen.module = module;
  descs[0].raygen.entryFunctionName = "__raygen__rg";
  descs[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
  descs[1].miss.module = module;
  descs[1].miss.entryFunctionName = "__miss__ms";
  descs[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
  descs[2].hitgroup.moduleCH = module;
  descs[2].hitgroup.entryFunctionNameCH = "__closesthit__sphere";
  descs[2].hitgroup.moduleIS = module;
  descs[2].hitgroup.entryFunctionNameIS = "__intersection__sphere";
  descs[2].hitgroup.moduleAH = module;
  descs[2].hitgroup.entryFunctionNameAH = "__anyhit__cutout";
  descs[3].kind = OPTIX_PROGRAM_GROUP_KIND_CALLABLES;
  descs[3].callables.moduleDC = module;
  descs[3].callables.entryFunctionNameDC = "__direct_callable__scale";
  OptixProgramGroup groups[4] = {};
  sizeof_log = sizeof(log);
  OPTIX_CHECK(
      optixProgramGroupCreate(context, descs, 4, &program_group_options, log, &sizeof_log, groups));

  OptixPipelineLinkOptions pipeline_link_options = {};
  pipeline_link_options.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  sizeof_log = sizeof(log);
  OPTIX_CHECK(optixPipelineCreate(context, &pipeline_compile_options, &pipeline_link_options,
                                  groups, 4, log, &sizeof_log, &pipeline));
  OptixStackSizes stack_sizes = {};
  for (OptixProgramGroup group : groups)
    OPTIX_CHECK(optixUtilAccumulateStackSizes(group, &stack_sizes, pipeline));
  uint32_t dc_from_traversal, dc_from_state, continuation;
  OPTIX_CHECK(optixUtilComputeStackSizes(&stack_sizes, 1, 0, 1, &dc_from_traversal, &dc_from_state,
                                         &continuation));
  OPTIX_CHECK(
      optixPipelineSetStackSize(pipeline, dc_from_traversal, dc_from_state, continuation, 2));

  // Shader binding table.
  RayGenSbtRecord rg_sbt;
  MissSbtRecord ms_sbt;
  ms_sbt.data.bg_color = make_float3(0.3f, 0.1f, 0.2f);
  HitGroupSbtRecord hg_sbt;
  hg_sbt.data.center = make_float3(0, 0, 0);
  hg_sbt.data.radius = 1.5f;
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[0], &rg_sbt));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[1], &ms_sbt));
  OPTIX_CHECK(optixSbtRecordPackHeader(groups[2], &hg_sbt));
  CUdeviceptr d_rg = 0, d_ms = 0, d_hg = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_rg), sizeof(rg_sbt)));
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_ms), sizeof(ms_sbt)));
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_hg), sizeof(hg_sbt)));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = d_rg;
  sbt.missRecordBase = d_ms;
  sbt.missRecordStrideInBytes = sizeof(MissSbtRecord);
  sbt.missRecordCount = 1;
  sbt.hitgroupRecordBase = d_hg;
  sbt.hitgroupRecordStrideInBytes = sizeof(HitGroupSbtRecord);
  sbt.hitgroupRecordCount = 1;

  // Launch.
  const unsigned int width = 64, height = 48;
  uchar4* d_image = nullptr;
  CUDA_CHECK(cudaMalloc(&d_image, width * height * sizeof(uchar4)));  // typed overload
  cudaStream_t stream;
  CUDA_CHECK(cudaStreamCreate(&stream));
  Params params = {d_image, width, height, make_float3(0, 0, 2), ias_handle};
  CUdeviceptr d_params = 0;
  CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_params), sizeof(Params)));
  CUDA_CHECK(cudaMemcpyAsync(reinterpret_cast<void*>(d_params), &params, sizeof(params),
                             cudaMemcpyHostToDevice, stream));
  cudaEvent_t start, stop;
  CUDA_CHECK(cudaEventCreate(&start));
  CUDA_CHECK(cudaEventCreate(&stop));
  CUDA_CHECK(cudaEventRecord(start, stream));
  OPTIX_CHECK(optixLaunch(pipeline, stream, d_params, sizeof(Params), &sbt, width, height, 1));
  CUDA_CHECK(cudaEventRecord(stop, stream));
  CUDA_CHECK(cudaStreamSynchronize(stream));
  float ms = 0;
  CUDA_CHECK(cudaEventElapsedTime(&ms, start, stop));
  std::vector<uchar4> image(width * height);
  CUDA_CHECK(
      cudaMemcpy(image.data(), d_image, width * height * sizeof(uchar4), cudaMemcpyDeviceToHost));
  CUDA_CHECK(cudaMemset(d_image, 0, width * height * sizeof(uchar4)));
  CUDA_CHECK(cudaMemsetAsync(d_image, 0, width * height * sizeof(uchar4), stream));
  CUDA_CHECK(cudaDeviceSynchronize());
  CUDA_CHECK(cudaGetLastError());
  CUDA_CHECK(cudaPeekAtLastError());

  // A texture, as SDK samples create them.
  cudaChannelFormatDesc channel_desc = cudaCreateChannelDesc<uchar4>();
  cudaArray_t texture_array = nullptr;
  CUDA_CHECK(cudaMallocArray(&texture_array, &channel_desc, width, height));
  CUDA_CHECK(cudaMemcpy2DToArray(texture_array, 0, 0, image.data(), width * sizeof(uchar4),
                                 width * sizeof(uchar4), height, cudaMemcpyHostToDevice));
  cudaResourceDesc res_desc = {};
  res_desc.resType = cudaResourceTypeArray;
  res_desc.res.array.array = texture_array;
  cudaTextureDesc tex_desc = {};
  tex_desc.addressMode[0] = cudaAddressModeWrap;
  tex_desc.addressMode[1] = cudaAddressModeClamp;
  tex_desc.filterMode = cudaFilterModeLinear;
  tex_desc.readMode = cudaReadModeNormalizedFloat;
  tex_desc.normalizedCoords = 1;
  tex_desc.maxAnisotropy = 1;
  tex_desc.sRGB = 0;
  cudaTextureObject_t texture = 0;
  CUDA_CHECK(cudaCreateTextureObject(&texture, &res_desc, &tex_desc, nullptr));
  cudaArray_t volume = nullptr;
  const cudaChannelFormatDesc float_desc = cudaCreateChannelDesc<float>();
  CUDA_CHECK(cudaMalloc3DArray(&volume, &float_desc, make_cudaExtent(8, 8, 8)));
  cudaMemcpy3DParms copy = {};
  copy.dstArray = volume;
  copy.extent = make_cudaExtent(8, 8, 8);
  copy.kind = cudaMemcpyHostToDevice;
  CUDA_CHECK(cudaMemcpy3D(&copy));
  CUDA_CHECK(cudaDestroyTextureObject(texture));
  CUDA_CHECK(cudaFreeArray(texture_array));
  CUDA_CHECK(cudaFreeArray(volume));

  // Managed and peer memory.
  float* managed = nullptr;
  CUDA_CHECK(cudaMallocManaged(&managed, 16 * sizeof(float)));
  CUDA_CHECK(cudaMemcpyPeer(managed, 0, reinterpret_cast<void*>(d_params), 0, sizeof(float)));

  // Clean up.
  CUDA_CHECK(cudaFree(managed));
  CUDA_CHECK(cudaEventDestroy(start));
  CUDA_CHECK(cudaEventDestroy(stop));
  CUDA_CHECK(cudaStreamDestroy(stream));
  OPTIX_CHECK(optixPipelineDestroy(pipeline));
  for (OptixProgramGroup group : groups) OPTIX_CHECK(optixProgramGroupDestroy(group));
  OPTIX_CHECK(optixModuleDestroy(module));
  OPTIX_CHECK(optixDeviceContextDestroy(context));
  return 0;
}

int main(int argc, char** argv) {
  // Never true in practice: the calls above are compiled, and would run only for such a command.
  if (argc > 100) return RenderTriangleAndSphere(argv[1], 0);
  return 0;
}
