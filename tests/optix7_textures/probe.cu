// The texture probe's program: lookup number i of the probe list, with the function and result
// type it names, its bits into out[i].
#include <optix.h>

#include "probe.h"

extern "C" {
__constant__ Params params;
}

template <class T>
static __device__ T Lookup(const Probe& p) {
  const cudaTextureObject_t t = p.texture;
  switch (p.op) {
    case kTex1D:
      return tex1D<T>(t, p.x);
    case kTex2D:
      return tex2D<T>(t, p.x, p.y);
    case kTex2DPointerForm: {
      T r;
      tex2D(&r, t, p.x, p.y);
      return r;
    }
    case kTex3D:
      return tex3D<T>(t, p.x, p.y, p.z);
    case kTex1DLayered:
      return tex1DLayered<T>(t, p.x, p.layer);
    case kTex2DLayered:
      return tex2DLayered<T>(t, p.x, p.y, p.layer);
    case kTexCubemap:
      return texCubemap<T>(t, p.x, p.y, p.z);
    case kTexCubemapLayered:
      return texCubemapLayered<T>(t, p.x, p.y, p.z, p.layer);
    case kTex1DLod:
      return tex1DLod<T>(t, p.x, p.level);
    case kTex2DLod:
      return tex2DLod<T>(t, p.x, p.y, p.level);
    case kTex3DLod:
      return tex3DLod<T>(t, p.x, p.y, p.z, p.level);
    case kTex1DFetch:
      return tex1Dfetch<T>(t, static_cast<int>(p.x));
    case kTex2DGrad:
      return tex2DGrad<T>(t, p.x, p.y, p.ddx, p.ddy);
    default:
      return T{};
  }
}

static __device__ unsigned Bits(float f) { return __float_as_uint(f); }
static __device__ unsigned Bits(int i) { return static_cast<unsigned>(i); }

extern "C" __global__ void __raygen__probe() {
  const unsigned i = optixGetLaunchIndex().x;
  if (i >= params.count) return;
  const Probe p = params.probes[i];
  uint4 out = make_uint4(0, 0, 0, 0);
  if (p.op == kTex2DGather) {  // four components whatever the texels
    if (p.result == kFloat4) {
      const float4 v = tex2Dgather<float4>(p.texture, p.x, p.y, p.comp);
      out = make_uint4(Bits(v.x), Bits(v.y), Bits(v.z), Bits(v.w));
    } else {
      const int4 v = tex2Dgather<int4>(p.texture, p.x, p.y, p.comp);
      out = make_uint4(Bits(v.x), Bits(v.y), Bits(v.z), Bits(v.w));
    }
  } else {
    switch (p.result) {
      case kFloat4: {
        const float4 v = Lookup<float4>(p);
        out = make_uint4(Bits(v.x), Bits(v.y), Bits(v.z), Bits(v.w));
        break;
      }
      case kFloat1:
        out.x = Bits(Lookup<float>(p));
        break;
      case kUchar4: {
        const uchar4 v = Lookup<uchar4>(p);
        out = make_uint4(v.x, v.y, v.z, v.w);
        break;
      }
      case kShort2: {
        const short2 v = Lookup<short2>(p);
        out = make_uint4(Bits(int(v.x)), Bits(int(v.y)), 0, 0);
        break;
      }
      case kInt4: {
        const int4 v = Lookup<int4>(p);
        out = make_uint4(Bits(v.x), Bits(v.y), Bits(v.z), Bits(v.w));
        break;
      }
      case kUint4:
        out = Lookup<uint4>(p);
        break;
      default:
        break;
    }
  }
  params.out[i] = out;
}
