// The denoiser and the opacity and displacement micromap functions: OPTIX_ERROR_NOT_SUPPORTED,
// with a message saying why. OptiX's denoiser is a trained network that NVIDIA ships inside its
// driver for its GPUs; there is none for CPUs here (an application can denoise with Intel Open
// Image Denoise on the host instead). Micromaps have no counterpart in Embree 3, which traces
// Tessera's scenes. Handles are still checked first, so a bad argument reads as one.
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "call.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

constexpr char kNoDenoiser[] =
    "the OptiX AI denoiser is not supported: its trained network ships with NVIDIA's driver "
    "for its GPUs and Tessera runs on CPUs (denoise on the host, e.g. with Intel Open Image "
    "Denoise)";
constexpr char kNoMicromaps[] =
    "opacity and displacement micromaps are not supported: Embree, which traces Tessera's "
    "scenes, has no micromaps (use any-hit programs for cut-outs)";

// A context-taking function that Tessera does not support.
OptixResult Unsupported(const char* function, OptixDeviceContext context, const char* why) {
  return Call(function).Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    return OptixError(OPTIX_ERROR_NOT_SUPPORTED, why);
  });
}

// A denoiser function: no denoiser handle can exist, so any one is invalid.
OptixResult NoDenoiser(const char* function, OptixDenoiser denoiser) {
  return Call(function).Run([&](Call&) -> absl::Status {
    if (denoiser == nullptr) return OptixError(OPTIX_ERROR_INVALID_VALUE, "denoiser is null");
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("denoiser is not a live OptixDenoiser (", kNoDenoiser, ")"));
  });
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::kNoDenoiser;
using tessera::optix7::kNoMicromaps;
using tessera::optix7::NoDenoiser;
using tessera::optix7::Unsupported;

extern "C" {

OptixResult optixDenoiserCreate(OptixDeviceContext context, OptixDenoiserModelKind,
                                const OptixDenoiserOptions*, OptixDenoiser* denoiser) {
  if (denoiser != nullptr) *denoiser = nullptr;
  return Unsupported("optixDenoiserCreate", context, kNoDenoiser);
}

OptixResult optixDenoiserCreateWithUserModel(OptixDeviceContext context, const void*, size_t,
                                             OptixDenoiser* denoiser) {
  if (denoiser != nullptr) *denoiser = nullptr;
  return Unsupported("optixDenoiserCreateWithUserModel", context, kNoDenoiser);
}

OptixResult optixDenoiserDestroy(OptixDenoiser denoiser) {
  return NoDenoiser("optixDenoiserDestroy", denoiser);
}

OptixResult optixDenoiserComputeMemoryResources(const OptixDenoiser denoiser, unsigned int,
                                                unsigned int, OptixDenoiserSizes*) {
  return NoDenoiser("optixDenoiserComputeMemoryResources", denoiser);
}

OptixResult optixDenoiserSetup(OptixDenoiser denoiser, CUstream, unsigned int, unsigned int,
                               CUdeviceptr, size_t, CUdeviceptr, size_t) {
  return NoDenoiser("optixDenoiserSetup", denoiser);
}

OptixResult optixDenoiserInvoke(OptixDenoiser denoiser, CUstream, const OptixDenoiserParams*,
                                CUdeviceptr, size_t, const OptixDenoiserGuideLayer*,
                                const OptixDenoiserLayer*, unsigned int, unsigned int, unsigned int,
                                CUdeviceptr, size_t) {
  return NoDenoiser("optixDenoiserInvoke", denoiser);
}

OptixResult optixDenoiserComputeIntensity(OptixDenoiser denoiser, CUstream, const OptixImage2D*,
                                          CUdeviceptr, CUdeviceptr, size_t) {
  return NoDenoiser("optixDenoiserComputeIntensity", denoiser);
}

OptixResult optixDenoiserComputeAverageColor(OptixDenoiser denoiser, CUstream, const OptixImage2D*,
                                             CUdeviceptr, CUdeviceptr, size_t) {
  return NoDenoiser("optixDenoiserComputeAverageColor", denoiser);
}

OptixResult optixOpacityMicromapArrayComputeMemoryUsage(OptixDeviceContext context,
                                                        const OptixOpacityMicromapArrayBuildInput*,
                                                        OptixMicromapBufferSizes*) {
  return Unsupported("optixOpacityMicromapArrayComputeMemoryUsage", context, kNoMicromaps);
}

OptixResult optixOpacityMicromapArrayBuild(OptixDeviceContext context, CUstream,
                                           const OptixOpacityMicromapArrayBuildInput*,
                                           const OptixMicromapBuffers*) {
  return Unsupported("optixOpacityMicromapArrayBuild", context, kNoMicromaps);
}

OptixResult optixOpacityMicromapArrayGetRelocationInfo(OptixDeviceContext context, CUdeviceptr,
                                                       OptixRelocationInfo*) {
  return Unsupported("optixOpacityMicromapArrayGetRelocationInfo", context, kNoMicromaps);
}

OptixResult optixOpacityMicromapArrayRelocate(OptixDeviceContext context, CUstream,
                                              const OptixRelocationInfo*, CUdeviceptr, size_t) {
  return Unsupported("optixOpacityMicromapArrayRelocate", context, kNoMicromaps);
}

OptixResult optixDisplacementMicromapArrayComputeMemoryUsage(
    OptixDeviceContext context, const OptixDisplacementMicromapArrayBuildInput*,
    OptixMicromapBufferSizes*) {
  return Unsupported("optixDisplacementMicromapArrayComputeMemoryUsage", context, kNoMicromaps);
}

OptixResult optixDisplacementMicromapArrayBuild(OptixDeviceContext context, CUstream,
                                                const OptixDisplacementMicromapArrayBuildInput*,
                                                const OptixMicromapBuffers*) {
  return Unsupported("optixDisplacementMicromapArrayBuild", context, kNoMicromaps);
}

}  // extern "C"
