// The OptiX 3 side of the texture probe: a texture described as an OptiX 3 application would
// describe its rtTextureSampler and buffer, sampled with the OptiX 3 layer's sampler. Includes no
// header of either include root, so that main.cc (OptiX 7) and reference.cc (OptiX 3) share it.
#ifndef TESSERA_TESTS_OPTIX7_TEXTURES_REFERENCE_H_
#define TESSERA_TESTS_OPTIX7_TEXTURES_REFERENCE_H_

namespace reference {

enum class Wrap { kRepeat, kClampToEdge, kMirror, kClampToBorder };

struct Level {
  const void* texels;  // packed
  unsigned width, height, depth;
};

// An rtTextureSampler over an rtBuffer, in OptiX 3's terms.
struct Sampler {
  Level levels[16];
  unsigned level_count = 1;
  unsigned buffer_dims = 2;  // rtBufferCreate's 1D, 2D or 3D
  bool layered = false, cubemap = false;
  char kind = 'u';  // the buffer's RTformat family: 'u' unsigned, 's' signed, 'f' float, 'h' half
  unsigned bits = 8, channels = 4;
  Wrap wrap[3] = {Wrap::kRepeat, Wrap::kRepeat, Wrap::kRepeat};
  bool linear = false;  // RT_FILTER_LINEAR for minification and magnification
  char mip = 'n';       // 'n' RT_FILTER_NONE, 'p' nearest, 'l' linear
  bool normalized_read = false;
  bool srgb = false;
  bool normalized_coords = false;
  float max_anisotropy = 1.f, mip_bias = 0.f, mip_min = 0.f, mip_max = 0.f;
};

// A lookup as probe.h spells it (op and result are ProbeOp and ProbeResult).
struct Lookup {
  unsigned op, result;
  float x, y, z, level;
  int layer, comp;
  float ddx[2], ddy[2];
};

// The lookup's result bits, as probe.cu writes them.
void Sample(const Sampler& s, const Lookup& l, unsigned out[4]);

}  // namespace reference

#endif  // TESSERA_TESTS_OPTIX7_TEXTURES_REFERENCE_H_
