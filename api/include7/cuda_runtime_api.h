/* The CUDA runtime functions OptiX 7 applications call, as cuda_runtime_api.h of the CUDA toolkit
 * declares them (C linkage, CUDA 12 signatures). Tessera implements them over its device memory
 * (docs/optix7.md): one address range that the host and every worker map at the same virtual
 * address, so that pointers in launch parameters and SBT records mean the same everywhere.
 *
 * libtessera exports every function declared here (api/optix7/cuda_*.cc).
 *
 * Thread-safety: as CUDA's; the current device is per host thread. */
#ifndef TESSERA_OPTIX7_CUDA_RUNTIME_API_H_
#define TESSERA_OPTIX7_CUDA_RUNTIME_API_H_

#include <stddef.h>

#include "driver_types.h"
#include "tessera/optix7_cuda_defines.h"
#include "texture_types.h"
#include "vector_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Errors ---------------------------------------------------------------------------------- */
/* The last error of the calling thread; cudaGetLastError also resets it to cudaSuccess. */
cudaError_t cudaGetLastError(void);
cudaError_t cudaPeekAtLastError(void);
/* Static strings: "invalid argument", "cudaErrorInvalidValue". */
const char* cudaGetErrorString(cudaError_t error);
const char* cudaGetErrorName(cudaError_t error);

/* ---- Devices --------------------------------------------------------------------------------- */
/* One device whose launches are tiled over every Tessera device of TESSERA_DEVICES, or with
 * TESSERA_CUDA_DEVICES=each one device per Tessera device (docs/optix7.md, "Devices"). The current
 * device is per host thread (0 until cudaSetDevice); an OptixDeviceContext belongs to the device
 * current when it was created. */
cudaError_t cudaGetDeviceCount(int* count);
cudaError_t cudaSetDevice(int device);
cudaError_t cudaGetDevice(int* device);
cudaError_t cudaGetDeviceProperties(struct cudaDeviceProp* prop, int device);
/* Devices share one address range: any device may reach another's memory (canAccessPeer is 1 for
 * two different devices). Enabling access makes the current device's launches ship the peer's
 * allocations too; without it they ship only the device's own (CUDA forbids the access then). */
cudaError_t cudaDeviceCanAccessPeer(int* canAccessPeer, int device, int peerDevice);
cudaError_t cudaDeviceEnablePeerAccess(int peerDevice, unsigned int flags);
cudaError_t cudaDeviceDisablePeerAccess(int peerDevice);
/* Waits for every stream of the current device. */
cudaError_t cudaDeviceSynchronize(void);
cudaError_t cudaDeviceReset(void);
cudaError_t cudaDriverGetVersion(int* driverVersion);
cudaError_t cudaRuntimeGetVersion(int* runtimeVersion);
cudaError_t cudaMemGetInfo(size_t* free, size_t* total);

/* ---- Memory ---------------------------------------------------------------------------------- */
/* cudaFree(0) is the customary way to create the primary context; it returns cudaSuccess. */
cudaError_t cudaMalloc(void** devPtr, size_t size);
cudaError_t cudaMallocManaged(void** devPtr, size_t size,
                              unsigned int flags TESSERA_CUDA_DEFAULT(cudaMemAttachGlobal));
cudaError_t cudaMallocHost(void** ptr, size_t size);
cudaError_t cudaMallocPitch(void** devPtr, size_t* pitch, size_t width, size_t height);
cudaError_t cudaFree(void* devPtr);
cudaError_t cudaFreeHost(void* ptr);
cudaError_t cudaMemcpy(void* dst, const void* src, size_t count, enum cudaMemcpyKind kind);
cudaError_t cudaMemcpyAsync(void* dst, const void* src, size_t count, enum cudaMemcpyKind kind,
                            cudaStream_t stream TESSERA_CUDA_DEFAULT(0));
cudaError_t cudaMemcpy2D(void* dst, size_t dpitch, const void* src, size_t spitch, size_t width,
                         size_t height, enum cudaMemcpyKind kind);
/* Between two devices' allocations: Tessera's devices share one address range, so this is a copy
 * within it (device ordinals are checked: cudaErrorInvalidDevice). */
cudaError_t cudaMemcpyPeer(void* dst, int dstDevice, const void* src, int srcDevice, size_t count);
cudaError_t cudaMemcpyPeerAsync(void* dst, int dstDevice, const void* src, int srcDevice,
                                size_t count, cudaStream_t stream TESSERA_CUDA_DEFAULT(0));
cudaError_t cudaMemset(void* devPtr, int value, size_t count);
cudaError_t cudaMemsetAsync(void* devPtr, int value, size_t count,
                            cudaStream_t stream TESSERA_CUDA_DEFAULT(0));

/* ---- Arrays ---------------------------------------------------------------------------------- */
/* Texel storage for textures: device allocations whose handles are their addresses; texels are
 * packed, x fastest, then y, then z (layer, or cube face +x -x +y -y +z -z, 6 per layer). Sizes,
 * formats and flags are checked as CUDA checks them (docs/optix7.md, "Textures"). */
