// Programs that read textures through a declared sampler (`tex`, bound by the context variable of
// that name) and through a bindless id (`tex_id`), at texel centres of the launch grid shifted by
// `offset` texels, at mip level `lod`.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(int, tex_id, , );
rtDeclareVariable(int, bytes_id, , );
rtDeclareVariable(float, lod, , );
rtDeclareVariable(float2, offset, , );
rtTextureSampler<float4, 2> tex;
rtTextureSampler<float4, 2> unbound_tex;  // no scope names it
rtTextureSampler<uchar4, 2, cudaReadModeNormalizedFloat> bytes_tex;
rtTextureSampler<float4, cudaTextureTypeCubemap> cube_tex;
rtTextureSampler<float4, cudaTextureType2DLayered> layers_tex;
rtBuffer<float4, 2> declared_out;
rtBuffer<float4, 2> bindless_out;

namespace {
float2 Coordinates() {
  return make_float2((launch_index.x + 0.5f + offset.x) / launch_dim.x,
                     (launch_index.y + 0.5f + offset.y) / launch_dim.y);
}
}  // namespace

RT_PROGRAM void sample_both() {
  const float2 c = Coordinates();
  declared_out[launch_index] = tex2DLod(tex, c.x, c.y, lod);
  bindless_out[launch_index] = rtTex2DLod<float4>(tex_id, c.x, c.y, lod);
}

RT_PROGRAM void sample_plain() {
  const float2 c = Coordinates();
  declared_out[launch_index] = tex2D(tex, c.x, c.y);
  float4 by_pointer;
  rtTex2D(&by_pointer, tex_id, c.x, c.y);
  bindless_out[launch_index] = by_pointer;
}

RT_PROGRAM void sample_unbound() {
  const float2 c = Coordinates();
  declared_out[launch_index] = tex2D(unbound_tex, c.x, c.y);
  const uint3 size = rtTexSize(tex_id);
  bindless_out[launch_index] = make_float4(size.x, size.y, size.z, 0.f);
}

RT_PROGRAM void sample_bytes() {
  const float2 c = Coordinates();
  declared_out[launch_index] = tex2D(bytes_tex, c.x, c.y);
}

// bytes_tex declared and by id (bytes_id): an RGBA8 image as a program reads its colours.
RT_PROGRAM void sample_bytes_both() {
  const float2 c = Coordinates();
  declared_out[launch_index] = tex2D(bytes_tex, c.x, c.y);
  bindless_out[launch_index] = rtTex2D<float4>(bytes_id, c.x, c.y);
}

RT_PROGRAM void record_exception() {
  declared_out[launch_index] = make_float4(static_cast<float>(rtGetExceptionCode()), 0.f, 0.f, 0.f);
}

// Launch index i = x + width * y looks along the axis of cube face i % 6 (+x, -x, +y, -y, +z, -z)
// into declared_out, and reads the centre of layer i % 3 into bindless_out.
RT_PROGRAM void sample_cube_and_layers() {
  const unsigned i = launch_index.x + launch_dim.x * launch_index.y;
  const float axes[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const float* a = axes[i % 6];
  declared_out[launch_index] = texCubemap(cube_tex, a[0], a[1], a[2]);
  bindless_out[launch_index] = tex2DLayered(layers_tex, 0.5f, 0.5f, static_cast<int>(i % 3));
}
