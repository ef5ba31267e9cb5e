// The parts of CUDA C that an OptiX program can name but Tessera cannot give it, declared so that
// a use stops the compile with a message naming the feature and the reason, instead of
// "'threadIdx' was not declared in this scope". Every check is a static_assert in a template that
// only a use instantiates: declaring or never touching these costs nothing.
//
//   threadIdx, blockIdx, blockDim, gridDim, warpSize: a launch index is not a CUDA thread (the
//     OptiX guide tells programs to use rtLaunchIndex and rtLaunchDim), and there is no warp;
//     reading one as a number, or doing arithmetic or comparisons with it, fails.
//   Warp intrinsics (__shfl*, __ballot*, __any*, __all*, __activemask, __syncwarp, __match_*,
//     __reduce_*): launch indices run one at a time on a CPU thread, with no lanes to exchange
//     values with.
//   Surface writes and reads (surf1D*, surf2D*, surf3D*): OptiX 3-6 programs write buffers.
#ifndef TESSERA_CUDA_UNSUPPORTED_H_
#define TESSERA_CUDA_UNSUPPORTED_H_

namespace tessera_cuda_unsupported {

template <typename... T>
inline constexpr bool kNever = sizeof...(T) < 0;  // false, but only once a use names T

#define TESSERA_NOT_A_THREAD_                                                                  \
  "threadIdx, blockIdx, blockDim, gridDim and warpSize: a Tessera launch index is not a CUDA " \
  "thread and has no warp; use rtDeclareVariable(uint2, launch_index, rtLaunchIndex, ) and "   \
  "rtLaunchDim (docs/COMPATIBILITY.md)"

// One component (threadIdx.x) or warpSize. A template, so that nothing is checked until a use.
template <int Which>
struct NotAThread {
  template <typename T>
  operator T() const {  // NOLINT(google-explicit-constructor): the use that must fail
    static_assert(kNever<T>, TESSERA_NOT_A_THREAD_);
    return T();
  }
};
template <int Which>
struct NotAThread3 {
  NotAThread<Which> x, y, z;
};

// Arithmetic and comparisons with a component fail with the same message (the conversion alone
// would leave the compiler choosing among built-in operators, and saying only that it cannot).
#define TESSERA_NOT_A_THREAD_OPERATOR_(op)                                      \
  template <int W, typename U>                                                  \
  int operator op(NotAThread<W>, const U&) {                                    \
    static_assert(kNever<U>, TESSERA_NOT_A_THREAD_);                            \
    return 0;                                                                   \
  }                                                                             \
  template <int W, typename U>                                                  \
  int operator op(const U&, NotAThread<W>) {                                    \
    static_assert(kNever<U>, TESSERA_NOT_A_THREAD_);                            \
    return 0;                                                                   \
  }                                                                             \
  template <int W, int V>                                                       \
  int operator op(NotAThread<W>, NotAThread<V>) {                               \
    static_assert(kNever<NotAThread<W>, NotAThread<V>>, TESSERA_NOT_A_THREAD_); \
    return 0;                                                                   \
  }
TESSERA_NOT_A_THREAD_OPERATOR_(+)
TESSERA_NOT_A_THREAD_OPERATOR_(-)
TESSERA_NOT_A_THREAD_OPERATOR_(*)
TESSERA_NOT_A_THREAD_OPERATOR_(/)
TESSERA_NOT_A_THREAD_OPERATOR_(%)
TESSERA_NOT_A_THREAD_OPERATOR_(&)
TESSERA_NOT_A_THREAD_OPERATOR_(|)
TESSERA_NOT_A_THREAD_OPERATOR_(^)
TESSERA_NOT_A_THREAD_OPERATOR_(<<)
TESSERA_NOT_A_THREAD_OPERATOR_(>>)
TESSERA_NOT_A_THREAD_OPERATOR_(<)
TESSERA_NOT_A_THREAD_OPERATOR_(>)
TESSERA_NOT_A_THREAD_OPERATOR_(<=)
TESSERA_NOT_A_THREAD_OPERATOR_(>=)
TESSERA_NOT_A_THREAD_OPERATOR_(==)
TESSERA_NOT_A_THREAD_OPERATOR_(!=)
#undef TESSERA_NOT_A_THREAD_OPERATOR_

}  // namespace tessera_cuda_unsupported

inline constexpr tessera_cuda_unsupported::NotAThread3<0> threadIdx{};
inline constexpr tessera_cuda_unsupported::NotAThread3<1> blockIdx{};
inline constexpr tessera_cuda_unsupported::NotAThread3<2> blockDim{};
inline constexpr tessera_cuda_unsupported::NotAThread3<3> gridDim{};
inline constexpr tessera_cuda_unsupported::NotAThread<4> warpSize{};
#undef TESSERA_NOT_A_THREAD_

// Functions: templates over their arguments, so a call instantiates the message and a program
// that never calls them compiles.
#define TESSERA_CUDA_UNSUPPORTED_(name, reason)                  \
  template <typename... A>                                       \
  inline int name(A...) {                                        \
    static_assert(::tessera_cuda_unsupported::kNever<A...>,      \
                  #name ": " reason " (docs/COMPATIBILITY.md)"); \
    return 0;                                                    \
  }
#define TESSERA_NO_WARP_ \
  "Tessera runs one launch index at a time per CPU thread: there is no warp to exchange values in"
TESSERA_CUDA_UNSUPPORTED_(__shfl, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_up, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_down, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_xor, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_up_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_down_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__shfl_xor_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__ballot, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__ballot_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__any, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__all, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__any_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__all_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__uni_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__activemask, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__syncwarp, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__match_any_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__match_all_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_add_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_min_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_max_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_and_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_or_sync, TESSERA_NO_WARP_)
TESSERA_CUDA_UNSUPPORTED_(__reduce_xor_sync, TESSERA_NO_WARP_)
#undef TESSERA_NO_WARP_
#define TESSERA_NO_SURFACES_ \
  "Tessera has no CUDA surfaces; OptiX programs write output through rtBuffer"
TESSERA_CUDA_UNSUPPORTED_(surf1Dread, TESSERA_NO_SURFACES_)
TESSERA_CUDA_UNSUPPORTED_(surf1Dwrite, TESSERA_NO_SURFACES_)
TESSERA_CUDA_UNSUPPORTED_(surf2Dread, TESSERA_NO_SURFACES_)
TESSERA_CUDA_UNSUPPORTED_(surf2Dwrite, TESSERA_NO_SURFACES_)
TESSERA_CUDA_UNSUPPORTED_(surf3Dread, TESSERA_NO_SURFACES_)
TESSERA_CUDA_UNSUPPORTED_(surf3Dwrite, TESSERA_NO_SURFACES_)
#undef TESSERA_NO_SURFACES_
#undef TESSERA_CUDA_UNSUPPORTED_

#endif  // TESSERA_CUDA_UNSUPPORTED_H_
