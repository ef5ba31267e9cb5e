// cudaCreateTextureObject and cudaDestroyTextureObject (docs/optix7.md, "Textures"): a texture
// object is a TesseraCudaTextureObject (tessera/optix7_texture_abi.h) in device memory, the OptiX 3
// sampler's view of the texels with CUDA's modes translated, and its cudaTextureObject_t is its
// address. Nothing else is needed on devices: the descriptor and the texels travel as device
// memory does, and programs sample through the view (texture_indirect_functions.h).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "cuda_arrays.h"
#include "cuda_devices.h"
#include "host_device_memory.h"
#include "tessera/detail/texture_fast_float.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/optix7_texture_abi.h"

namespace tessera::optix7 {
namespace {

namespace tx = tessera::texture;

// cudaDeviceProp::textureAlignment and texturePitchAlignment (cuda_runtime.cc reports them):
// where linear and pitched texture memory may start, and what its pitch is a multiple of.
constexpr uintptr_t kTextureAlignment = memory::DeviceAllocator::kAlignment;
constexpr size_t kTexturePitchAlignment = 32;
// cudaDeviceProp::maxTexture1DLinear and maxTexture2DLinear of compute capability 8.x.
constexpr size_t kMaxLinear = size_t{1} << 28, kMaxPitchSide = 131072 - 32;

void SetLevel(TesseraTextureLevel* level, uintptr_t data, size_t w, size_t h, size_t d,
              size_t pitch = 0) {
  level->data = reinterpret_cast<const void*>(data);
  level->width = static_cast<unsigned>(w);
  level->height = static_cast<unsigned>(h);
  level->depth = static_cast<unsigned>(d);
  level->pitch = static_cast<unsigned>(pitch);
}

// The view's levels and shape from an array (cudaResourceTypeArray, or a mipmapped array's level).
void DescribeArray(const CudaArray& a, TesseraTextureView* v, unsigned level) {
  SetLevel(&v->levels[level], a.data, a.width, a.height, a.depth);
  v->layered = (a.flags & cudaArrayLayered) != 0 ? 1 : 0;
  v->cubemap = (a.flags & cudaArrayCubemap) != 0 ? 1 : 0;
  // The buffer's, as OptiX 3 has them: layers and faces make a 3D buffer.
  v->dimensionality = v->layered != 0 || v->cubemap != 0 ? 3 : a.ndims;
}

// The view of a resource: levels, format and what the application's allocation is. `storage` is
// the allocation the texture must keep (arrays), 0 for memory the application owns.
// The integer an enum field holds: an application's out-of-range value, which is refused, would be
// undefined behaviour loaded as the enum.
template <typename Enum>
int AsInt(const Enum& e) {
  static_assert(sizeof(Enum) == sizeof(int), "CUDA's enums are int-sized");
  int v = 0;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

cudaError_t DescribeResource(const cudaResourceDesc& r, TesseraTextureView* v, TexelFormat* format,
                             uintptr_t* storage) {
  absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
  if (!memory.ok()) return cudaErrorInitializationError;
  *storage = 0;
  v->level_count = 1;
  switch (AsInt(r.resType)) {
    case cudaResourceTypeArray: {
      const std::optional<CudaArray> a = TextureHandles::Get().FindArray(r.res.array.array);
      if (!a) return cudaErrorInvalidValue;
      DescribeArray(*a, v, 0);
      *format = a->format;
      *storage = a->mipmap != 0 ? a->mipmap : a->data;
      return cudaSuccess;
    }
    case cudaResourceTypeMipmappedArray: {
      const std::optional<CudaMipmappedArray> m =
          TextureHandles::Get().FindMipmappedArray(r.res.mipmap.mipmap);
      if (!m) return cudaErrorInvalidValue;
      for (unsigned level = 0; level < m->levels; ++level) {
        const std::optional<CudaArray> a =
            TextureHandles::Get().FindArray(reinterpret_cast<const void*>(m->level_data[level]));
        if (!a) return cudaErrorInvalidValue;
        DescribeArray(*a, v, level);
      }
      v->level_count = m->levels;
      *format = m->level0.format;
      *storage = m->level0.data;
      return cudaSuccess;
    }
    case cudaResourceTypeLinear: {
      const std::optional<TexelFormat> f = FormatOf(r.res.linear.desc);
      if (!f) return cudaErrorInvalidChannelDescriptor;
      const uintptr_t p = reinterpret_cast<uintptr_t>(r.res.linear.devPtr);
      const size_t texels = r.res.linear.sizeInBytes / f->element_size;
      if (p == 0 || p % kTextureAlignment != 0 || texels == 0 || texels > kMaxLinear ||
          !(*memory)->IsAllocated(p, texels * f->element_size)) {
        return cudaErrorInvalidValue;
      }
      SetLevel(&v->levels[0], p, texels, 1, 1);
      v->dimensionality = 1;
      *format = *f;
      return cudaSuccess;
    }
    case cudaResourceTypePitch2D: {
      const std::optional<TexelFormat> f = FormatOf(r.res.pitch2D.desc);
      if (!f) return cudaErrorInvalidChannelDescriptor;
      const auto& p2 = r.res.pitch2D;
      const uintptr_t p = reinterpret_cast<uintptr_t>(p2.devPtr);
      const size_t row = p2.width * f->element_size;
      if (p == 0 || p % kTextureAlignment != 0 || p2.width == 0 || p2.height == 0 ||
          p2.width > kMaxPitchSide || p2.height > kMaxPitchSide || p2.pitchInBytes < row ||
          p2.pitchInBytes % kTexturePitchAlignment != 0 ||
          !(*memory)->IsAllocated(p, p2.pitchInBytes * (p2.height - 1) + row)) {
        return cudaErrorInvalidValue;
      }
      // The pitch alignment is a multiple of every texel size (1 to 16 bytes): whole texels.
      SetLevel(&v->levels[0], p, p2.width, p2.height, 1, p2.pitchInBytes / f->element_size);
      v->dimensionality = 2;
      *format = *f;
      return cudaSuccess;
    }
    default:
      return cudaErrorInvalidValue;
  }
}

bool ValidAddressMode(int m) {
  return m == cudaAddressModeWrap || m == cudaAddressModeClamp || m == cudaAddressModeMirror ||
         m == cudaAddressModeBorder;
}

unsigned WrapOf(cudaTextureAddressMode m) {
  switch (m) {
    case cudaAddressModeWrap:
      return tx::kWrapRepeat;
    case cudaAddressModeMirror:
      return tx::kWrapMirror;
    case cudaAddressModeBorder:
      return tx::kWrapClampToBorder;
    default:
      return tx::kWrapClampToEdge;
  }
}

// The sampling modes of a texture description over texels of `format`; cudaErrorInvalidValue
// for what CUDA refuses, cudaErrorNotSupported for what it does and the sampler does not.
cudaError_t DescribeSampling(const cudaTextureDesc& t, const TexelFormat& format, bool mipmapped,
                             TesseraTextureView* v) {
  for (const cudaTextureAddressMode& m : t.addressMode) {
    if (!ValidAddressMode(AsInt(m))) return cudaErrorInvalidValue;
  }
  const auto valid_filter = [](int f) {
    return f == cudaFilterModePoint || f == cudaFilterModeLinear;
  };
  if (!valid_filter(AsInt(t.filterMode)) ||
      (mipmapped && !valid_filter(AsInt(t.mipmapFilterMode)))) {
    return cudaErrorInvalidValue;
  }
  const int read_mode = AsInt(t.readMode);
  if (read_mode != cudaReadModeElementType && read_mode != cudaReadModeNormalizedFloat) {
    return cudaErrorInvalidValue;
  }
  const bool normalized_read = t.readMode == cudaReadModeNormalizedFloat;
  // CUDA filters and normalizes only what it returns as floats: integer texels read as they are
  // can be neither blended nor normalized when they are 32 bits wide.
  if (format.integer &&
      (normalized_read ? format.channel_bits == 32
                       : t.filterMode == cudaFilterModeLinear ||
                             (mipmapped && t.mipmapFilterMode == cudaFilterModeLinear))) {
    return cudaErrorInvalidValue;
  }
  // The sampler's border texels are 0 and it filters each cube face alone.
  bool border = false;
  for (int i = 0; i < 3; ++i) border = border || t.addressMode[i] == cudaAddressModeBorder;
  if (border && (t.borderColor[0] != 0.f || t.borderColor[1] != 0.f || t.borderColor[2] != 0.f ||
                 t.borderColor[3] != 0.f)) {
    return cudaErrorNotSupported;
  }
  if (v->cubemap != 0 && t.seamlessCubemap != 0 && t.filterMode == cudaFilterModeLinear) {
    return cudaErrorNotSupported;
  }
  for (int i = 0; i < 3; ++i) v->wrap[i] = WrapOf(t.addressMode[i]);
  v->min_filter = v->mag_filter =
      t.filterMode == cudaFilterModeLinear ? tx::kFilterLinear : tx::kFilterNearest;
  v->mip_filter = !mipmapped                                   ? tx::kFilterNone
                  : t.mipmapFilterMode == cudaFilterModeLinear ? tx::kFilterLinear
                                                               : tx::kFilterNearest;
  // sRGB decodes 8-bit unsigned texels read as floats; the sampler leaves other formats alone.
  v->read_mode = t.sRGB != 0
                     ? (normalized_read ? tx::kReadNormalizedFloatSrgb : tx::kReadElementTypeSrgb)
                     : (normalized_read ? tx::kReadNormalizedFloat : tx::kReadElementType);
  v->index_mode = t.normalizedCoords != 0 ? tx::kIndexNormalizedCoordinates : tx::kIndexArrayIndex;
  v->max_anisotropy = static_cast<float>(std::clamp(t.maxAnisotropy, 1u, 16u));
  v->mip_level_bias = t.mipmapLevelBias;
  v->mip_level_clamp[0] = t.minMipmapLevelClamp;
  v->mip_level_clamp[1] = t.maxMipmapLevelClamp;
  return cudaSuccess;
}

cudaError_t CreateTextureObject(cudaTextureObject_t* object, const cudaResourceDesc* resource,
                                const cudaTextureDesc* texture,
                                const cudaResourceViewDesc* view_desc) {
  if (object == nullptr || resource == nullptr || texture == nullptr) {
    return cudaErrorInvalidValue;
  }
  *object = 0;
  if (view_desc != nullptr) return cudaErrorNotSupported;  // reinterpreted formats, sub-ranges
  TesseraCudaTextureObject d;
  std::memset(&d, 0, sizeof d);  // the padding travels too: keep it deterministic
  TexelFormat format;
  uintptr_t storage = 0;
  cudaError_t e = DescribeResource(*resource, &d.view, &format, &storage);
  if (e != cudaSuccess) return e;
  e = DescribeSampling(*texture, format, resource->resType == cudaResourceTypeMipmappedArray,
                       &d.view);
  if (e != cudaSuccess) return e;
  d.view.format = format.format;
  d.view.element_size = format.element_size;
  tx::MarkFastLookups(d.view);  // as the OptiX 3 engine marks its views
  d.magic = TESSERA_CUDA_TEXTURE_MAGIC;

  absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
  if (!memory.ok()) return cudaErrorInitializationError;
  if (!TextureHandles::Get().Hold(storage)) return cudaErrorInvalidValue;  // freed meanwhile
  absl::StatusOr<uintptr_t> address = (*memory)->Allocate(sizeof d, CurrentCudaDevice());
  if (!address.ok()) {
    TextureHandles::Get().Release(storage);
    return cudaErrorMemoryAllocation;
  }
  std::memcpy(reinterpret_cast<void*>(*address), &d, sizeof d);
  (*memory)->MarkWritten(*address, sizeof d);
  TextureHandles::Get().AddTexture(*address, storage);
  *object = *address;
  return cudaSuccess;
}

}  // namespace
}  // namespace tessera::optix7

extern "C" {

cudaError_t cudaCreateTextureObject(cudaTextureObject_t* pTexObject,
                                    const struct cudaResourceDesc* pResDesc,
                                    const struct cudaTextureDesc* pTexDesc,
                                    const struct cudaResourceViewDesc* pResViewDesc) {
  const cudaError_t e =
      tessera::optix7::CreateTextureObject(pTexObject, pResDesc, pTexDesc, pResViewDesc);
  return e == cudaSuccess ? e : tessera::optix7::RecordCudaError(e);
}

cudaError_t cudaDestroyTextureObject(cudaTextureObject_t texObject) {
  using tessera::optix7::HostDeviceMemory;
  uintptr_t storage = 0;
  if (!tessera::optix7::TextureHandles::Get().RemoveTexture(texObject, &storage)) {
    return tessera::optix7::RecordCudaError(cudaErrorInvalidValue);
  }
  absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
  if (memory.ok()) {
    // Using a destroyed object is undefined in CUDA; here the magic is gone from the host's copy
    // at least, so a lookup in this process that still reaches the memory reads zeros.
    std::memset(reinterpret_cast<void*>(texObject), 0, sizeof(TesseraCudaTextureObject));
    (void)(*memory)->Free(texObject);
  }
  tessera::optix7::TextureHandles::Get().Release(storage);
  return cudaSuccess;
}

}  // extern "C"
