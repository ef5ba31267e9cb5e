// The OptiX headers compile as C++20 too: libstdc++ then declares std::lerp in the global
// namespace, which the scalar lerp of optixu_math_namespace.h must not collide with.
#include <optix_world.h>
#include <optixu/optixpp_namespace.h>
#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>
#include <optixu/optixu_matrix_namespace.h>

int main() {
  const float mid = lerp(0.f, 2.f, 0.5f);
  const optix::float3 v = optix::lerp(optix::make_float3(0.f), optix::make_float3(2.f), 0.5f);
  return mid == 1.f && v.x == 1.f ? 0 : 1;
}
