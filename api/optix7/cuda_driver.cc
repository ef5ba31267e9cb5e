// The CUDA driver API subset of cuda.h that OptiX 7 applications call around OptiX: devices,
// contexts, a few memory and stream calls, errors. A CUcontext is a device and nothing more
// (memory, streams and modules are not per context here), so the driver calls are the runtime's
// with the driver's result codes; contexts exist so that an application that creates one per
// device, makes it current and passes it to optixDeviceContextCreate gets that device.
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "cuda.h"
#include "cuda_devices.h"
#include "cuda_runtime_api.h"

struct CUctx_st {
  int device = 0;
};

namespace tessera::optix7 {
namespace {

// Live contexts: primary contexts (one per device, made when first named, never destroyed, as
// CUDA's live as long as the process here) and those of cuCtxCreate.
class Contexts {
 public:
  static Contexts& Get() {
    static Contexts* c = new Contexts;
    return *c;
  }
  CUcontext Primary(int device) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::unique_ptr<CUctx_st>& p = primary_[device];
    if (!p) {
      p = std::make_unique<CUctx_st>();
      p->device = device;
      live_.insert(p.get());
    }
    return p.get();
  }
  CUcontext Create(int device) {
    auto* c = new CUctx_st;
    c->device = device;
    std::lock_guard<std::mutex> lock(mutex_);
    live_.insert(c);
    return c;
  }
  // False for a context that is not live, or is a primary one (cuCtxDestroy refuses those).
  bool Destroy(CUcontext c) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto p = primary_.find(c == nullptr ? -1 : DeviceLocked(c));
    if (live_.count(c) == 0 || (p != primary_.end() && p->second.get() == c)) return false;
    live_.erase(c);
    delete c;
    return true;
  }
  // The device of a live context, -1 otherwise.
  int DeviceOf(const void* c) {
    std::lock_guard<std::mutex> lock(mutex_);
    return DeviceLocked(c);
  }

 private:
  int DeviceLocked(const void* c) const {
    auto it = live_.find(static_cast<CUcontext>(const_cast<void*>(c)));
    return it == live_.end() ? -1 : (*it)->device;
  }
  std::mutex mutex_;
  std::map<int, std::unique_ptr<CUctx_st>> primary_;
  std::set<CUcontext> live_;
};

// The calling thread's context stack (cuCtxPushCurrent); empty: the current device's primary
// context, which the runtime makes current as CUDA 12's does.
thread_local std::vector<CUcontext> t_stack;

CUcontext CurrentContext() {
  return t_stack.empty() ? Contexts::Get().Primary(CurrentCudaDevice()) : t_stack.back();
}

// The runtime follows the driver's current context, as in CUDA.
void Follow() {
  if (!t_stack.empty()) SetCurrentCudaDevice(t_stack.back()->device);
}

CUresult FromRuntime(cudaError_t e) {
  switch (e) {
    case cudaSuccess:
      return CUDA_SUCCESS;
    case cudaErrorInvalidValue:
    case cudaErrorInvalidDevicePointer:
    case cudaErrorInvalidMemcpyDirection:
      return CUDA_ERROR_INVALID_VALUE;
    case cudaErrorMemoryAllocation:
      return CUDA_ERROR_OUT_OF_MEMORY;
    case cudaErrorInitializationError:
      return CUDA_ERROR_NOT_INITIALIZED;
    case cudaErrorNoDevice:
      return CUDA_ERROR_NO_DEVICE;
    case cudaErrorInvalidDevice:
      return CUDA_ERROR_INVALID_DEVICE;
    case cudaErrorInvalidResourceHandle:
      return CUDA_ERROR_INVALID_HANDLE;
    case cudaErrorNotSupported:
      return CUDA_ERROR_NOT_SUPPORTED;
    default:
      return CUDA_ERROR_UNKNOWN;
  }
}

bool ValidOrdinal(int device) {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && device >= 0 && device < count;
}

}  // namespace

