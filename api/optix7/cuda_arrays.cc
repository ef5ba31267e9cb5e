// cudaMallocArray, cudaMalloc3DArray, cudaMallocMipmappedArray and their handles (cuda_arrays.h).
#include "cuda_arrays.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "cuda_devices.h"
#include "host_device_memory.h"
#include "tessera/detail/mip_levels.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/detail/texture_view.h"

namespace tessera::optix7 {

namespace tx = tessera::texture;

std::optional<TexelFormat> FormatOf(const cudaChannelFormatDesc& d) {
  const int bits = d.x;
  int channels;
  if (d.y == 0 && d.z == 0 && d.w == 0) {
    channels = 1;
  } else if (d.y == bits && d.z == 0 && d.w == 0) {
    channels = 2;
  } else if (d.y == bits && d.z == bits && d.w == bits) {
    channels = 4;  // CUDA has no 3-channel arrays
  } else {
    return std::nullopt;
  }
  // The first format of each family (1 channel); 2 and 4 channels follow it, as do OptiX 3's
  // RTformats, whose 3-channel member sits between them.
  unsigned first;
  switch (d.f) {
    case cudaChannelFormatKindSigned:
      first = bits == 8 ? tx::kFormatByte : bits == 16 ? tx::kFormatShort : tx::kFormatInt;
      break;
    case cudaChannelFormatKindUnsigned:
      first = bits == 8    ? tx::kFormatUnsignedByte
              : bits == 16 ? tx::kFormatUnsignedShort
                           : tx::kFormatUnsignedInt;
      break;
    case cudaChannelFormatKindFloat:
      if (bits == 8) return std::nullopt;
      first = bits == 16 ? tx::kFormatHalf : tx::kFormatFloat;
      break;
    default:
      return std::nullopt;
  }
  if (bits != 8 && bits != 16 && bits != 32) return std::nullopt;
  TexelFormat f;
  f.format = first + (channels == 4 ? 3 : channels - 1);
  f.channel_bits = static_cast<unsigned>(bits);
  f.element_size = static_cast<unsigned>(bits / 8 * channels);
  f.integer = d.f != cudaChannelFormatKindFloat;
  return f;
}

TextureHandles& TextureHandles::Get() {
  static TextureHandles* h = new TextureHandles;
  return *h;
}

void TextureHandles::AddArray(const CudaArray& a) {
  std::lock_guard<std::mutex> lock(mutex_);
  arrays_[a.data] = a;
  if (a.mipmap == 0) storage_[a.data] = Storage{};
}

void TextureHandles::AddMipmappedArray(const CudaMipmappedArray& m) {
  std::lock_guard<std::mutex> lock(mutex_);
  mipmaps_[m.level0.data] = m;
  storage_[m.level0.data] = Storage{};
}

std::optional<CudaArray> TextureHandles::FindArray(const void* handle) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = arrays_.find(reinterpret_cast<uintptr_t>(handle));
  if (it == arrays_.end()) return std::nullopt;
  return it->second;
}

std::optional<CudaMipmappedArray> TextureHandles::FindMipmappedArray(const void* handle) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = mipmaps_.find(reinterpret_cast<uintptr_t>(handle));
  if (it == mipmaps_.end()) return std::nullopt;
  return it->second;
}

cudaError_t TextureHandles::FreeArray(const void* handle) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = arrays_.find(reinterpret_cast<uintptr_t>(handle));
  if (it == arrays_.end() || it->second.mipmap != 0) return cudaErrorInvalidValue;
  const uintptr_t storage = it->first;
  arrays_.erase(it);
  storage_[storage].freed = true;
  MaybeRelease(storage);
  return cudaSuccess;
}

cudaError_t TextureHandles::FreeMipmappedArray(const void* handle) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = mipmaps_.find(reinterpret_cast<uintptr_t>(handle));
  if (it == mipmaps_.end()) return cudaErrorInvalidValue;
  const uintptr_t storage = it->first;
  for (unsigned level = 0; level < it->second.levels; ++level) {
    arrays_.erase(it->second.level_data[level]);
  }
  mipmaps_.erase(it);
  storage_[storage].freed = true;
  MaybeRelease(storage);
  return cudaSuccess;
}

bool TextureHandles::Hold(uintptr_t storage) {
  if (storage == 0) return true;
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = storage_.find(storage);
  if (it == storage_.end() || it->second.freed) return false;
  ++it->second.holders;
  return true;
}

void TextureHandles::AddTexture(uintptr_t object, uintptr_t storage) {
  std::lock_guard<std::mutex> lock(mutex_);
  textures_[object] = storage;
}

bool TextureHandles::RemoveTexture(uintptr_t object, uintptr_t* storage) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = textures_.find(object);
  if (it == textures_.end()) return false;
  *storage = it->second;
  textures_.erase(it);
  return true;
}

