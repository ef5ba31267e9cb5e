// Program code that never says `using namespace optix;`: it reaches the vector math through
// argument-dependent lookup (even from a namespace that declares functions of the same names),
// through optix:: qualification, and mixes in the standard library after the CUDA compatibility
// header, with `using namespace std;` in scope where it calls min/max. Compiled as a program
// module with -Wall -Wextra -Werror; program_module_test.cc checks the numbers.
#include <internal/optix_datatypes.h>
#include <optixu/optixu_math_namespace.h>
#include <optixu/optixu_matrix_namespace.h>
#include <tessera/cuda_compat.h>

// Standard headers after cuda_compat.h: its qualifier macros (__noinline__ in particular) must
// not break them.
#include <algorithm>
#include <memory>
#include <vector>

namespace user {

// Same names as the math functions; they hide the global ones from ordinary lookup in this
// namespace, so the float3 calls below compile only through argument-dependent lookup.
inline float normalize(float x) { return x < 0.0f ? -1.0f : 1.0f; }
inline float dot(float a, float b) { return a * b; }

extern "C" float module_adl(float x, float y, float z) {
  const float3 v = ::make_float3(x, y, z);
  const float3 n = normalize(v);                            // ::normalize, by ADL.
  const float3 sum = n + optix::make_float3(1.0f);          // ::operator+, by ADL.
  return dot(sum, n) + dot(2.0f, 0.5f) + normalize(-3.0f);  // ::dot by ADL, then user's.
}

extern "C" float module_qualified(float x) {
  const optix::float3 a = optix::make_float3(x, 0.0f, 0.0f);
  const optix::float3 b = optix::cross(a, optix::make_float3(0.0f, 1.0f, 0.0f));
  const optix::Matrix3x3 m = optix::Matrix3x3::identity() * 2.0f;
  const optix::float3 c = m * b;
  const optix::Ray ray = optix::make_Ray(a, c, 0u, 0.0f, RT_DEFAULT_MAX);
  return optix::length(ray.direction) + optix::clamp(x, 0.0f, 1.0f) + optix::fmaxf(c);
}

extern "C" int module_std_mix(int a, int b) {
  using namespace std;
  std::vector<int> values = {a, b, 7};
  std::shared_ptr<int> shared = std::make_shared<int>(max(a, b));  // ::max(int, int).
  const int smallest = *std::min_element(values.begin(), values.end());
  return min(*shared, 100) + smallest + static_cast<int>(max(1.5f, 0.5f));
}

}  // namespace user
