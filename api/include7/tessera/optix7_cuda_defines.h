/* The CUDA C language words that OptiX 7 host and program code spells, for a C or C++ compiler
 * that is not nvcc. Tessera runs programs on CPUs: a program module is a shared library that g++
 * builds from the .cu file with -D__CUDACC__, so the execution-space and memory-space qualifiers
 * mean nothing and become empty, in host code and program code alike (nvcc's host pass also reads
 * them as nothing special). `extern "C" __constant__ Params params;` is then an ordinary global
 * that the engine finds by its name, and `extern "C" __global__ void __raygen__rg()` an ordinary
 * exported function.
 *
 * __align__(n) is GCC's aligned attribute, as CUDA's host_defines.h makes it for GCC: the SDK's
 * SBT record template aligns its header with it in host code.
 *
 * This header belongs to the OptiX 7 include root (api/include7) and includes nothing from the
 * OptiX 3 root (api/include); the OptiX 3 layer has its own copy of the qualifiers in
 * tessera/cuda_compat.h. Both define each word only when it is not defined yet, to the same
 * expansion. */
#ifndef TESSERA_OPTIX7_CUDA_DEFINES_H_
#define TESSERA_OPTIX7_CUDA_DEFINES_H_

/* Execution and memory spaces. __forceinline__ is plain `inline`: always_inline turns a recursive
 * or address-taken function into a hard error under g++, which inlines small functions at -O2
 * anyway. */
#ifndef __device__
#define __device__
#endif
#ifndef __host__
#define __host__
#endif
#ifndef __global__
#define __global__
#endif
#ifndef __constant__
#define __constant__
#endif
#ifndef __shared__
#define __shared__
#endif
#ifndef __managed__
#define __managed__
#endif
#ifndef __forceinline__
#define __forceinline__ inline
#endif
// Empty, not __attribute__((noinline)): libstdc++ 12 writes `__attribute__((__noinline__))`
// (<memory>'s shared_ptr_base.h), which that definition turns into an error in every file that
// includes a C++ library header after this one. Empty, it leaves `__attribute__(())` there, and
// a program's `__noinline__` only loses a hint that changes no result.
#ifndef __noinline__
#define __noinline__
#endif
#ifndef __align__
#define __align__(n) __attribute__((aligned(n)))
#endif
#ifndef __device_builtin__
#define __device_builtin__
#endif
#ifndef __builtin_align__
#define __builtin_align__(n) __align__(n)
#endif
#ifndef __cudart_builtin__
#define __cudart_builtin__
#endif
#ifndef CUDARTAPI
#define CUDARTAPI
#endif
#ifndef CUDAAPI
#define CUDAAPI
#endif

/* The CUDA version these headers describe: 12.0, a toolkit OptiX 7.7 supports. Programs and
 * libraries that choose code by CUDA version read these. __CUDA_ARCH__ stays undefined: code
 * under it is GPU-only (inline PTX) and g++ cannot compile it; its #else branch is plain C++. */
#ifndef CUDART_VERSION
#define CUDART_VERSION 12000
#endif
#ifndef CUDA_VERSION
#define CUDA_VERSION 12000
#endif
#if defined(__CUDACC__) && !defined(__CUDACC_VER_MAJOR__)
#define __CUDACC_VER_MAJOR__ 12
#define __CUDACC_VER_MINOR__ 0
#define __CUDACC_VER_BUILD__ 0
#endif

/* Default arguments exist only in C++; the C declarations of the same functions have none. */
#ifdef __cplusplus
#define TESSERA_CUDA_DEFAULT(value) = value
#else
#define TESSERA_CUDA_DEFAULT(value)
#endif

#endif /* TESSERA_OPTIX7_CUDA_DEFINES_H_ */
