// Standard stream operators for the float, int and uint vector types, optix::Aabb and
// optix::Matrix, as OptiX 3's optixu_math_stream_namespace.h offers them (the guide lists the
// header). Vectors print as "[x, y, z]", a box as "[min] | [max]", a matrix as its rows, each in
// brackets, inside brackets; operator>> reads the same text back (any single separator character
// between numbers).
#ifndef OPTIXU_OPTIXU_MATH_STREAM_NAMESPACE_H_
#define OPTIXU_OPTIXU_MATH_STREAM_NAMESPACE_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include <istream>
#include <ostream>

#include "optixu_aabb_namespace.h"
#include "optixu_math_namespace.h"
#include "optixu_matrix_namespace.h"

namespace optixu_detail {
template <typename T>
inline void WriteComponents(std::ostream& os, const T* c, unsigned int n) {
  os << '[';
  for (unsigned int i = 0; i < n; ++i) os << (i == 0 ? "" : ", ") << c[i];
  os << ']';
}
template <typename T>
inline void ReadComponents(std::istream& is, T* c, unsigned int n) {
  char separator;
  is >> separator;                                               // '['
  for (unsigned int i = 0; i < n; ++i) is >> c[i] >> separator;  // ',' or ']'
}
}  // namespace optixu_detail

// Global, beside the types and their arithmetic, so that argument-dependent lookup finds them;
// re-exported into namespace optix below.
#define OPTIXU_STREAM_(V, S, N)                                                   \
  inline std::ostream& operator<<(std::ostream& os, const V& v) {                 \
    const S c[4] = {getByIndex(v, 0), getByIndex(v, 1 % N), getByIndex(v, 2 % N), \
                    getByIndex(v, 3 % N)};                                        \
    optixu_detail::WriteComponents(os, c, N);                                     \
    return os;                                                                    \
  }                                                                               \
  inline std::istream& operator>>(std::istream& is, V& v) {                       \
    S c[4] = {};                                                                  \
    optixu_detail::ReadComponents(is, c, N);                                      \
    for (int i = 0; i < N; ++i) setByIndex(v, i, c[i]);                           \
    return is;                                                                    \
  }
OPTIXU_STREAM_(float2, float, 2)
OPTIXU_STREAM_(float3, float, 3)
OPTIXU_STREAM_(float4, float, 4)
OPTIXU_STREAM_(int2, int, 2)
OPTIXU_STREAM_(int3, int, 3)
OPTIXU_STREAM_(int4, int, 4)
OPTIXU_STREAM_(uint2, unsigned int, 2)
OPTIXU_STREAM_(uint3, unsigned int, 3)
OPTIXU_STREAM_(uint4, unsigned int, 4)
#undef OPTIXU_STREAM_

namespace optix {
using ::operator<<;
using ::operator>>;

inline std::ostream& operator<<(std::ostream& os, const Aabb& box) {
  return os << box.m_min << " | " << box.m_max;
}

template <unsigned int M, unsigned int N>
std::ostream& operator<<(std::ostream& os, const Matrix<M, N>& m) {
  os << '[';
  for (unsigned int row = 0; row < M; ++row) {
    optixu_detail::WriteComponents(os, m.getData() + row * N, N);
  }
  return os << ']';
}
template <unsigned int M, unsigned int N>
std::istream& operator>>(std::istream& is, Matrix<M, N>& m) {
  char bracket;
  is >> bracket;
  for (unsigned int row = 0; row < M; ++row) {
    optixu_detail::ReadComponents(is, m.getData() + row * N, N);
  }
  return is >> bracket;
}
}  // namespace optix

#endif  // OPTIXU_OPTIXU_MATH_STREAM_NAMESPACE_H_
