// A program that includes only <optix.h> and brings its own small vector helpers, as many
// OptiX 3-era projects did (a cutil_math-style header). OptiX's optix.h gives make_float3 and
// friends but not the optixu vector math, so these definitions must not collide with anything
// optix.h declares. Compiled as a program module with -Wall -Wextra -Werror.
#include <optix.h>

inline float3 operator+(float3 a, float3 b) { return make_float3(a.x + b.x, a.y + b.y, a.z + b.z); }
inline float3 operator-(float3 a, float3 b) { return make_float3(a.x - b.x, a.y - b.y, a.z - b.z); }
inline float3 operator*(float3 a, float s) { return make_float3(a.x * s, a.y * s, a.z * s); }
inline float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 normalize(float3 v) { return v * (1.0f / sqrtf(dot(v, v))); }
inline float lerp(float a, float b, float t) { return a + t * (b - a); }
inline float clamp(float f, float a, float b) { return fmaxf(a, fminf(f, b)); }
inline float luminance(float3 c) { return dot(c, make_float3(0.2126f, 0.7152f, 0.0722f)); }

extern "C" float module_own_helpers(float x, float y, float z) {
  const float3 v = normalize(make_float3(x, y, z) - make_float3(0.0f, 0.0f, 0.0f));
  return clamp(lerp(dot(v, v), luminance(v + v), 0.5f), 0.0f, 10.0f);
}
