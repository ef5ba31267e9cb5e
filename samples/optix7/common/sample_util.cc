#include "sample_util.h"

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <memory>

namespace sample {
namespace {

void LogCallback(unsigned int level, const char* tag, const char* message, void*) {
  std::fprintf(stderr, "[optix %u][%s] %s\n", level, tag, message);
}

}  // namespace

OptixDeviceContext CreateContext() {
  CUDA_CHECK(cudaFree(nullptr));  // initializes CUDA, as the SDK samples do
  OPTIX_CHECK(optixInit());
  OptixDeviceContextOptions options = {};
  options.logCallbackFunction = &LogCallback;
  options.logCallbackLevel = 3;  // fatal, errors and warnings
  OptixDeviceContext context = nullptr;
  CUcontext cu_context = nullptr;  // the current one
  OPTIX_CHECK(optixDeviceContextCreate(cu_context, &options, &context));
  return context;
}

CUdeviceptr Upload(const void* data, size_t bytes) {
  void* device = nullptr;
  CUDA_CHECK(cudaMalloc(&device, bytes));
  CUDA_CHECK(cudaMemcpy(device, data, bytes, cudaMemcpyHostToDevice));
  return reinterpret_cast<CUdeviceptr>(device);
}

OptixModule CreateModule(OptixDeviceContext context,
                         const OptixModuleCompileOptions& module_options,
                         const OptixPipelineCompileOptions& pipeline_options,
                         const std::string& input) {
  char log[2048];
  size_t log_size = sizeof(log);
  OptixModule module = nullptr;
  const OptixResult result =
      optixModuleCreate(context, &module_options, &pipeline_options, input.c_str(), input.size(),
                        log, &log_size, &module);
  if (result != OPTIX_SUCCESS) {
    std::fprintf(stderr, "optixModuleCreate failed: %s\n%s\n", optixGetErrorName(result), log);
    std::exit(1);
  }
  return module;
}

OptixTraversableHandle BuildAccel(OptixDeviceContext context, const OptixBuildInput* inputs,
                                  unsigned count, unsigned build_flags, CUdeviceptr* storage) {
  OptixAccelBuildOptions options = {};
  options.buildFlags = build_flags | OPTIX_BUILD_FLAG_ALLOW_COMPACTION;
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  OptixAccelBufferSizes sizes;
  OPTIX_CHECK(optixAccelComputeMemoryUsage(context, &options, inputs, count, &sizes));
  void* temp = nullptr;
  void* output = nullptr;
  void* compacted_size = nullptr;
  CUDA_CHECK(cudaMalloc(&temp, sizes.tempSizeInBytes));
  CUDA_CHECK(cudaMalloc(&output, sizes.outputSizeInBytes));
  CUDA_CHECK(cudaMalloc(&compacted_size, sizeof(size_t)));
  OptixAccelEmitDesc emit = {};
  emit.type = OPTIX_PROPERTY_TYPE_COMPACTED_SIZE;
  emit.result = reinterpret_cast<CUdeviceptr>(compacted_size);
  OptixTraversableHandle handle = 0;
  OPTIX_CHECK(optixAccelBuild(context, nullptr, &options, inputs, count,
                              reinterpret_cast<CUdeviceptr>(temp), sizes.tempSizeInBytes,
                              reinterpret_cast<CUdeviceptr>(output), sizes.outputSizeInBytes,
                              &handle, &emit, 1));
  size_t compacted = 0;
  CUDA_CHECK(cudaMemcpy(&compacted, compacted_size, sizeof(size_t), cudaMemcpyDeviceToHost));
  CUDA_CHECK(cudaFree(temp));
  CUDA_CHECK(cudaFree(compacted_size));
  if (compacted < sizes.outputSizeInBytes) {
    void* small = nullptr;
    CUDA_CHECK(cudaMalloc(&small, compacted));
    OPTIX_CHECK(optixAccelCompact(context, nullptr, handle, reinterpret_cast<CUdeviceptr>(small),
                                  compacted, &handle));
    CUDA_CHECK(cudaFree(output));
    output = small;
  }
  *storage = reinterpret_cast<CUdeviceptr>(output);
  return handle;
}

void WriteImage(const std::string& path, int width, int height, const std::vector<uchar4>& pixels) {
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
  if (!out) {
    std::fprintf(stderr, "cannot write %s: %s\n", path.c_str(), OIIO::geterror().c_str());
    std::exit(1);
  }
  OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::UINT8);
  // Launch row 0 is the bottom of the image; files start at the top.
  const auto* last_row =
      reinterpret_cast<const unsigned char*>(&pixels[size_t(height - 1) * width]);
  if (!out->open(path, spec) ||
      !out->write_image(OIIO::TypeDesc::UINT8, last_row, OIIO::AutoStride,
                        -static_cast<OIIO::stride_t>(width * sizeof(uchar4))) ||
      !out->close()) {
    std::fprintf(stderr, "cannot write %s: %s\n", path.c_str(), out->geterror().c_str());
    std::exit(1);
  }
}

std::string Option(int argc, char** argv, const char* flag, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], flag) == 0) return argv[i + 1];
  }
  return fallback;
}

}  // namespace sample
