// First thing every program-side header includes. In a translation unit compiled as a program
// module (-D__CUDACC__, C++), it reads the C and C++ library headers Tessera's headers need while
// glibc's non-standard global names that CUDA device code does not have are renamed, so that a
// program may declare them itself:
//   rtDeclareVariable(uint2, index, rtLaunchIndex, );   // glibc: char* index(const char*, int)
//   rtDeclareVariable(float, time, , );                  // glibc: time_t time(time_t*)
// glibc declares `index` and `rindex` (<strings.h>, reached through <cstring>), `random`
// (<stdlib.h>, reached through <cmath>), `select` (<sys/select.h>, through <stdlib.h>), `time`
// (<time.h>, through <chrono> and <memory>) and `gamma` (<math.h>) at global scope; each include
// guard then keeps a later #include of those headers, by the program or the library, from declaring
// them again. The library keeps them under tessera_libc_* names. std::time goes too (with
// libstdc++; with another C++ library `time` stays declared): a program has no use for the calendar
// clock, which CUDA device code cannot call either. clock() is replaced the same way (below).
//
// This works when a Tessera header is the program's first #include, as optix.h, optix_world.h or
// optixu/*.h is in OptiX programs; a program that includes <cstring> or <cmath> before them has
// glibc's names declared already (docs/programs.md).
//
// Host code (no __CUDACC__) is left alone: a host .cpp that includes optix.h keeps every libc name.
#ifndef TESSERA_DETAIL_PROGRAM_PRELUDE_H_
#define TESSERA_DETAIL_PROGRAM_PRELUDE_H_

#if defined(__cplusplus) && defined(__CUDACC__) && !defined(TESSERA_KEEP_LIBC_NAMES)
#include <cstddef>  // declares none of the names; tells which C++ library this is (__GLIBCXX__)

#define index tessera_libc_index
#define rindex tessera_libc_rindex
#define random tessera_libc_random
#define select tessera_libc_select
#define gamma tessera_libc_gamma
#if defined(__GLIBCXX__)
#define time tessera_libc_time
#define clock tessera_libc_clock
#endif

// The glibc headers that declare those names.
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/select.h>
#include <sys/types.h>
#include <time.h>

#if defined(__GLIBCXX__)
#undef time
#undef clock
// CUDA's clock() counts a thread's own cycles; the C library's counts the CPU time of the whole
// process, every thread's work included. Programs get a monotonic nanosecond counter instead, the
// one clock64() reads (tessera/cuda_compat.h), so that a difference of two readings in a launch
// index measures that stretch of its program.
inline clock_t clock() noexcept {
  timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<clock_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
}
// libstdc++'s <ctime> undefines any macro named `time` and then re-exports ::time into std, which
// no longer exists: it is stood in for here with every other name it re-exports (the C++17
// list), and its include guard, so that <chrono> and the rest find what they use.
#define _GLIBCXX_CTIME 1
namespace std {
using ::asctime;
using ::clock;
using ::clock_t;
using ::ctime;
using ::difftime;
using ::gmtime;
using ::localtime;
using ::mktime;
using ::strftime;
using ::time_t;
using ::tm;
#if __cplusplus >= 201703L && defined(_GLIBCXX_HAVE_TIMESPEC_GET)
using ::timespec;
using ::timespec_get;
#endif
}  // namespace std
#endif

// Every library header Tessera's program-side headers include, so that none is first read
// after the names come back.
#include <cfloat>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <limits>
#include <memory>
#include <string>
#include <vector>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#undef index
#undef rindex
#undef random
#undef select
#undef gamma
#endif

#endif  // TESSERA_DETAIL_PROGRAM_PRELUDE_H_
