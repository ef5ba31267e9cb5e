// The fast-math tests' programs in a default module whose static constructor turns on FTZ/DAZ
// (as crtfastmath.o's does in modules linked with -ffast-math): loading it must not change the
// loading thread's mode, and its launches, which are not fast-math ones, keep IEEE denormals.
#include <xmmintrin.h>

#include "fast_math_programs.cu"

namespace {
__attribute__((constructor)) void FlushDenormalsOnLoad() { _mm_setcsr(_mm_getcsr() | 0x8040u); }
}  // namespace
