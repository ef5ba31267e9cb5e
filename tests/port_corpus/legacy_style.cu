// OptiX 3-era idioms: optix_math.h, an sm_1x stub under __CUDA_ARCH__ (undefined here, as in host
// passes of nvcc), version checks, program helpers under __CUDACC__, RT_HOSTDEVICE,
// __forceinline__, callable programs and the optixu/optixu_math.h name.
#include <optix.h>
#include <optix_math.h>
#include <optixu/optixu_math.h>

#ifndef __CUDACC__
#error "program modules are compiled with __CUDACC__ defined"
#endif
#if !defined(__CUDACC_VER_MAJOR__) || __CUDACC_VER_MAJOR__ < 9
#error "__CUDACC_VER_MAJOR__ says which CUDA the program is compiled as"
#endif
#ifdef __CUDA_ARCH__
#error "__CUDA_ARCH__ would select GPU-only branches"
#endif

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float4, 2> output_buffer;
rtCallableProgram(float3, get_color, (float3, float));

RT_HOSTDEVICE __forceinline__ float3 tint(const float3& c) {
  return c * make_float3(0.9f, 1.f, 1.1f);
}

static __device__ __inline__ float3 checker(float2 uv) {
  const int parity = (int(floorf(uv.x * 8.f)) + int(floorf(uv.y * 8.f))) & 1;
  return parity ? make_float3(1.f) : make_float3(0.1f);
}

RT_CALLABLE_PROGRAM float3 checker_color(float3 p, float scale) {
  return tint(checker(make_float2(p.x, p.y) * scale));
}

RT_PROGRAM void checker_gen() {
  const float3 p = make_float3(make_float2(launch_index) / 64.f, 0.f);
  output_buffer[launch_index] = make_float4(get_color(p, 1.f), 1.f);
}

// Stubs only needed for sm_1x (OptiX 3 SDK samples)
#if __CUDA_ARCH__ < 200
__global__ void checker_color_stub() { (void)checker_color(make_float3(0.f), 1.f); }
#endif
