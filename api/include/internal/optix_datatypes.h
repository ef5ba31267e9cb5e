// optix::Ray, the ray that rtTrace takes and rtCurrentRay exposes, and RT_DEFAULT_MAX.
//
// The engine copies rays across the program boundary as raw bytes, so the layout is fixed:
// origin, direction, ray_type, tmin, tmax; 36 bytes, 4-byte aligned, trivially copyable.
#ifndef INTERNAL_OPTIX_DATATYPES_H_
#define INTERNAL_OPTIX_DATATYPES_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "../optixu/optixu_vector_types.h"

// The "infinite" tmax OptiX programs pass for unbounded rays. A large finite value rather than
// infinity, so that origin + tmax * direction stays finite and comparisons behave under
// -ffast-math.
#define RT_DEFAULT_MAX 1.e27f

namespace optix {

struct Ray {
  // Leaves the members uninitialized, like OptiX's, which keeps Ray trivial; `Ray r = {};`
  // zeroes it.
  Ray() = default;
  constexpr Ray(float3 origin_, float3 direction_, unsigned int ray_type_, float tmin_,
                float tmax_ = RT_DEFAULT_MAX)
      : origin(origin_), direction(direction_), ray_type(ray_type_), tmin(tmin_), tmax(tmax_) {}

  float3 origin;
  float3 direction;
  unsigned int ray_type;  // Selects the closest/any hit programs of each material.
  float tmin;             // The ray covers origin + t * direction for t in [tmin, tmax].
  float tmax;
};

constexpr Ray make_Ray(float3 origin, float3 direction, unsigned int ray_type, float tmin,
                       float tmax) {
  return Ray(origin, direction, ray_type, tmin, tmax);
}

}  // namespace optix

#endif  // INTERNAL_OPTIX_DATATYPES_H_
