// The CUDA runtime subset of OptiX 7 applications (include7/cuda_runtime_api.h) over Tessera's
// device memory: one device or one per Tessera device (cuda_devices.h), all work done in host order
// (every call has finished when it returns, so streams and events only order what is already
// ordered), memory in the arena that workers map at the same addresses (docs/device_memory.md).
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cuda_arrays.h"
#include "cuda_devices.h"
#include "cuda_runtime_api.h"
#include "host_device_memory.h"

namespace tessera::optix7 {
namespace {

// CUDA's error state: the last error of the calling thread, until cudaGetLastError reads it.
thread_local cudaError_t t_last_error = cudaSuccess;

cudaError_t Result(cudaError_t e) {
  if (e != cudaSuccess) t_last_error = e;
  return e;
}

HostDeviceMemory* Memory() {
  absl::StatusOr<HostDeviceMemory*> m = HostDeviceMemory::Get();
  return m.ok() ? *m : nullptr;
}

uintptr_t Address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

// Where a cudaMemcpy's pointer must point for its kind: device memory must lie in one live
// allocation, host memory outside the arena.
bool Fits(HostDeviceMemory& m, const void* p, size_t count, bool device) {
  if (device) return m.IsAllocated(Address(p), count);
  return !m.InArena(Address(p));
}

struct Stream {
  unsigned flags = 0;
};
struct Event {
  unsigned flags = 0;
  bool recorded = false;
  std::chrono::steady_clock::time_point when;
};

// Live stream and event handles: a handle that is not one (destroyed, null, a stand-in such as
// cudaStreamLegacy, garbage) is an error, never a crash.
class Handles {
 public:
  void Add(const void* h) {
    std::lock_guard<std::mutex> lock(mutex_);
    live_.insert(h);
  }
  bool Remove(const void* h) {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_.erase(h) == 1;
  }
  bool Has(const void* h) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return live_.count(h) == 1;
  }

 private:
  mutable std::mutex mutex_;
  std::set<const void*> live_;
};
Handles& Streams() {
  static Handles* h = new Handles;
  return *h;
}
Handles& Events() {
  static Handles* h = new Handles;
  return *h;
}
// A device ordinal of the current mode (cuda_devices.h).
bool ValidDevice(int device) {
  if (device < 0) return false;
  absl::StatusOr<std::vector<CudaDevice>> devices = CudaDevices();
  return devices.ok() && device < static_cast<int>(devices->size());
}

// A stream argument: null (the default stream), CUDA's stand-ins, or a live stream.
bool ValidStream(cudaStream_t s) {
  return s == nullptr || s == cudaStreamLegacy || s == cudaStreamPerThread || Streams().Has(s);
}

}  // namespace

cudaError_t RecordCudaError(cudaError_t e) { return Result(e); }

}  // namespace tessera::optix7

using tessera::optix7::HostDeviceMemory;
using tessera::optix7::Result;
using tessera::optix7::t_last_error;

extern "C" {

// ---- Errors ------------------------------------------------------------------------------------

cudaError_t cudaGetLastError(void) {
  const cudaError_t e = t_last_error;
  t_last_error = cudaSuccess;
  return e;
}

cudaError_t cudaPeekAtLastError(void) { return t_last_error; }

const char* cudaGetErrorName(cudaError_t error) {
  switch (error) {
#define TESSERA_CUDA_ERROR_NAME(e) \
  case e:                          \
    return #e;
    TESSERA_CUDA_ERROR_NAME(cudaSuccess)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidValue)
    TESSERA_CUDA_ERROR_NAME(cudaErrorMemoryAllocation)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInitializationError)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidPitchValue)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidDevicePointer)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidChannelDescriptor)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidMemcpyDirection)
    TESSERA_CUDA_ERROR_NAME(cudaErrorNoDevice)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidDevice)
    TESSERA_CUDA_ERROR_NAME(cudaErrorInvalidResourceHandle)
    TESSERA_CUDA_ERROR_NAME(cudaErrorNotReady)
    TESSERA_CUDA_ERROR_NAME(cudaErrorIllegalAddress)
    TESSERA_CUDA_ERROR_NAME(cudaErrorPeerAccessAlreadyEnabled)
    TESSERA_CUDA_ERROR_NAME(cudaErrorPeerAccessNotEnabled)
    TESSERA_CUDA_ERROR_NAME(cudaErrorLaunchFailure)
    TESSERA_CUDA_ERROR_NAME(cudaErrorNotSupported)
    TESSERA_CUDA_ERROR_NAME(cudaErrorUnknown)
