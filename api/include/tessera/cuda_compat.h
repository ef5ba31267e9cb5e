// The parts of the CUDA C device language that OptiX 3 programs use, for programs compiled as
// plain C++ by g++: the function and variable qualifiers become no-ops, and the device
// intrinsics (__float_as_int, __saturatef, __popc, atomicAdd, ...) become inline functions with
// the documented CUDA semantics. Everything is in the global namespace, where CUDA puts it.
//
// What a program cannot have (threadIdx and the rest of the CUDA thread model, warp intrinsics,
// surfaces) is declared in tessera/cuda_unsupported.h, so that a use fails with a message saying
// why, rather than silently seeing zeros.
//
// clock() and clock64() are one monotonic nanosecond counter: like CUDA's cycle counters they are
// meant for differences within one launch index. In a program module (__CUDACC__) the prelude
// (tessera/detail/program_prelude.h) puts this clock() in place of the C library's, which is the
// CPU time of the whole process, every thread's work included; in host code clock() stays C's.
//
// Macros: a program module is compiled with -D__CUDACC__, as nvcc defines it, and this header
// then says CUDA 10.1 (__CUDACC_VER_MAJOR__/MINOR/BUILD), the toolkit OptiX 6.5 was built with,
// for programs that choose code by CUDA version. __CUDA_ARCH__ stays undefined: programs and
// CUDA-style headers put inline PTX and other GPU-only code under it, which g++ cannot compile,
// and what they put in its #else (host) branch is plain C++ (`#if __CUDA_ARCH__ < 200` stubs of
// OptiX 3 SDK samples compile too). __NVCC__ stays undefined: it names the nvcc driver, whose
// pragmas and flags g++ does not take.
#ifndef TESSERA_CUDA_COMPAT_H_
#define TESSERA_CUDA_COMPAT_H_

// clang-format off: before every other #include (see there)
#include "tessera/detail/program_prelude.h"
// clang-format on

#if defined(__CUDACC__) && !defined(__CUDACC_VER_MAJOR__)
#define __CUDACC_VER_MAJOR__ 10
#define __CUDACC_VER_MINOR__ 1
#define __CUDACC_VER_BUILD__ 0
#endif

// The C++ <math.h> comes first, for two reasons: it puts the float overloads of sqrt, pow,
// floor, fabs... in the global namespace, which CUDA programs rely on (`pow(x, y)` with floats
// stays float); and glibc's <math.h> declares __expf, __sinf etc. that the definitions below
// must redeclare compatibly. <memory> comes before the __noinline__ macro because libstdc++'s
// shared_ptr spells `__attribute__((__noinline__))`, which the macro would break if that
// header were first read after it.
#include <math.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <limits>
#include <memory>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

// ---- Qualifiers ---------------------------------------------------------------------------------
// Host and device code are the same code here, so the execution-space and memory-space
// qualifiers mean nothing. __inline__ and __restrict__ are GCC keywords already and are left
// alone. __forceinline__ is plain `inline`: always_inline turns a recursive or address-taken
// function into a hard error, and g++ -O2 inlines small functions anyway.
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
#ifndef __noinline__
#define __noinline__ __attribute__((noinline))
#endif
#ifndef __align__
#define __align__(n) __attribute__((aligned(n)))
#endif
#ifndef __launch_bounds__
#define __launch_bounds__(...)
#endif

// ---- Intrinsics
// ---------------------------------------------------------------------------------- Shared with
// the OptiX 7 root (api/include_common).
#include "tessera/detail/cuda_intrinsics.h"

// ---- Atomics ------------------------------------------------------------------------------------
// Shared with the OptiX 7 root (api/include_common). OptiX 3 buffers merge element by element, so
// nothing is noted here: an atomic is atomic within a device, not across devices (docs/devices.md).
#include "tessera/detail/cuda_atomics.h"

// Host code (a .cpp sharing a header with programs) needs no messages, and may see CUDA's own.
#if defined(__CUDACC__)
#include "tessera/cuda_unsupported.h"
#endif

#endif  // TESSERA_CUDA_COMPAT_H_
