// Copies into and out of CUDA arrays (cuda_arrays.h): cudaMemcpy2DToArray, cudaMemcpyToArray,
// cudaMemcpy2DFromArray and cudaMemcpy3D. Every copy is a sequence of rows between two places,
// each host memory, device memory or an array; what lands in device memory is marked written so
// that the next launch ships it (docs/device_memory.md).
#include <cstring>
#include <optional>

#include "cuda_arrays.h"
#include "host_device_memory.h"

namespace tessera::optix7 {
namespace {

// One side of a copy: rows of `row_bytes` starting at `base`, `pitch` bytes apart, and slices
// `slice` bytes apart. `device`: in device memory (arrays always are).
struct Side {
  uintptr_t base = 0;
  size_t pitch = 0;
  size_t slice = 0;
  bool device = false;
  bool array = false;
};

// Whether every row of `side` lies where it must: device rows in one live allocation, host rows
// outside device memory.
bool RowsFit(HostDeviceMemory& m, const Side& s, size_t row_bytes, size_t rows, size_t slices) {
  for (size_t z = 0; z < slices; ++z) {
    for (size_t y = 0; y < rows; ++y) {
      const uintptr_t row = s.base + z * s.slice + y * s.pitch;
      if (s.device ? !m.IsAllocated(row, row_bytes) : m.InArena(row)) return false;
    }
  }
  return true;
}

// Sides' memory kinds from the copy kind: cudaMemcpyDefault reads them from the pointers.
cudaError_t ResolveKind(HostDeviceMemory& m, cudaMemcpyKind kind, Side* src, Side* dst) {
  if (kind == cudaMemcpyDefault) {
    if (!src->array) src->device = m.InArena(src->base);
    if (!dst->array) dst->device = m.InArena(dst->base);
    return cudaSuccess;
  }
  bool src_device, dst_device;
  switch (kind) {
    case cudaMemcpyHostToHost:
      src_device = dst_device = false;
      break;
    case cudaMemcpyHostToDevice:
      src_device = false;
      dst_device = true;
      break;
    case cudaMemcpyDeviceToHost:
      src_device = true;
      dst_device = false;
      break;
    case cudaMemcpyDeviceToDevice:
      src_device = dst_device = true;
      break;
    default:
      return cudaErrorInvalidMemcpyDirection;
  }
  // An array is device memory: a kind that says otherwise is the wrong direction.
  if ((src->array && !src_device) || (dst->array && !dst_device)) {
    return cudaErrorInvalidMemcpyDirection;
  }
  src->device = src_device;
  dst->device = dst_device;
  return cudaSuccess;
}

// Copies `slices` slices of `rows` rows of `row_bytes` from src to dst and marks what it wrote
// in device memory.
cudaError_t CopyRows(cudaMemcpyKind kind, Side src, Side dst, size_t row_bytes, size_t rows,
                     size_t slices) {
  if (row_bytes == 0 || rows == 0 || slices == 0) return cudaSuccess;
  absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
  if (!memory.ok()) return cudaErrorInitializationError;
  HostDeviceMemory& m = **memory;
  if (src.base == 0 || dst.base == 0) return cudaErrorInvalidValue;
  const cudaError_t e = ResolveKind(m, kind, &src, &dst);
  if (e != cudaSuccess) return e;
  if (!RowsFit(m, src, row_bytes, rows, slices) || !RowsFit(m, dst, row_bytes, rows, slices)) {
    return cudaErrorInvalidMemcpyDirection;
  }
  for (size_t z = 0; z < slices; ++z) {
    for (size_t y = 0; y < rows; ++y) {
      std::memmove(reinterpret_cast<void*>(dst.base + z * dst.slice + y * dst.pitch),
                   reinterpret_cast<const void*>(src.base + z * src.slice + y * src.pitch),
                   row_bytes);
    }
  }
  if (dst.device) {
    // One mark over the whole span: bytes between pitched rows ship too, unchanged, which costs
    // less than a write epoch per row.
    const size_t span = (slices - 1) * dst.slice + (rows - 1) * dst.pitch + row_bytes;
    m.MarkWritten(dst.base, span);
  }
  return cudaSuccess;
}

// The array side of a copy at texel (x, y, z), or an error for a handle that is no array or a
// region past its end (`width_bytes` in bytes).
cudaError_t ArraySide(const void* handle, size_t x_bytes, size_t y, size_t z, size_t width_bytes,
                      size_t rows, size_t slices, Side* side) {
  const std::optional<CudaArray> a = TextureHandles::Get().FindArray(handle);
  if (!a) return cudaErrorInvalidValue;
  if (x_bytes + width_bytes > a->row_bytes() || y + rows > a->height || z + slices > a->depth) {
    return cudaErrorInvalidValue;
  }
  side->base = a->data + (z * a->height + y) * a->row_bytes() + x_bytes;
  side->pitch = a->row_bytes();
  side->slice = a->row_bytes() * a->height;
  side->array = side->device = true;
  return cudaSuccess;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::RecordCudaError;
using tessera::optix7::Side;

extern "C" {

cudaError_t cudaMemcpy2DToArray(cudaArray_t dst, size_t wOffset, size_t hOffset, const void* src,
                                size_t spitch, size_t width, size_t height,
                                enum cudaMemcpyKind kind) {
  if (width > spitch && height > 1) return RecordCudaError(cudaErrorInvalidPitchValue);
  Side s, d;
  cudaError_t e = tessera::optix7::ArraySide(dst, wOffset, hOffset, 0, width, height, 1, &d);
  s.base = reinterpret_cast<uintptr_t>(src);
  s.pitch = spitch;
  if (e == cudaSuccess) e = tessera::optix7::CopyRows(kind, s, d, width, height, 1);
  return e == cudaSuccess ? e : RecordCudaError(e);
}

cudaError_t cudaMemcpy2DFromArray(void* dst, size_t dpitch, cudaArray_const_t src, size_t wOffset,
                                  size_t hOffset, size_t width, size_t height,
                                  enum cudaMemcpyKind kind) {
  if (width > dpitch && height > 1) return RecordCudaError(cudaErrorInvalidPitchValue);
  Side s, d;
  cudaError_t e = tessera::optix7::ArraySide(src, wOffset, hOffset, 0, width, height, 1, &s);
  d.base = reinterpret_cast<uintptr_t>(dst);
  d.pitch = dpitch;
  if (e == cudaSuccess) e = tessera::optix7::CopyRows(kind, s, d, width, height, 1);
  return e == cudaSuccess ? e : RecordCudaError(e);
}

cudaError_t cudaMemcpyToArray(cudaArray_t dst, size_t wOffset, size_t hOffset, const void* src,
                              size_t count, enum cudaMemcpyKind kind) {
  // `count` bytes from (wOffset, hOffset) on, continuing row after row: the array's texels are
  // packed, so that is one run of its bytes.
  const std::optional<tessera::optix7::CudaArray> a =
      tessera::optix7::TextureHandles::Get().FindArray(dst);
  if (!a || wOffset > a->row_bytes() || hOffset >= a->height * a->depth) {
    return RecordCudaError(cudaErrorInvalidValue);
  }
  const size_t offset = hOffset * a->row_bytes() + wOffset;
  if (count > a->bytes() - offset) return RecordCudaError(cudaErrorInvalidValue);
  Side s, d;
  s.base = reinterpret_cast<uintptr_t>(src);
  d.base = a->data + offset;
  d.array = d.device = true;
  const cudaError_t e = tessera::optix7::CopyRows(kind, s, d, count, 1, 1);
  return e == cudaSuccess ? e : RecordCudaError(e);
}

cudaError_t cudaMemcpy3D(const struct cudaMemcpy3DParms* p) {
  if (p == nullptr) return RecordCudaError(cudaErrorInvalidValue);
  const bool src_array = p->srcArray != nullptr, dst_array = p->dstArray != nullptr;
  // Exactly one source and one destination.
  if (src_array == (p->srcPtr.ptr != nullptr) || dst_array == (p->dstPtr.ptr != nullptr)) {
    return RecordCudaError(cudaErrorInvalidValue);
  }
  // With an array in the copy, widths and array positions count its texels; pointer positions
  // count bytes, and so do widths without an array.
  size_t element = 1;
  for (const void* handle :
       {static_cast<const void*>(p->srcArray), static_cast<const void*>(p->dstArray)}) {
    if (handle == nullptr) continue;
    const std::optional<tessera::optix7::CudaArray> a =
        tessera::optix7::TextureHandles::Get().FindArray(handle);
    if (!a) return RecordCudaError(cudaErrorInvalidValue);
    if (element != 1 && element != a->format.element_size) {
      return RecordCudaError(cudaErrorInvalidValue);  // two arrays of different texel sizes
    }
    element = a->format.element_size;
  }
  const size_t width = p->extent.width * element, rows = p->extent.height, slices = p->extent.depth;
  Side s, d;
  auto side = [&](const void* array, const cudaPos& pos, const cudaPitchedPtr& ptr,
                  Side* out) -> cudaError_t {
    if (array != nullptr) {
      return tessera::optix7::ArraySide(array, pos.x * element, pos.y, pos.z, width, rows, slices,
                                        out);
    }
    if (pos.x + width > ptr.pitch) return cudaErrorInvalidPitchValue;
    if (slices > 1 && pos.y + rows > ptr.ysize) return cudaErrorInvalidValue;
    out->pitch = ptr.pitch;
    out->slice = ptr.pitch * ptr.ysize;
    out->base =
        reinterpret_cast<uintptr_t>(ptr.ptr) + pos.z * out->slice + pos.y * ptr.pitch + pos.x;
    return cudaSuccess;
  };
  cudaError_t e = side(p->srcArray, p->srcPos, p->srcPtr, &s);
  if (e == cudaSuccess) e = side(p->dstArray, p->dstPos, p->dstPtr, &d);
  if (e == cudaSuccess) e = tessera::optix7::CopyRows(p->kind, s, d, width, rows, slices);
  return e == cudaSuccess ? e : RecordCudaError(e);
}

}  // extern "C"
