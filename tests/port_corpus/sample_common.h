// A header shared by the corpus programs and by host code (port_corpus_test.cc), in the style of
// the OptiX SDK's sutil helpers and the PerRayData headers of community path tracers: types both
// sides use, program-only helpers under #ifdef __CUDACC__, and host-only ones in its #else.
#pragma once

#include <optixu/optixu_math_namespace.h>

struct PerRayData_radiance {
  optix::float3 result;
  float importance;
  int depth;
};

struct PerRayData_shadow {
  optix::float3 attenuation;
};

// Where the shared layout is checked on both sides: programs and host agree on these bytes.
static_assert(sizeof(PerRayData_radiance) == 20, "payload layout shared with the host");

// TEA, as sutil's random.h spells it: a hash the host and programs both call.
template <unsigned int N>
static __host__ __device__ __inline__ unsigned int tea(unsigned int val0, unsigned int val1) {
  unsigned int v0 = val0, v1 = val1, s0 = 0;
  for (unsigned int n = 0; n < N; n++) {
    s0 += 0x9e3779b9;
    v0 += ((v1 << 4) + 0xa341316c) ^ (v1 + s0) ^ ((v1 >> 5) + 0xc8013ea4);
    v1 += ((v0 << 4) + 0xad90777d) ^ (v0 + s0) ^ ((v0 >> 5) + 0x7e95761e);
  }
  return v0;
}

// A number in [0, 1) from a linear congruential step (sutil's rnd()).
static __host__ __device__ __inline__ float rnd(unsigned int& prev) {
  prev = 1664525u * prev + 1013904223u;
  return float(prev & 0x00FFFFFF) / float(0x01000000);
}

#ifdef __CUDACC__
// Program-side helpers, as sutil's helpers.h has them: only .cu files compile these.
static __device__ __inline__ optix::uchar4 make_color(const optix::float3& c) {
  return optix::make_uchar4(static_cast<unsigned char>(__saturatef(c.z) * 255.99f),  // B
                            static_cast<unsigned char>(__saturatef(c.y) * 255.99f),  // G
                            static_cast<unsigned char>(__saturatef(c.x) * 255.99f),  // R
                            255u);
}
static __device__ __inline__ bool in_program_module() { return true; }
#else
// Host-only code in the same header: what a host .cpp reads back from programs.
#include <cstdint>
inline optix::float3 color_from_bgra8(std::uint32_t bgra) {
  return optix::make_float3(((bgra >> 16) & 0xFF) / 255.f, ((bgra >> 8) & 0xFF) / 255.f,
                            (bgra & 0xFF) / 255.f);
}
inline bool in_program_module() { return false; }
#endif
