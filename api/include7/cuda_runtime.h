/* The CUDA runtime header OptiX 7 host code includes: the C API (cuda_runtime_api.h), the vector
 * types and their make_* functions, channel descriptors, and the C++ conveniences of CUDA's
 * cuda_runtime.h (typed cudaMalloc and friends, which forward to the C functions). libtessera
 * exports the functions (api/optix7/cuda_runtime.cc and its siblings; docs/COMPATIBILITY.md). */
#ifndef TESSERA_OPTIX7_CUDA_RUNTIME_H_
#define TESSERA_OPTIX7_CUDA_RUNTIME_H_

#include "channel_descriptor.h"
#include "cuda_runtime_api.h"
#include "driver_functions.h"
#include "tessera/optix7_cuda_defines.h"
#include "vector_functions.h"
#include "vector_types.h"

#ifdef __cplusplus

/* `float* d; cudaMalloc(&d, n)`: CUDA's typed overloads. */
template <class T>
static __inline__ __host__ cudaError_t cudaMalloc(T** devPtr, size_t size) {
  return ::cudaMalloc(reinterpret_cast<void**>(devPtr), size);
}

template <class T>
static __inline__ __host__ cudaError_t cudaMallocManaged(T** devPtr, size_t size,
                                                         unsigned int flags = cudaMemAttachGlobal) {
  return ::cudaMallocManaged(reinterpret_cast<void**>(devPtr), size, flags);
}

template <class T>
static __inline__ __host__ cudaError_t cudaMallocHost(T** ptr, size_t size) {
  return ::cudaMallocHost(reinterpret_cast<void**>(ptr), size);
}

template <class T>
static __inline__ __host__ cudaError_t cudaMallocPitch(T** devPtr, size_t* pitch, size_t width,
                                                       size_t height) {
  return ::cudaMallocPitch(reinterpret_cast<void**>(devPtr), pitch, width, height);
}

template <class T>
static __inline__ __host__ cudaError_t cudaMallocArray(cudaArray_t* array, size_t width,
                                                       size_t height = 0, unsigned int flags = 0) {
  const cudaChannelFormatDesc desc = cudaCreateChannelDesc<T>();
  return ::cudaMallocArray(array, &desc, width, height, flags);
}

#endif /* __cplusplus */

/* Programs: CUDA's cuda_runtime.h brings the device functions (atomics) to a .cu file too. */
#include "device_atomic_functions.h"

#endif /* TESSERA_OPTIX7_CUDA_RUNTIME_H_ */
