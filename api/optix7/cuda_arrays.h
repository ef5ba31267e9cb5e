// CUDA arrays and mipmapped arrays over Tessera's device memory (docs/optix7.md, "Textures"): an
// array is a device allocation of packed texels (x fastest, then y, then z, layer or cube face)
// and its cudaArray_t is that allocation's address; a mipmapped array holds its levels one after
// another in one allocation (tessera/detail/mip_levels.h), each level an array of its own. The
// host keeps what the handles mean here; devices see only the texels, through the texture objects
// that cuda_textures.cc writes into device memory.
#ifndef TESSERA_API_OPTIX7_CUDA_ARRAYS_H_
#define TESSERA_API_OPTIX7_CUDA_ARRAYS_H_

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>

#include "cuda_runtime_api.h"

namespace tessera::optix7 {

// A texel format: the sampler's (tessera/detail/texture_modes.h) and its size.
struct TexelFormat {
  unsigned format = 0;  // texture::kFormat*
  unsigned element_size = 0;
  unsigned channel_bits = 0;
  bool integer = false;  // signed or unsigned integer channels
};

// The format of a channel descriptor, or nothing when CUDA has no such texel: 1, 2 or 4 channels
// of equal width (8, 16 or 32 bits; float 16 or 32), as cudaMallocArray and texture objects take.
std::optional<TexelFormat> FormatOf(const cudaChannelFormatDesc& desc);

// What a cudaArray_t is: its format, its size in texels (unused dimensions 1; `depth` counts
// layers, or cube faces, 6 per layer, in layered and cube map arrays) and what it was made with.
struct CudaArray {
  uintptr_t data = 0;  // the handle: its first texel
  cudaChannelFormatDesc desc = {};
  TexelFormat format;
  unsigned ndims = 1;  // of one layer or face: 1, 2 or 3
  size_t width = 1, height = 1, depth = 1;
  cudaExtent extent = {};  // as the application gave it
  unsigned flags = 0;      // cudaArrayLayered, cudaArrayCubemap, ...
  uintptr_t mipmap = 0;    // the mipmapped array this is a level of; 0 for cudaMallocArray's

  size_t row_bytes() const { return width * format.element_size; }
  size_t bytes() const { return row_bytes() * height * depth; }
};

struct CudaMipmappedArray {
  CudaArray level0;
  unsigned levels = 1;
  uintptr_t level_data[16] = {};  // TESSERA_TEXTURE_MAX_LEVELS
};

// The live arrays, mipmapped arrays and texture objects of the process. An array that a texture
// object reads keeps its memory until the last such object is destroyed, even after
// cudaFreeArray: a program that samples it then reads the old texels, never freed memory.
class TextureHandles {
 public:
  static TextureHandles& Get();

  // Records an array whose memory is its own allocation, or a level of a mipmapped array.
  void AddArray(const CudaArray& a);
  void AddMipmappedArray(const CudaMipmappedArray& m);
  // The array or mipmapped array a live handle names (mip levels included).
  std::optional<CudaArray> FindArray(const void* handle) const;
  std::optional<CudaMipmappedArray> FindMipmappedArray(const void* handle) const;
  // cudaFreeArray and cudaFreeMipmappedArray: cudaErrorInvalidValue for a handle that is not one
  // the application may free (unknown, freed, a level of a mipmapped array).
  cudaError_t FreeArray(const void* handle);
  cudaError_t FreeMipmappedArray(const void* handle);

  // Texture objects: each holds the allocation it reads (an array's or a mipmapped array's; 0 for
  // linear and pitched memory, which the application owns). Hold fails if it was freed meanwhile.
  bool Hold(uintptr_t storage);
  void AddTexture(uintptr_t object, uintptr_t storage);
  // Removes a live texture object: false when `object` is not one.
  bool RemoveTexture(uintptr_t object, uintptr_t* storage);
  void Release(uintptr_t storage);

  // Whether `address` starts an allocation these handles own (cudaFree must refuse it).
  bool Owns(uintptr_t address) const;

 private:
  struct Storage {
    int holders = 0;     // texture objects reading it
    bool freed = false;  // by the application: its handle is gone
  };
  // Frees the allocation once it is freed and unheld. mutex_ held.
  void MaybeRelease(uintptr_t storage);

  mutable std::mutex mutex_;
  std::map<uintptr_t, CudaArray> arrays_;  // by handle; mip levels too
  std::map<uintptr_t, CudaMipmappedArray> mipmaps_;
  std::map<uintptr_t, Storage> storage_;     // allocations of arrays and mipmapped arrays
  std::map<uintptr_t, uintptr_t> textures_;  // texture object -> the storage it holds (or 0)
};

// CUDA's error state (cuda_runtime.cc): records a failure as the thread's last error.
cudaError_t RecordCudaError(cudaError_t e);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_CUDA_ARRAYS_H_
