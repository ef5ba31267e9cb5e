// What the OptiX 3 layer's sampler returns for a texture probe: the sampler's view filled from
// OptiX 3's enums (RTformat, RTwrapmode, ...), as worker/core/texture_views.cc fills it for an
// rtTextureSampler, never from the CUDA descriptor that the OptiX 7 layer translated.
#include "reference.h"

#include <cstring>

#include "probe_ops.h"
#include "tessera/detail/texture_sampling.h"
#include "tessera/rt.h"

namespace reference {
namespace {

RTformat FormatOf(const Sampler& s) {
  // OptiX 3's formats come in families of four (1, 2, 3, 4 components); CUDA's 4 is the 4th.
  const unsigned c = s.channels - 1;
  switch (s.kind) {
    case 'u':
      return static_cast<RTformat>((s.bits == 8    ? RT_FORMAT_UNSIGNED_BYTE
                                    : s.bits == 16 ? RT_FORMAT_UNSIGNED_SHORT
                                                   : RT_FORMAT_UNSIGNED_INT) +
                                   c);
    case 's':
      return static_cast<RTformat>((s.bits == 8    ? RT_FORMAT_BYTE
                                    : s.bits == 16 ? RT_FORMAT_SHORT
                                                   : RT_FORMAT_INT) +
                                   c);
    case 'h':
      return static_cast<RTformat>(RT_FORMAT_HALF + c);
    default:
      return static_cast<RTformat>(RT_FORMAT_FLOAT + c);
  }
}

RTwrapmode WrapOf(Wrap w) {
  switch (w) {
    case Wrap::kRepeat:
      return RT_WRAP_REPEAT;
    case Wrap::kMirror:
      return RT_WRAP_MIRROR;
    case Wrap::kClampToBorder:
      return RT_WRAP_CLAMP_TO_BORDER;
    default:
      return RT_WRAP_CLAMP_TO_EDGE;
  }
}

TesseraTextureView ViewOf(const Sampler& s) {
  TesseraTextureView v{};
  for (unsigned i = 0; i < s.level_count; ++i) {
    v.levels[i].data = s.levels[i].texels;
    v.levels[i].width = s.levels[i].width;
    v.levels[i].height = s.levels[i].height;
    v.levels[i].depth = s.levels[i].depth;
  }
  v.level_count = s.level_count;
  v.dimensionality = s.buffer_dims;
  v.format = FormatOf(s);
  v.element_size = s.bits / 8 * s.channels;
  v.layered = s.layered;
  v.cubemap = s.cubemap;
  for (int i = 0; i < 3; ++i) v.wrap[i] = WrapOf(s.wrap[i]);
  v.min_filter = v.mag_filter = s.linear ? RT_FILTER_LINEAR : RT_FILTER_NEAREST;
  v.mip_filter = s.mip == 'l'   ? RT_FILTER_LINEAR
                 : s.mip == 'p' ? RT_FILTER_NEAREST
                                : RT_FILTER_NONE;
  v.read_mode =
      s.normalized_read
          ? (s.srgb ? RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB : RT_TEXTURE_READ_NORMALIZED_FLOAT)
          : (s.srgb ? RT_TEXTURE_READ_ELEMENT_TYPE_SRGB : RT_TEXTURE_READ_ELEMENT_TYPE);
  v.index_mode =
      s.normalized_coords ? RT_TEXTURE_INDEX_NORMALIZED_COORDINATES : RT_TEXTURE_INDEX_ARRAY_INDEX;
  v.max_anisotropy = s.max_anisotropy;
  v.mip_level_bias = s.mip_bias;
  v.mip_level_clamp[0] = s.mip_min;
  v.mip_level_clamp[1] = s.mip_max;
  // The OptiX 3 engine's own choice of lookup path (texture_views.cc).
  v.fast = tessera::texture::FastKind(v);
  return v;
}

template <typename T>
T Run(const TesseraTextureView& v, const Lookup& l) {
  namespace tx = tessera::texture;
  switch (l.op) {
    case kTex1D:
      return tx::Sample1D<T>(v, l.x);
    case kTex2D:
    case kTex2DPointerForm:
      return tx::Sample2D<T>(v, l.x, l.y);
    case kTex3D:
      return tx::Sample3D<T>(v, l.x, l.y, l.z);
    case kTex1DLayered:
      return tx::Sample1DLayered<T>(v, l.x, l.layer);
    case kTex2DLayered:
      return tx::Sample2DLayered<T>(v, l.x, l.y, l.layer);
    case kTexCubemap:
      return tx::SampleCubemap<T>(v, l.x, l.y, l.z);
    case kTexCubemapLayered:
      return tx::SampleCubemapLayered<T>(v, l.x, l.y, l.z, l.layer);
    case kTex1DLod:
      return tx::Sample1DLod<T>(v, l.x, l.level);
    case kTex2DLod:
      return tx::Sample2DLod<T>(v, l.x, l.y, l.level);
    case kTex3DLod:
      return tx::Sample3DLod<T>(v, l.x, l.y, l.z, l.level);
    case kTex1DFetch:
      return tx::Fetch1D<T>(v, static_cast<int>(l.x));
    case kTex2DGrad:
      return tx::Sample2DGrad<T>(v, l.x, l.y, make_float2(l.ddx[0], l.ddx[1]),
                                 make_float2(l.ddy[0], l.ddy[1]));
    default:
      return T{};
  }
}

unsigned Bits(float f) {
  unsigned u;
  std::memcpy(&u, &f, 4);
  return u;
}
unsigned Bits(int i) { return static_cast<unsigned>(i); }
unsigned Bits(unsigned u) { return u; }

template <typename V>
void Put4(const V& v, unsigned out[4]) {
  out[0] = Bits(v.x);
  out[1] = Bits(v.y);
  out[2] = Bits(v.z);
  out[3] = Bits(v.w);
}

}  // namespace

void Sample(const Sampler& s, const Lookup& l, unsigned out[4]) {
  const TesseraTextureView v = ViewOf(s);
  out[0] = out[1] = out[2] = out[3] = 0;
  if (l.op == kTex2DGather) {
    if (l.result == kFloat4) {
      Put4(tessera::texture::Gather2D<float4>(v, l.x, l.y, l.comp), out);
    } else {
      Put4(tessera::texture::Gather2D<int4>(v, l.x, l.y, l.comp), out);
    }
    return;
  }
  switch (l.result) {
    case kFloat4:
      Put4(Run<float4>(v, l), out);
      break;
    case kFloat1:
      out[0] = Bits(Run<float>(v, l));
      break;
    case kUchar4: {
      const uchar4 c = Run<uchar4>(v, l);
      out[0] = c.x;
      out[1] = c.y;
      out[2] = c.z;
      out[3] = c.w;
      break;
    }
    case kShort2: {
      const short2 c = Run<short2>(v, l);
      out[0] = Bits(int(c.x));
      out[1] = Bits(int(c.y));
      break;
    }
    case kInt4:
      Put4(Run<int4>(v, l), out);
      break;
    case kUint4:
      Put4(Run<uint4>(v, l), out);
      break;
    default:
      break;
  }
}

}  // namespace reference