cudaError_t cudaMallocArray(cudaArray_t* array, const struct cudaChannelFormatDesc* desc,
                            size_t width, size_t height TESSERA_CUDA_DEFAULT(0),
                            unsigned int flags TESSERA_CUDA_DEFAULT(0));
cudaError_t cudaMalloc3DArray(cudaArray_t* array, const struct cudaChannelFormatDesc* desc,
                              struct cudaExtent extent, unsigned int flags TESSERA_CUDA_DEFAULT(0));
/* Levels one after another in one allocation; at most 16 (a 32768-texel side has 16). */
cudaError_t cudaMallocMipmappedArray(cudaMipmappedArray_t* mipmappedArray,
                                     const struct cudaChannelFormatDesc* desc,
                                     struct cudaExtent extent, unsigned int numLevels,
                                     unsigned int flags TESSERA_CUDA_DEFAULT(0));
cudaError_t cudaGetMipmappedArrayLevel(cudaArray_t* levelArray,
                                       cudaMipmappedArray_const_t mipmappedArray,
                                       unsigned int level);
/* An array a texture object still reads keeps its memory until that object is destroyed. */
cudaError_t cudaFreeArray(cudaArray_t array);
cudaError_t cudaFreeMipmappedArray(cudaMipmappedArray_t mipmappedArray);
cudaError_t cudaArrayGetInfo(struct cudaChannelFormatDesc* desc, struct cudaExtent* extent,
                             unsigned int* flags, cudaArray_t array);
cudaError_t cudaGetChannelDesc(struct cudaChannelFormatDesc* desc, cudaArray_const_t array);
/* Copies mark what they write in device memory, which the next launch ships. */
cudaError_t cudaMemcpy2DToArray(cudaArray_t dst, size_t wOffset, size_t hOffset, const void* src,
                                size_t spitch, size_t width, size_t height,
                                enum cudaMemcpyKind kind);
cudaError_t cudaMemcpy2DFromArray(void* dst, size_t dpitch, cudaArray_const_t src, size_t wOffset,
                                  size_t hOffset, size_t width, size_t height,
                                  enum cudaMemcpyKind kind);
/* Deprecated in CUDA but still in OptiX 7 samples. */
cudaError_t cudaMemcpyToArray(cudaArray_t dst, size_t wOffset, size_t hOffset, const void* src,
                              size_t count, enum cudaMemcpyKind kind);
cudaError_t cudaMemcpy3D(const struct cudaMemcpy3DParms* p);
struct cudaChannelFormatDesc cudaCreateChannelDesc(int x, int y, int z, int w,
                                                   enum cudaChannelFormatKind f);

/* ---- Texture objects ------------------------------------------------------------------------- */
/* A texture object is a descriptor in device memory (tessera/optix7_texture_abi.h) that programs
 * sample with texture_indirect_functions.h; pResViewDesc must be null (cudaErrorNotSupported). */
cudaError_t cudaCreateTextureObject(cudaTextureObject_t* pTexObject,
                                    const struct cudaResourceDesc* pResDesc,
                                    const struct cudaTextureDesc* pTexDesc,
                                    const struct cudaResourceViewDesc* pResViewDesc);
cudaError_t cudaDestroyTextureObject(cudaTextureObject_t texObject);

/* ---- Streams --------------------------------------------------------------------------------- */
/* Stream 0 (and cudaStreamLegacy) is the device's default stream. */
cudaError_t cudaStreamCreate(cudaStream_t* pStream);
cudaError_t cudaStreamCreateWithFlags(cudaStream_t* pStream, unsigned int flags);
cudaError_t cudaStreamDestroy(cudaStream_t stream);
cudaError_t cudaStreamSynchronize(cudaStream_t stream);
/* cudaSuccess when the stream's work is done, cudaErrorNotReady while it runs. */
cudaError_t cudaStreamQuery(cudaStream_t stream);
cudaError_t cudaStreamWaitEvent(cudaStream_t stream, cudaEvent_t event,
                                unsigned int flags TESSERA_CUDA_DEFAULT(0));

/* ---- Events ---------------------------------------------------------------------------------- */
cudaError_t cudaEventCreate(cudaEvent_t* event);
cudaError_t cudaEventCreateWithFlags(cudaEvent_t* event, unsigned int flags);
cudaError_t cudaEventDestroy(cudaEvent_t event);
cudaError_t cudaEventRecord(cudaEvent_t event, cudaStream_t stream TESSERA_CUDA_DEFAULT(0));
cudaError_t cudaEventSynchronize(cudaEvent_t event);
cudaError_t cudaEventQuery(cudaEvent_t event);
/* Milliseconds between two recorded events. */
cudaError_t cudaEventElapsedTime(float* ms, cudaEvent_t start, cudaEvent_t end);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_CUDA_RUNTIME_API_H_ */