#undef TESSERA_CUDA_ERROR_NAME
    default:
      return "cudaErrorUnknown";
  }
}

const char* cudaGetErrorString(cudaError_t error) {
  switch (error) {
    case cudaSuccess:
      return "no error";
    case cudaErrorInvalidValue:
      return "invalid argument";
    case cudaErrorMemoryAllocation:
      return "out of memory (Tessera's device memory: its range is full, or it could not be "
             "reserved at TESSERA_DEVICE_MEMORY_BASE)";
    case cudaErrorInitializationError:
      return "initialization error: Tessera could not reserve its device memory range (set "
             "TESSERA_DEVICE_MEMORY_BASE to a free range)";
    case cudaErrorInvalidPitchValue:
      return "invalid pitch argument";
    case cudaErrorInvalidDevicePointer:
      return "invalid device pointer (not the start of a cudaMalloc allocation)";
    case cudaErrorInvalidChannelDescriptor:
      return "invalid channel descriptor (1, 2 or 4 channels of 8, 16 or 32 bits, float 16 or 32)";
    case cudaErrorNotSupported:
      return "operation not supported (by Tessera: docs/COMPATIBILITY.md, OptiX 7)";
    case cudaErrorInvalidMemcpyDirection:
      return "invalid copy direction for memcpy (a pointer is not where the kind says: device "
             "memory must lie in one cudaMalloc allocation, host memory outside device memory)";
    case cudaErrorInvalidDevice:
      return "invalid device ordinal";
    case cudaErrorInvalidResourceHandle:
      return "invalid resource handle";
    case cudaErrorNotReady:
      return "device not ready";
    case cudaErrorPeerAccessAlreadyEnabled:
      return "peer access is already enabled";
    case cudaErrorPeerAccessNotEnabled:
      return "peer access has not been enabled";
    default:
      return cudaGetErrorName(error);
  }
}

// ---- Devices -----------------------------------------------------------------------------------

cudaError_t cudaGetDeviceCount(int* count) {
  if (count == nullptr) return Result(cudaErrorInvalidValue);
  absl::StatusOr<std::vector<tessera::optix7::CudaDevice>> devices = tessera::optix7::CudaDevices();
  if (!devices.ok() || devices->empty()) return Result(cudaErrorNoDevice);
  *count = static_cast<int>(devices->size());
  return cudaSuccess;
}

cudaError_t cudaSetDevice(int device) {
  if (!tessera::optix7::ValidDevice(device)) return Result(cudaErrorInvalidDevice);
  tessera::optix7::SetCurrentCudaDevice(device);
  return cudaSuccess;
}

cudaError_t cudaGetDevice(int* device) {
  if (device == nullptr) return Result(cudaErrorInvalidValue);
  *device = tessera::optix7::CurrentCudaDevice();
  return cudaSuccess;
}