int CudaDeviceOfContext(const void* context) {
  return context == nullptr ? -1 : Contexts::Get().DeviceOf(context);
}

}  // namespace tessera::optix7

using tessera::optix7::Contexts;
using tessera::optix7::FromRuntime;
using tessera::optix7::t_stack;

extern "C" {

CUresult cuInit(unsigned int flags) { return flags == 0 ? CUDA_SUCCESS : CUDA_ERROR_INVALID_VALUE; }

CUresult cuDriverGetVersion(int* driverVersion) {
  return FromRuntime(cudaDriverGetVersion(driverVersion));
}

CUresult cuDeviceGetCount(int* count) { return FromRuntime(cudaGetDeviceCount(count)); }

CUresult cuDeviceGet(CUdevice* device, int ordinal) {
  if (device == nullptr) return CUDA_ERROR_INVALID_VALUE;
  if (!tessera::optix7::ValidOrdinal(ordinal)) return CUDA_ERROR_INVALID_DEVICE;
  *device = ordinal;  // a CUdevice is its ordinal, as in CUDA
  return CUDA_SUCCESS;
}

CUresult cuDeviceGetName(char* name, int len, CUdevice dev) {
  if (name == nullptr || len <= 0) return CUDA_ERROR_INVALID_VALUE;
  cudaDeviceProp prop;
  if (CUresult r = FromRuntime(cudaGetDeviceProperties(&prop, dev)); r != CUDA_SUCCESS) return r;
  const size_t n = std::min(sizeof(prop.name) - 1, static_cast<size_t>(len) - 1);
  std::copy(prop.name, prop.name + n, name);
  name[n] = '\0';
  return CUDA_SUCCESS;
}

CUresult cuCtxGetCurrent(CUcontext* pctx) {
  if (pctx == nullptr) return CUDA_ERROR_INVALID_VALUE;
  *pctx = tessera::optix7::CurrentContext();
  return CUDA_SUCCESS;
}

CUresult cuCtxSetCurrent(CUcontext ctx) {
  if (ctx == nullptr) {  // unbinds: the runtime's primary context is current again
    if (!t_stack.empty()) t_stack.pop_back();
    tessera::optix7::Follow();
    return CUDA_SUCCESS;
  }
  if (Contexts::Get().DeviceOf(ctx) < 0) return CUDA_ERROR_INVALID_CONTEXT;
  if (t_stack.empty()) {
    t_stack.push_back(ctx);
  } else {
    t_stack.back() = ctx;
  }
  tessera::optix7::Follow();
  return CUDA_SUCCESS;
}

CUresult cuCtxCreate_v2(CUcontext* pctx, unsigned int flags, CUdevice dev) {
  (void)flags;  // scheduling and host-mapping flags mean nothing for CPU devices
  if (pctx == nullptr) return CUDA_ERROR_INVALID_VALUE;
  if (!tessera::optix7::ValidOrdinal(dev)) return CUDA_ERROR_INVALID_DEVICE;
  *pctx = Contexts::Get().Create(dev);
  t_stack.push_back(*pctx);  // a new context is current, as in CUDA
  tessera::optix7::Follow();
  return CUDA_SUCCESS;
}

CUresult cuCtxDestroy_v2(CUcontext ctx) {
  if (!Contexts::Get().Destroy(ctx)) return CUDA_ERROR_INVALID_CONTEXT;
  t_stack.erase(std::remove(t_stack.begin(), t_stack.end(), ctx), t_stack.end());
  tessera::optix7::Follow();
  return CUDA_SUCCESS;
}

CUresult cuCtxPushCurrent_v2(CUcontext ctx) {
  if (Contexts::Get().DeviceOf(ctx) < 0) return CUDA_ERROR_INVALID_CONTEXT;
  t_stack.push_back(ctx);
  tessera::optix7::Follow();
  return CUDA_SUCCESS;
}

CUresult cuCtxPopCurrent_v2(CUcontext* pctx) {
  if (t_stack.empty()) return CUDA_ERROR_INVALID_CONTEXT;
  if (pctx != nullptr) *pctx = t_stack.back();
  t_stack.pop_back();
  tessera::optix7::Follow();
  return CUDA_SUCCESS;
}

CUresult cuCtxSynchronize(void) { return CUDA_SUCCESS; }  // every call has finished

CUresult cuMemAlloc_v2(CUdeviceptr* dptr, size_t bytesize) {
  if (dptr == nullptr) return CUDA_ERROR_INVALID_VALUE;
  void* p = nullptr;
  const CUresult r = FromRuntime(cudaMalloc(&p, bytesize));
  *dptr = reinterpret_cast<CUdeviceptr>(p);
  return r;
}

CUresult cuMemFree_v2(CUdeviceptr dptr) {
  return FromRuntime(cudaFree(reinterpret_cast<void*>(dptr)));
}

CUresult cuMemcpyHtoD_v2(CUdeviceptr dstDevice, const void* srcHost, size_t ByteCount) {
  return FromRuntime(
      cudaMemcpy(reinterpret_cast<void*>(dstDevice), srcHost, ByteCount, cudaMemcpyHostToDevice));
}

CUresult cuMemcpyDtoH_v2(void* dstHost, CUdeviceptr srcDevice, size_t ByteCount) {
  return FromRuntime(cudaMemcpy(dstHost, reinterpret_cast<const void*>(srcDevice), ByteCount,
                                cudaMemcpyDeviceToHost));
}

CUresult cuStreamCreate(CUstream* phStream, unsigned int Flags) {
  return FromRuntime(cudaStreamCreateWithFlags(reinterpret_cast<cudaStream_t*>(phStream), Flags));
}

CUresult cuStreamDestroy_v2(CUstream hStream) {
  return FromRuntime(cudaStreamDestroy(reinterpret_cast<cudaStream_t>(hStream)));
}

CUresult cuStreamSynchronize(CUstream hStream) {
  return FromRuntime(cudaStreamSynchronize(reinterpret_cast<cudaStream_t>(hStream)));
}

CUresult cuGetErrorName(CUresult error, const char** pStr) {
  if (pStr == nullptr) return CUDA_ERROR_INVALID_VALUE;
  switch (error) {
#define TESSERA_CU_ERROR_NAME(e) \
  case e:                        \
    *pStr = #e;                  \
    return CUDA_SUCCESS;
    TESSERA_CU_ERROR_NAME(CUDA_SUCCESS)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_INVALID_VALUE)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_OUT_OF_MEMORY)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NOT_INITIALIZED)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_DEINITIALIZED)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NO_DEVICE)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_INVALID_DEVICE)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_INVALID_IMAGE)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_INVALID_CONTEXT)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_CONTEXT_ALREADY_CURRENT)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_INVALID_HANDLE)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NOT_FOUND)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NOT_READY)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_ILLEGAL_ADDRESS)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_LAUNCH_FAILED)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NOT_PERMITTED)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_NOT_SUPPORTED)
    TESSERA_CU_ERROR_NAME(CUDA_ERROR_UNKNOWN)
#undef TESSERA_CU_ERROR_NAME
  }
  *pStr = nullptr;
  return CUDA_ERROR_INVALID_VALUE;  // as CUDA: not an error code
}

CUresult cuGetErrorString(CUresult error, const char** pStr) {
  if (pStr == nullptr) return CUDA_ERROR_INVALID_VALUE;
  switch (error) {
    case CUDA_SUCCESS:
      *pStr = "no error";
      return CUDA_SUCCESS;
    case CUDA_ERROR_INVALID_CONTEXT:
      *pStr = "invalid device context";
      return CUDA_SUCCESS;
    case CUDA_ERROR_INVALID_DEVICE:
      *pStr = "invalid device ordinal";
      return CUDA_SUCCESS;
    case CUDA_ERROR_INVALID_VALUE:
      *pStr = "invalid argument";
      return CUDA_SUCCESS;
    default:
      return cuGetErrorName(error, pStr);
  }
}

}  // extern "C"
