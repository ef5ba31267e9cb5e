// Programs of tessera-bench-texture: one texture lookup per launch index, against the same texel
// read from a buffer.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtBuffer<float4, 2> output;
rtBuffer<uchar4, 2> texels;
rtTextureSampler<float4, 2, cudaReadModeNormalizedFloat> image;

// Where launch index (x, y) looks, in normalized texture coordinates: off the texel centres, so
// that bilinear filtering blends four texels.
static __device__ __inline__ float2 Coordinate() {
  return make_float2((launch_index.x + 0.3f) / launch_dim.x,
                     (launch_index.y + 0.7f) / launch_dim.y);
}

// A bilinear lookup through the sampler (normalized float read mode, clamp to edge).
RT_PROGRAM void sample_texture() {
  const float2 c = Coordinate();
  output[launch_index] = tex2D(image, c.x, c.y);
}

// The baseline: the nearest texel read from a buffer and converted to float as the sampler's
// normalized float read mode does.
RT_PROGRAM void read_buffer() {
  const float2 c = Coordinate();
  const size_t2 size = texels.size();
  const uint2 i =
      make_uint2(min(static_cast<unsigned>(c.x * size.x), static_cast<unsigned>(size.x - 1)),
                 min(static_cast<unsigned>(c.y * size.y), static_cast<unsigned>(size.y - 1)));
  const uchar4 t = texels[i];
  output[launch_index] = make_float4(t.x, t.y, t.z, t.w) * (1.0f / 255.0f);
}