cudaError_t cudaGetDeviceProperties(struct cudaDeviceProp* prop, int device) {
  if (prop == nullptr) return Result(cudaErrorInvalidValue);
  absl::StatusOr<std::vector<tessera::optix7::CudaDevice>> devices = tessera::optix7::CudaDevices();
  if (!devices.ok() || device < 0 || device >= static_cast<int>(devices->size())) {
    return Result(cudaErrorInvalidDevice);
  }
  const tessera::optix7::CudaDevice& d = (*devices)[device];
  std::memset(prop, 0, sizeof(*prop));
  std::strncpy(prop->name, d.name.c_str(), sizeof(prop->name) - 1);
  HostDeviceMemory* m = tessera::optix7::Memory();
  // Every device has the whole arena: one address range serves them all.
  prop->totalGlobalMem = m != nullptr ? m->capacity() : 0;
  prop->warpSize = 1;  // a launch index is not a warp lane
  prop->maxThreadsPerBlock = 1;
  prop->maxThreadsDim[0] = prop->maxThreadsDim[1] = prop->maxThreadsDim[2] = 1;
  prop->maxGridSize[0] = prop->maxGridSize[1] = prop->maxGridSize[2] = 0x7fffffff;
  prop->memPitch = prop->totalGlobalMem;
  prop->textureAlignment = tessera::memory::DeviceAllocator::kAlignment;
  prop->texturePitchAlignment = 32;  // what GPUs report; pitched textures need no more here
  prop->multiProcessorCount = d.threads;
  prop->canMapHostMemory = 0;
  return cudaSuccess;
}

cudaError_t cudaDeviceCanAccessPeer(int* canAccessPeer, int device, int peerDevice) {
  if (canAccessPeer == nullptr) return Result(cudaErrorInvalidValue);
  if (!tessera::optix7::ValidDevice(device) || !tessera::optix7::ValidDevice(peerDevice)) {
    return Result(cudaErrorInvalidDevice);
  }
  // One address range serves every device, so any may reach any other's memory once enabled;
  // a device and itself is 0, as in CUDA.
  *canAccessPeer = device != peerDevice ? 1 : 0;
  return cudaSuccess;
}

cudaError_t cudaDeviceEnablePeerAccess(int peerDevice, unsigned int flags) {
  if (flags != 0) return Result(cudaErrorInvalidValue);
  const int device = tessera::optix7::CurrentCudaDevice();
  if (!tessera::optix7::ValidDevice(peerDevice) || peerDevice == device) {
    return Result(cudaErrorInvalidDevice);
  }
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorInitializationError);
  // From now on the device's launches ship the peer's allocations too (launch_target.cc).
  return m->SetPeerAccess(device, peerDevice, true) ? cudaSuccess
                                                    : Result(cudaErrorPeerAccessAlreadyEnabled);
}

cudaError_t cudaDeviceDisablePeerAccess(int peerDevice) {
  const int device = tessera::optix7::CurrentCudaDevice();
  if (!tessera::optix7::ValidDevice(peerDevice) || peerDevice == device) {
    return Result(cudaErrorInvalidDevice);
  }
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorInitializationError);
  return m->SetPeerAccess(device, peerDevice, false) ? cudaSuccess
                                                     : Result(cudaErrorPeerAccessNotEnabled);
}

cudaError_t cudaDeviceSynchronize(void) { return cudaSuccess; }  // every call has finished

// Frees every cudaMalloc/cudaMallocManaged allocation of the current device, as CUDA destroys the
// device's context. Arrays and texture objects stay until their own free calls (their handles
// know who reads them); streams and events are plain handles with nothing on the device.
cudaError_t cudaDeviceReset(void) {
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return cudaSuccess;  // nothing was ever allocated
  const int device = tessera::optix7::CurrentCudaDevice();
  for (const auto& [address, size] : m->Allocations()) {
    if (m->OwnerOf(address) != device) continue;
    if (tessera::optix7::TextureHandles::Get().Owns(address)) continue;
    (void)m->Free(address);
  }
  return cudaSuccess;
}

cudaError_t cudaDriverGetVersion(int* version) {
  if (version == nullptr) return Result(cudaErrorInvalidValue);
  *version = 12000;
  return cudaSuccess;
}

cudaError_t cudaRuntimeGetVersion(int* version) { return cudaDriverGetVersion(version); }

