// What every OptiX 7 sample's host code shares, written as OptiX 7 SDK samples write it: error
// checks around CUDA and OptiX calls, a device context with a log callback, a typed SBT record,
// device buffers, and the image written through OpenImageIO.
#ifndef TESSERA_SAMPLES_OPTIX7_COMMON_SAMPLE_UTIL_H_
#define TESSERA_SAMPLES_OPTIX7_COMMON_SAMPLE_UTIL_H_

#include <cuda_runtime.h>
#include <optix.h>
#include <optix_stubs.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#define CUDA_CHECK(call)                                                                    \
  do {                                                                                      \
    cudaError_t error_ = (call);                                                            \
    if (error_ != cudaSuccess) {                                                            \
      std::fprintf(stderr, "%s:%d: CUDA call '%s' failed: %s\n", __FILE__, __LINE__, #call, \
                   cudaGetErrorString(error_));                                             \
      std::exit(1);                                                                         \
    }                                                                                       \
  } while (0)

#define OPTIX_CHECK(call)                                                                         \
  do {                                                                                            \
    OptixResult result_ = (call);                                                                 \
    if (result_ != OPTIX_SUCCESS) {                                                               \
      std::fprintf(stderr, "%s:%d: OptiX call '%s' failed: %s (%s)\n", __FILE__, __LINE__, #call, \
                   optixGetErrorName(result_), optixGetErrorString(result_));                     \
      std::exit(1);                                                                               \
    }                                                                                             \
  } while (0)

// An SBT record: the header optixSbtRecordPackHeader fills, then the program's data.
template <typename T>
struct SbtRecord {
  __align__(OPTIX_SBT_RECORD_ALIGNMENT) char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  T data;
};
struct EmptyData {};

namespace sample {

// optixInit, cudaFree(0) and a device context whose log messages go to stderr.
OptixDeviceContext CreateContext();

// Copies `bytes` from the host into a new device allocation.
CUdeviceptr Upload(const void* data, size_t bytes);
template <typename T>
CUdeviceptr Upload(const std::vector<T>& v) {
  return Upload(v.data(), v.size() * sizeof(T));
}
template <typename T>
std::vector<T> Download(CUdeviceptr from, size_t count) {
  std::vector<T> v(count);
  CUDA_CHECK(cudaMemcpy(v.data(), reinterpret_cast<const void*>(from), count * sizeof(T),
                        cudaMemcpyDeviceToHost));
  return v;
}

// A packed SBT record of `group` carrying `data`, uploaded.
template <typename T>
CUdeviceptr UploadRecord(OptixProgramGroup group, const T& data) {
  SbtRecord<T> record;
  OPTIX_CHECK(optixSbtRecordPackHeader(group, &record));
  record.data = data;
  return Upload(&record, sizeof(record));
}

// A module from an OptiX 7 program as the application has it (the embedded text of
// tessera_embed_program, a source string or a path).
OptixModule CreateModule(OptixDeviceContext context,
                         const OptixModuleCompileOptions& module_options,
                         const OptixPipelineCompileOptions& pipeline_options,
                         const std::string& input);

// Builds an acceleration structure from `inputs`, compacted as the SDK samples do.
OptixTraversableHandle BuildAccel(OptixDeviceContext context, const OptixBuildInput* inputs,
                                  unsigned count, unsigned build_flags, CUdeviceptr* storage);

// Writes RGBA8 pixels (row 0 at the bottom, as launches write them) to `path` (PNG).
void WriteImage(const std::string& path, int width, int height, const std::vector<uchar4>& pixels);

// The value after `flag` in argv, or `fallback`.
std::string Option(int argc, char** argv, const char* flag, const std::string& fallback);

}  // namespace sample

#endif  // TESSERA_SAMPLES_OPTIX7_COMMON_SAMPLE_UTIL_H_