void TextureHandles::Release(uintptr_t storage) {
  if (storage == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = storage_.find(storage);
  if (it == storage_.end()) return;
  --it->second.holders;
  MaybeRelease(storage);
}

void TextureHandles::MaybeRelease(uintptr_t storage) {
  auto it = storage_.find(storage);
  if (it == storage_.end() || !it->second.freed || it->second.holders > 0) return;
  storage_.erase(it);
  absl::StatusOr<HostDeviceMemory*> m = HostDeviceMemory::Get();
  if (m.ok()) (void)(*m)->Free(storage);  // it was allocated here, so this cannot fail
}

bool TextureHandles::Owns(uintptr_t address) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return storage_.count(address) != 0 || textures_.count(address) != 0;
}

namespace {

// The largest sizes a CUDA device of compute capability 8.x takes (cudaDeviceProp::maxTexture*),
// so that an application that runs on a GPU runs here and one that would fail there fails here.
constexpr size_t kMax1D = 131072, kMax2DWidth = 131072, kMax2DHeight = 65536, kMax3D = 16384,
                 kMaxLayeredSide = 32768, kMaxLayers = 2048, kMaxCubeSide = 32768;

// The shape of an array from cudaMalloc3DArray's extent and flags, as CUDA reads them: (w, 0, 0)
// 1D, (w, h, 0) 2D, (w, h, d) 3D; with cudaArrayLayered (w, 0, layers) or (w, h, layers); with
// cudaArrayCubemap (w, w, 6), and 6 faces per layer when layered too.
cudaError_t ShapeOf(const cudaChannelFormatDesc* desc, cudaExtent e, unsigned flags, CudaArray* a) {
  if (desc == nullptr) return cudaErrorInvalidValue;
  const std::optional<TexelFormat> format = FormatOf(*desc);
  if (!format) return cudaErrorInvalidChannelDescriptor;
  constexpr unsigned kKnown =
      cudaArrayLayered | cudaArraySurfaceLoadStore | cudaArrayCubemap | cudaArrayTextureGather;
  if ((flags & ~kKnown) != 0 || e.width == 0) return cudaErrorInvalidValue;
  a->desc = *desc;
  a->format = *format;
  a->extent = e;
  a->flags = flags;
  a->width = e.width;
  a->height = std::max<size_t>(e.height, 1);
  a->depth = std::max<size_t>(e.depth, 1);
  const bool layered = (flags & cudaArrayLayered) != 0;
  if ((flags & cudaArrayCubemap) != 0) {
    if (e.width != e.height || e.width > kMaxCubeSide) return cudaErrorInvalidValue;
    if (layered ? (e.depth == 0 || e.depth % 6 != 0 || e.depth / 6 > kMaxLayers) : e.depth != 6) {
      return cudaErrorInvalidValue;
    }
    a->ndims = 2;
  } else if (layered) {
    if (e.depth == 0 || e.depth > kMaxLayers || e.width > kMaxLayeredSide ||
        e.height > kMaxLayeredSide) {
      return cudaErrorInvalidValue;
    }
    a->ndims = e.height == 0 ? 1 : 2;
  } else if (e.height == 0) {
    if (e.depth != 0 || e.width > kMax1D) return cudaErrorInvalidValue;
    a->ndims = 1;
  } else if (e.depth == 0) {
    if (e.width > kMax2DWidth || e.height > kMax2DHeight) return cudaErrorInvalidValue;
    a->ndims = 2;
  } else {
    if (e.width > kMax3D || e.height > kMax3D || e.depth > kMax3D) return cudaErrorInvalidValue;
    a->ndims = 3;
  }
  return cudaSuccess;
}

bool KeepsDepth(const CudaArray& a) {
  return (a.flags & (cudaArrayLayered | cudaArrayCubemap)) != 0;
}

cudaError_t Allocate(size_t bytes, uintptr_t* address) {
  absl::StatusOr<HostDeviceMemory*> m = HostDeviceMemory::Get();
  if (!m.ok()) return cudaErrorMemoryAllocation;
  absl::StatusOr<uintptr_t> a = (*m)->Allocate(bytes, CurrentCudaDevice());
  if (!a.ok()) return cudaErrorMemoryAllocation;
  *address = *a;
  return cudaSuccess;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::CudaArray;
using tessera::optix7::CudaMipmappedArray;
using tessera::optix7::RecordCudaError;
using tessera::optix7::TextureHandles;

extern "C" {

struct cudaChannelFormatDesc cudaCreateChannelDesc(int x, int y, int z, int w,
                                                   enum cudaChannelFormatKind f) {
  return cudaChannelFormatDesc{x, y, z, w, f};
}

cudaError_t cudaMalloc3DArray(cudaArray_t* array, const struct cudaChannelFormatDesc* desc,
                              struct cudaExtent extent, unsigned int flags) {
  if (array == nullptr) return RecordCudaError(cudaErrorInvalidValue);
  *array = nullptr;
  CudaArray a;
  cudaError_t e = tessera::optix7::ShapeOf(desc, extent, flags, &a);
  if (e == cudaSuccess) e = tessera::optix7::Allocate(a.bytes(), &a.data);
  if (e != cudaSuccess) return RecordCudaError(e);
  TextureHandles::Get().AddArray(a);
  *array = reinterpret_cast<cudaArray_t>(a.data);
  return cudaSuccess;
}

cudaError_t cudaMallocArray(cudaArray_t* array, const struct cudaChannelFormatDesc* desc,
                            size_t width, size_t height, unsigned int flags) {
  // Layers and cube faces need a depth: cudaMalloc3DArray's.
  if ((flags & (cudaArrayLayered | cudaArrayCubemap)) != 0) {
    if (array != nullptr) *array = nullptr;
    return RecordCudaError(cudaErrorInvalidValue);
  }
  return cudaMalloc3DArray(array, desc, cudaExtent{width, height, 0}, flags);
}

cudaError_t cudaMallocMipmappedArray(cudaMipmappedArray_t* mipmap,
                                     const struct cudaChannelFormatDesc* desc,
                                     struct cudaExtent extent, unsigned int numLevels,
                                     unsigned int flags) {
  if (mipmap == nullptr) return RecordCudaError(cudaErrorInvalidValue);
  *mipmap = nullptr;
  CudaMipmappedArray m;
  cudaError_t e = tessera::optix7::ShapeOf(desc, extent, flags, &m.level0);
  if (e != cudaSuccess) return RecordCudaError(e);
  if (numLevels == 0) return RecordCudaError(cudaErrorInvalidValue);
  const CudaArray& a0 = m.level0;
  const std::array<uint64_t, 3> dims = {a0.width, a0.height, a0.depth};
  const bool keep = tessera::optix7::KeepsDepth(a0);
  // More levels than the size has are not made (as CUDA); the sampler reads at most 16.
  m.levels = std::min({numLevels, tessera::detail::MaxMipLevels(dims, a0.ndims, keep),
                       unsigned{TESSERA_TEXTURE_MAX_LEVELS}});
  const uint64_t elements = tessera::detail::MipLevelOffset(dims, a0.ndims, keep, m.levels);
  uintptr_t base = 0;
  e = tessera::optix7::Allocate(elements * a0.format.element_size, &base);
  if (e != cudaSuccess) return RecordCudaError(e);
  for (unsigned level = 0; level < m.levels; ++level) {
    CudaArray l = a0;
    const std::array<uint64_t, 3> d = tessera::detail::MipLevelDims(dims, a0.ndims, keep, level);
    l.width = d[0];
    l.height = d[1];
    l.depth = d[2];
    l.extent = {d[0], a0.extent.height == 0 ? 0 : d[1], a0.extent.depth == 0 ? 0 : d[2]};
    l.data = base +
             tessera::detail::MipLevelOffset(dims, a0.ndims, keep, level) * a0.format.element_size;
    l.mipmap = base;
    m.level_data[level] = l.data;
    if (level == 0) m.level0 = l;
    TextureHandles::Get().AddArray(l);
  }
  TextureHandles::Get().AddMipmappedArray(m);
  *mipmap = reinterpret_cast<cudaMipmappedArray_t>(base);
  return cudaSuccess;
}

cudaError_t cudaGetMipmappedArrayLevel(cudaArray_t* levelArray,
                                       cudaMipmappedArray_const_t mipmappedArray,
                                       unsigned int level) {
  if (levelArray == nullptr) return RecordCudaError(cudaErrorInvalidValue);
  const std::optional<CudaMipmappedArray> m =
      TextureHandles::Get().FindMipmappedArray(mipmappedArray);
  if (!m || level >= m->levels) return RecordCudaError(cudaErrorInvalidValue);
  *levelArray = reinterpret_cast<cudaArray_t>(m->level_data[level]);
  return cudaSuccess;
}

cudaError_t cudaFreeArray(cudaArray_t array) {
  if (array == nullptr) return cudaSuccess;  // as CUDA: nothing to free
  return RecordCudaError(TextureHandles::Get().FreeArray(array));
}

cudaError_t cudaFreeMipmappedArray(cudaMipmappedArray_t mipmappedArray) {
  if (mipmappedArray == nullptr) return cudaSuccess;
  return RecordCudaError(TextureHandles::Get().FreeMipmappedArray(mipmappedArray));
}

cudaError_t cudaArrayGetInfo(struct cudaChannelFormatDesc* desc, struct cudaExtent* extent,
                             unsigned int* flags, cudaArray_t array) {
  const std::optional<CudaArray> a = TextureHandles::Get().FindArray(array);
  if (!a) return RecordCudaError(cudaErrorInvalidValue);
  if (desc != nullptr) *desc = a->desc;
  if (extent != nullptr) *extent = a->extent;
  if (flags != nullptr) *flags = a->flags;
  return cudaSuccess;
}

cudaError_t cudaGetChannelDesc(struct cudaChannelFormatDesc* desc, cudaArray_const_t array) {
  if (desc == nullptr) return RecordCudaError(cudaErrorInvalidValue);
  return cudaArrayGetInfo(desc, nullptr, nullptr, const_cast<cudaArray_t>(array));
}

}  // extern "C"