cudaError_t cudaMemGetInfo(size_t* free, size_t* total) {
  if (free == nullptr || total == nullptr) return Result(cudaErrorInvalidValue);
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorInitializationError);
  *total = m->capacity();
  *free = m->capacity() - m->bytes_in_use();
  return cudaSuccess;
}

// ---- Memory ------------------------------------------------------------------------------------

cudaError_t cudaMalloc(void** ptr, size_t size) {
  if (ptr == nullptr) return Result(cudaErrorInvalidValue);
  *ptr = nullptr;
  if (size == 0) return cudaSuccess;  // as CUDA: no allocation, a null pointer
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorMemoryAllocation);
  // Owned by the current device: with one CUDA device per Tessera device, only its launches
  // (and its peers') ship it.
  absl::StatusOr<uintptr_t> address = m->Allocate(size, tessera::optix7::CurrentCudaDevice());
  if (!address.ok()) return Result(cudaErrorMemoryAllocation);
  *ptr = reinterpret_cast<void*>(*address);
  return cudaSuccess;
}

cudaError_t cudaMallocManaged(void** ptr, size_t size, unsigned int flags) {
  if (ptr == nullptr) return Result(cudaErrorInvalidValue);
  *ptr = nullptr;
  if (size == 0 || (flags != cudaMemAttachGlobal && flags != cudaMemAttachHost)) {
    return Result(cudaErrorInvalidValue);
  }
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorMemoryAllocation);
  // Device memory is host memory here: the host reads and writes it through the pointer, and
  // each launch first takes the host's view of it (HostDeviceMemory::MarkManagedWritten).
  absl::StatusOr<uintptr_t> address =
      m->Allocate(size, tessera::optix7::CurrentCudaDevice(), /*managed=*/true);
  if (!address.ok()) return Result(cudaErrorMemoryAllocation);
  *ptr = reinterpret_cast<void*>(*address);
  return cudaSuccess;
}

cudaError_t cudaFree(void* ptr) {
  if (ptr == nullptr) return cudaSuccess;  // cudaFree(0): the usual way to initialize CUDA
  HostDeviceMemory* m = tessera::optix7::Memory();
  // Arrays and texture objects are freed by their own calls, which know who still reads them.
  if (m == nullptr || tessera::optix7::TextureHandles::Get().Owns(tessera::optix7::Address(ptr)) ||
      !m->Free(tessera::optix7::Address(ptr)).ok()) {
    return Result(cudaErrorInvalidDevicePointer);
  }
  return cudaSuccess;
}

cudaError_t cudaMallocHost(void** ptr, size_t size) {
  if (ptr == nullptr) return Result(cudaErrorInvalidValue);
  // Page-locked memory has no meaning here: plain host memory, aligned like an allocation.
  *ptr = size == 0 ? nullptr : ::operator new (size, std::align_val_t{256}, std::nothrow);
  return size == 0 || *ptr != nullptr ? cudaSuccess : Result(cudaErrorMemoryAllocation);
}

cudaError_t cudaFreeHost(void* ptr) {
  if (ptr != nullptr) ::operator delete (ptr, std::align_val_t{256});
  return cudaSuccess;
}

cudaError_t cudaMallocPitch(void** ptr, size_t* pitch, size_t width, size_t height) {
  if (pitch == nullptr) return Result(cudaErrorInvalidValue);
  constexpr size_t kAlign = tessera::memory::DeviceAllocator::kAlignment;
  *pitch = (width + kAlign - 1) / kAlign * kAlign;
  return cudaMalloc(ptr, *pitch * height);
}

