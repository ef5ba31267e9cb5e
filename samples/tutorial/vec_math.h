// The few float3 operations the host code needs, kept local so it depends only on the vector
// types (optixu_vector_types.h).
#ifndef TESSERA_SAMPLES_TUTORIAL_VEC_MATH_H_
#define TESSERA_SAMPLES_TUTORIAL_VEC_MATH_H_

#include <optixu/optixu_vector_types.h>

#include <cmath>

namespace tessera::tutorial {

inline float3 Add(const float3& a, const float3& b) {
  return make_float3(a.x + b.x, a.y + b.y, a.z + b.z);
}
inline float3 Sub(const float3& a, const float3& b) {
  return make_float3(a.x - b.x, a.y - b.y, a.z - b.z);
}
inline float3 Scale(const float3& a, float s) { return make_float3(a.x * s, a.y * s, a.z * s); }
inline float Dot(const float3& a, const float3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 Cross(const float3& a, const float3& b) {
  return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
inline float Length(const float3& a) { return std::sqrt(Dot(a, a)); }
inline float3 Normalize(const float3& a) { return Scale(a, 1.0f / Length(a)); }

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_VEC_MATH_H_
