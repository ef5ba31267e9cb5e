// The lookups of the texture probe (probe.h), without the OptiX 7 headers: reference.cc, which is
// compiled against the OptiX 3 root, names them too.
#ifndef TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_OPS_H_
#define TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_OPS_H_

// Which texture function a probe calls.
enum ProbeOp : unsigned {
  kTex1D,
  kTex2D,
  kTex2DPointerForm,  // tex2D(&result, t, x, y)
  kTex3D,
  kTex1DLayered,
  kTex2DLayered,
  kTexCubemap,
  kTexCubemapLayered,
  kTex1DLod,
  kTex2DLod,
  kTex3DLod,
  kTex1DFetch,
  kTex2DGather,
  kTex2DGrad,
  kProbeOpCount
};

// The T of tex*<T>: what the program declares the texels to read as.
enum ProbeResult : unsigned {
  kFloat4,
  kFloat1,
  kUchar4,
  kShort2,
  kInt4,
  kUint4,
  kProbeResultCount
};

#endif  // TESSERA_TESTS_OPTIX7_TEXTURES_PROBE_OPS_H_