cudaError_t cudaMemcpy(void* dst, const void* src, size_t count, enum cudaMemcpyKind kind) {
  if (count == 0) return cudaSuccess;
  if (dst == nullptr || src == nullptr) return Result(cudaErrorInvalidValue);
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorInitializationError);
  if (kind == cudaMemcpyDefault) {  // unified addressing: the pointers say where they point
    const bool d = m->InArena(tessera::optix7::Address(dst));
    const bool s = m->InArena(tessera::optix7::Address(src));
    kind = d ? (s ? cudaMemcpyDeviceToDevice : cudaMemcpyHostToDevice)
             : (s ? cudaMemcpyDeviceToHost : cudaMemcpyHostToHost);
  }
  bool dst_device, src_device;
  switch (kind) {
    case cudaMemcpyHostToHost:
      dst_device = src_device = false;
      break;
    case cudaMemcpyHostToDevice:
      dst_device = true;
      src_device = false;
      break;
    case cudaMemcpyDeviceToHost:
      dst_device = false;
      src_device = true;
      break;
    case cudaMemcpyDeviceToDevice:
      dst_device = src_device = true;
      break;
    default:
      return Result(cudaErrorInvalidMemcpyDirection);
  }
  if (!tessera::optix7::Fits(*m, dst, count, dst_device) ||
      !tessera::optix7::Fits(*m, src, count, src_device)) {
    return Result(cudaErrorInvalidMemcpyDirection);
  }
  std::memmove(dst, src, count);
  if (dst_device) m->MarkWritten(tessera::optix7::Address(dst), count);
  return cudaSuccess;
}

cudaError_t cudaMemcpyAsync(void* dst, const void* src, size_t count, enum cudaMemcpyKind kind,
                            cudaStream_t stream) {
  if (!tessera::optix7::ValidStream(stream)) return Result(cudaErrorInvalidResourceHandle);
  return cudaMemcpy(dst, src, count, kind);  // done in host order
}

cudaError_t cudaMemcpy2D(void* dst, size_t dpitch, const void* src, size_t spitch, size_t width,
                         size_t height, enum cudaMemcpyKind kind) {
  if (width > dpitch || width > spitch) return Result(cudaErrorInvalidPitchValue);
  for (size_t row = 0; row < height; ++row) {
    const cudaError_t e = cudaMemcpy(static_cast<char*>(dst) + row * dpitch,
                                     static_cast<const char*>(src) + row * spitch, width, kind);
    if (e != cudaSuccess) return e;
  }
  return cudaSuccess;
}

cudaError_t cudaMemcpyPeer(void* dst, int dstDevice, const void* src, int srcDevice, size_t count) {
  if (!tessera::optix7::ValidDevice(dstDevice) || !tessera::optix7::ValidDevice(srcDevice)) {
    return Result(cudaErrorInvalidDevice);
  }
  // Both devices' memory lies in the one address range: a copy within it, which the next launch
  // of a device that may reach `dst` ships (the host's copy is authoritative).
  return cudaMemcpy(dst, src, count, cudaMemcpyDeviceToDevice);
}

cudaError_t cudaMemcpyPeerAsync(void* dst, int dstDevice, const void* src, int srcDevice,
                                size_t count, cudaStream_t stream) {
  if (!tessera::optix7::ValidStream(stream)) return Result(cudaErrorInvalidResourceHandle);
  return cudaMemcpyPeer(dst, dstDevice, src, srcDevice, count);  // done in host order
}

cudaError_t cudaMemset(void* ptr, int value, size_t count) {
  if (count == 0) return cudaSuccess;
  HostDeviceMemory* m = tessera::optix7::Memory();
  if (m == nullptr) return Result(cudaErrorInitializationError);
  if (!m->IsAllocated(tessera::optix7::Address(ptr), count)) {
    return Result(cudaErrorInvalidValue);
  }
  std::memset(ptr, value, count);
  m->MarkWritten(tessera::optix7::Address(ptr), count);
  return cudaSuccess;
}

cudaError_t cudaMemsetAsync(void* ptr, int value, size_t count, cudaStream_t stream) {
  if (!tessera::optix7::ValidStream(stream)) return Result(cudaErrorInvalidResourceHandle);
  return cudaMemset(ptr, value, count);
}

