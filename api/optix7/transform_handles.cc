// optixConvertPointerToTraversableHandle: the handle of a static or motion transform is its
// address in device memory with its type in the low bits, which the trace path reads as OptiX's
// does (worker/core/optix7_transforms.h).
#include <memory>

#include "absl/strings/str_cat.h"
#include "call.h"
#include "host_device_memory.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

size_t TransformBytes(OptixTraversableType type) {
  switch (type) {
    case OPTIX_TRAVERSABLE_TYPE_STATIC_TRANSFORM:
      return sizeof(OptixStaticTransform);
    case OPTIX_TRAVERSABLE_TYPE_MATRIX_MOTION_TRANSFORM:
      return sizeof(OptixMatrixMotionTransform);
    case OPTIX_TRAVERSABLE_TYPE_SRT_MOTION_TRANSFORM:
      return sizeof(OptixSRTMotionTransform);
  }
  return 0;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::HostDeviceMemory;
using tessera::optix7::OptixError;

extern "C" {

OptixResult optixConvertPointerToTraversableHandle(OptixDeviceContext onDevice, CUdeviceptr pointer,
                                                   OptixTraversableType traversableType,
                                                   OptixTraversableHandle* traversableHandle) {
  return Call("optixConvertPointerToTraversableHandle").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(onDevice, "onDevice", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(traversableHandle, "traversableHandle"); !s.ok()) return s;
    const size_t bytes = tessera::optix7::TransformBytes(traversableType);
    if (bytes == 0) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("traversableType 0x", absl::Hex(static_cast<unsigned>(traversableType)),
                       " is no OptixTraversableType"));
    }
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::HostDeviceMemory::Get();
    if (!m.ok()) return m.status();
    if (pointer == 0 || pointer % OPTIX_TRANSFORM_BYTE_ALIGNMENT != 0 ||
        !(*m)->IsAllocated(pointer, bytes)) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("pointer 0x", absl::Hex(pointer), " is not ", bytes,
                                     " bytes of device memory, OPTIX_TRANSFORM_BYTE_ALIGNMENT (64) "
                                     "aligned"));
    }
    // The handle is the address with the OptixTransformType in its low bits (the pointer is
    // 64-byte aligned; accelerations' handles, 128-byte aligned, have none): the engine tells a
    // transform from an acceleration, and the three kinds apart, without reading device memory.
    const unsigned tag = traversableType == OPTIX_TRAVERSABLE_TYPE_STATIC_TRANSFORM
                             ? OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM
                         : traversableType == OPTIX_TRAVERSABLE_TYPE_MATRIX_MOTION_TRANSFORM
                             ? OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM
                             : OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM;
    *traversableHandle = pointer | tag;
    return absl::OkStatus();
  });
}

}  // extern "C"