// ---- Streams and events (all work is done when its call returns) -------------------------------

cudaError_t cudaStreamCreateWithFlags(cudaStream_t* stream, unsigned int flags) {
  if (stream == nullptr) return Result(cudaErrorInvalidValue);
  *stream = reinterpret_cast<cudaStream_t>(new tessera::optix7::Stream{flags});
  tessera::optix7::Streams().Add(*stream);
  return cudaSuccess;
}

cudaError_t cudaStreamCreate(cudaStream_t* stream) { return cudaStreamCreateWithFlags(stream, 0); }

cudaError_t cudaStreamDestroy(cudaStream_t stream) {
  if (!tessera::optix7::Streams().Remove(stream)) return Result(cudaErrorInvalidResourceHandle);
  delete reinterpret_cast<tessera::optix7::Stream*>(stream);
  return cudaSuccess;
}

cudaError_t cudaStreamSynchronize(cudaStream_t stream) {
  return tessera::optix7::ValidStream(stream) ? cudaSuccess
                                              : Result(cudaErrorInvalidResourceHandle);
}
cudaError_t cudaStreamQuery(cudaStream_t stream) { return cudaStreamSynchronize(stream); }
cudaError_t cudaStreamWaitEvent(cudaStream_t stream, cudaEvent_t event, unsigned int) {
  if (!tessera::optix7::ValidStream(stream) || !tessera::optix7::Events().Has(event)) {
    return Result(cudaErrorInvalidResourceHandle);
  }
  return cudaSuccess;
}

cudaError_t cudaEventCreateWithFlags(cudaEvent_t* event, unsigned int flags) {
  if (event == nullptr) return Result(cudaErrorInvalidValue);
  auto* e = new tessera::optix7::Event;
  e->flags = flags;
  *event = reinterpret_cast<cudaEvent_t>(e);
  tessera::optix7::Events().Add(*event);
  return cudaSuccess;
}

cudaError_t cudaEventCreate(cudaEvent_t* event) { return cudaEventCreateWithFlags(event, 0); }

cudaError_t cudaEventDestroy(cudaEvent_t event) {
  if (!tessera::optix7::Events().Remove(event)) return Result(cudaErrorInvalidResourceHandle);
  delete reinterpret_cast<tessera::optix7::Event*>(event);
  return cudaSuccess;
}

cudaError_t cudaEventRecord(cudaEvent_t event, cudaStream_t stream) {
  if (!tessera::optix7::Events().Has(event) || !tessera::optix7::ValidStream(stream)) {
    return Result(cudaErrorInvalidResourceHandle);
  }
  auto* e = reinterpret_cast<tessera::optix7::Event*>(event);
  e->recorded = true;
  e->when = std::chrono::steady_clock::now();
  return cudaSuccess;
}

cudaError_t cudaEventSynchronize(cudaEvent_t event) {
  return tessera::optix7::Events().Has(event) ? cudaSuccess
                                              : Result(cudaErrorInvalidResourceHandle);
}

cudaError_t cudaEventQuery(cudaEvent_t event) { return cudaEventSynchronize(event); }

cudaError_t cudaEventElapsedTime(float* ms, cudaEvent_t start, cudaEvent_t end) {
  if (ms == nullptr) return Result(cudaErrorInvalidValue);
  if (!tessera::optix7::Events().Has(start) || !tessera::optix7::Events().Has(end)) {
    return Result(cudaErrorInvalidResourceHandle);
  }
  const auto* a = reinterpret_cast<const tessera::optix7::Event*>(start);
  const auto* b = reinterpret_cast<const tessera::optix7::Event*>(end);
  if (!a->recorded || !b->recorded) return Result(cudaErrorInvalidResourceHandle);
  *ms = std::chrono::duration<float, std::milli>(b->when - a->when).count();
  return cudaSuccess;
}

}  // extern "C"
