// optixAccel*: sizes and builds over accel_build.h, emitted properties, compaction and
// relocation (copies: the descriptor of worker/memory/accel_format.h is position independent;
// only an instance build's child handles are addresses, which optixAccelRelocate replaces).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "accel_build.h"
#include "accel_format.h"
#include "call.h"
#include "hash.h"
#include "host_device_memory.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

using memory::AccelHeader;
using memory::AccelInput;
using memory::AccelKind;

constexpr uint64_t kRelocationMagic = 0x4c43434137525354ull;  // "TSR7ACCL", little-endian
// How deep optixAccelBuild follows instances to bound an instance build (OptiX's graph depth).
constexpr int kMaxBoundsDepth = 31;

absl::StatusOr<HostDeviceMemory*> Memory() {
  absl::StatusOr<HostDeviceMemory*> m = HostDeviceMemory::Get();
  if (!m.ok()) return OptixError(OPTIX_ERROR_CUDA_ERROR, m.status().message());
  return m;
}

// The descriptor a traversable handle of a build points at, checked to lie in device memory.
absl::StatusOr<const AccelHeader*> Descriptor(HostDeviceMemory& m, OptixTraversableHandle handle,
                                              absl::string_view argument) {
  if (handle == 0) return OptixError(OPTIX_ERROR_INVALID_VALUE, absl::StrCat(argument, " is 0"));
  if (!m.IsAllocated(handle, sizeof(AccelHeader))) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(argument, " 0x", absl::Hex(handle),
                                   " is not an acceleration in device memory"));
  }
  const auto* header = reinterpret_cast<const AccelHeader*>(handle);
  const uint64_t size = header->total_size;
  if (size < sizeof(AccelHeader) || !m.IsAllocated(handle, size)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(argument, " 0x", absl::Hex(handle),
                                   " is not an acceleration built by optixAccelBuild"));
  }
  absl::StatusOr<const AccelHeader*> read =
      memory::ReadAccelHeader(reinterpret_cast<const void*>(handle), size);
  if (!read.ok()) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE, absl::StrCat(argument, " 0x", absl::Hex(handle),
                                                              ": ", read.status().message()));
  }
  return read;
}

template <typename T>
const T* At(const AccelHeader* h, uint64_t offset) {
  return reinterpret_cast<const T*>(reinterpret_cast<const unsigned char*>(h) + offset);
}

void Extend(OptixAabb& box, const float p[3]) {
  box.minX = std::min(box.minX, p[0]);
  box.minY = std::min(box.minY, p[1]);
  box.minZ = std::min(box.minZ, p[2]);
  box.maxX = std::max(box.maxX, p[0]);
  box.maxY = std::max(box.maxY, p[1]);
  box.maxZ = std::max(box.maxZ, p[2]);
}

// `box` through 3x4 matrix `t` into `out`.
void ExtendTransformed(OptixAabb& out, const OptixAabb& box, const float t[12]) {
  for (int corner = 0; corner < 8; ++corner) {
    const float x = corner & 1 ? box.maxX : box.minX;
    const float y = corner & 2 ? box.maxY : box.minY;
    const float z = corner & 4 ? box.maxZ : box.minZ;
    const float p[3] = {t[0] * x + t[1] * y + t[2] * z + t[3],
                        t[4] * x + t[5] * y + t[6] * z + t[7],
                        t[8] * x + t[9] * y + t[10] * z + t[11]};
    Extend(out, p);
  }
}

// An SRT motion key (OptixSRTData) as its matrix C = T * R * S, the quaternion normalized.
void SrtKeyMatrix(const float v[16], float out[12]) {
  float q[4] = {v[9], v[10], v[11], v[12]};
  const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (float& c : q) c = n > 0.f ? c / n : c;
  const float x = q[0], y = q[1], z = q[2], w = q[3];
  const float r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                      2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                      2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
  const float s[12] = {v[0], v[1], v[2], v[3], 0, v[4], v[5], v[6], 0, 0, v[7], v[8]};
  const float t[3] = {v[13], v[14], v[15]};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 4; ++k) {
      out[i * 4 + k] =
          r[i * 3] * s[k] + r[i * 3 + 1] * s[4 + k] + r[i * 3 + 2] * s[8 + k] + (k == 3 ? t[i] : 0);
    }
  }
}

absl::StatusOr<OptixAabb> Bounds(HostDeviceMemory& m, OptixTraversableHandle handle, int depth);

// The bounds of a transform traversable's child through its keys (a handle with a type tag,
// api/optix7/transform_handles.cc). Matrix keys bound a matrix motion exactly; an SRT's rotation
// between keys may reach a little outside its keys' boxes, which the box does not cover.
absl::StatusOr<OptixAabb> TransformBounds(HostDeviceMemory& m, OptixTraversableHandle handle,
                                          int depth) {
  const CUdeviceptr p = handle & ~CUdeviceptr{63};
  const unsigned tag = static_cast<unsigned>(handle & 63);
  if (tag < OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM ||
      tag > OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM || !m.IsAllocated(p, 32)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("traversable 0x", absl::Hex(handle), " is no transform"));
  }
  const auto* bytes = reinterpret_cast<const unsigned char*>(p);
  OptixTraversableHandle child;
  std::memcpy(&child, bytes, sizeof(child));
  absl::StatusOr<OptixAabb> inner = Bounds(m, child, depth + 1);
  if (!inner.ok() || inner->minX > inner->maxX) return inner;
  OptixAabb box{FLT_MAX, FLT_MAX, FLT_MAX, -FLT_MAX, -FLT_MAX, -FLT_MAX};
  if (tag == OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM) {
    float t[12];
    std::memcpy(t, bytes + offsetof(OptixStaticTransform, transform), sizeof(t));
    ExtendTransformed(box, *inner, t);
    return box;
  }
  OptixMotionOptions mo;
  std::memcpy(&mo, bytes + 8, sizeof(mo));
  const size_t per_key = tag == OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM ? 12 : 16;
  if (!m.IsAllocated(p, 32 + per_key * 4 * mo.numKeys)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("motion transform 0x", absl::Hex(handle), " of ", mo.numKeys,
                                   " keys does not lie in one allocation"));
  }
  for (unsigned k = 0; k < mo.numKeys; ++k) {
    float v[16], t[12];
    std::memcpy(v, bytes + 32 + per_key * 4 * k, per_key * 4);
    if (per_key == 16) {
      SrtKeyMatrix(v, t);
    } else {
      std::memcpy(t, v, sizeof(t));
    }
    ExtendTransformed(box, *inner, t);
  }
  return box;
}

// The bounds of everything a build holds (every motion key); an empty build's box has
// min > max.
absl::StatusOr<OptixAabb> Bounds(HostDeviceMemory& m, OptixTraversableHandle handle, int depth) {
  if (depth > kMaxBoundsDepth) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE, "instances nest deeper than 31 levels");
  }
  if ((handle & 63) != 0) return TransformBounds(m, handle, depth);
  absl::StatusOr<const AccelHeader*> h = Descriptor(m, handle, "traversable");
  if (!h.ok()) return h.status();
  OptixAabb box{FLT_MAX, FLT_MAX, FLT_MAX, -FLT_MAX, -FLT_MAX, -FLT_MAX};
  if ((*h)->kind == AccelKind::kInstances) {
    for (uint64_t k = 0; k < (*h)->primitive_count; ++k) {
      OptixInstance instance;
      std::memcpy(&instance,
                  At<unsigned char>(*h, (*h)->inputs_offset + k * memory::kInstanceBytes),
                  sizeof(instance));
      if (instance.traversableHandle == 0) continue;
      absl::StatusOr<OptixAabb> child = Bounds(m, instance.traversableHandle, depth + 1);
      if (!child.ok()) {
        return OptixError(ToOptixResult(child.status()),
                          absl::StrCat("instance ", k, ": ", child.status().message()));
      }
      if (child->minX > child->maxX) continue;
      ExtendTransformed(box, *child, instance.transform);
    }
    return box;
  }
  uint32_t keys = 1;
  if ((*h)->motion_offset != 0) {
    keys = At<memory::AccelMotion>(*h, (*h)->motion_offset)->keys;
  }
  for (uint32_t i = 0; i < (*h)->input_count; ++i) {
    const AccelInput& in = *At<AccelInput>(*h, (*h)->inputs_offset + i * sizeof(AccelInput));
    for (uint32_t key = 0; key < keys; ++key) {
      if ((*h)->kind == AccelKind::kTriangles) {
        const float* vertices = At<float>(*h, in.vertices_offset) + 3ull * in.vertex_count * key;
        const uint32_t* indices = At<uint32_t>(*h, in.indices_offset);
        for (uint64_t k = 0; k < uint64_t{in.primitive_count} * 3; ++k) {
          if (indices[k] < in.vertex_count) Extend(box, vertices + uint64_t{indices[k]} * 3);
        }
      } else if ((*h)->kind == AccelKind::kSpheres) {
        const float* spheres = At<float>(*h, in.vertices_offset) + 4ull * in.primitive_count * key;
        for (uint64_t k = 0; k < in.primitive_count; ++k) {
          const float* c = spheres + 4 * k;
          const float lo[3] = {c[0] - c[3], c[1] - c[3], c[2] - c[3]};
          const float hi[3] = {c[0] + c[3], c[1] + c[3], c[2] + c[3]};
          Extend(box, lo);
          Extend(box, hi);
        }
      } else {
        const float* boxes = At<float>(*h, in.aabbs_offset) + 6ull * in.primitive_count * key;
        for (uint64_t k = 0; k < in.primitive_count; ++k) {
          Extend(box, boxes + k * 6);
          Extend(box, boxes + k * 6 + 3);
        }
      }
    }
  }
  return box;
}

// One OptixAccelEmitDesc's destination, checked before anything is built.
absl::Status CheckEmit(HostDeviceMemory& m, const OptixAccelEmitDesc& e, const std::string& what) {
  size_t bytes = 0;
  if (e.type == OPTIX_PROPERTY_TYPE_COMPACTED_SIZE) {
    bytes = sizeof(size_t);
  } else if (e.type == OPTIX_PROPERTY_TYPE_AABBS) {
    bytes = sizeof(OptixAabb);
  } else {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(what, ".type 0x", absl::Hex(static_cast<unsigned>(e.type)),
                                   " is no OptixAccelPropertyType"));
  }
  if (e.result == 0 || e.result % 8 != 0 || !m.IsAllocated(e.result, bytes)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(what, ".result 0x", absl::Hex(e.result), " is not ", bytes,
                                   " bytes of device memory, 8-byte aligned"));
  }
  return absl::OkStatus();
}

absl::Status Emit(HostDeviceMemory& m, OptixTraversableHandle handle, const OptixAccelEmitDesc& e) {
  if (e.type == OPTIX_PROPERTY_TYPE_COMPACTED_SIZE) {
    // Compaction is a copy: the compacted size is the descriptor's own.
    absl::StatusOr<const AccelHeader*> h = Descriptor(m, handle, "handle");
    if (!h.ok()) return h.status();
    const size_t size = (*h)->total_size;
    std::memcpy(reinterpret_cast<void*>(e.result), &size, sizeof(size));
    m.MarkWritten(e.result, sizeof(size));
    return absl::OkStatus();
  }
  absl::StatusOr<OptixAabb> box = Bounds(m, handle, 0);
  if (!box.ok()) return box.status();
  std::memcpy(reinterpret_cast<void*>(e.result), &*box, sizeof(OptixAabb));
  m.MarkWritten(e.result, sizeof(OptixAabb));
  return absl::OkStatus();
}

absl::Status CheckOutput(HostDeviceMemory& m, CUdeviceptr output, size_t output_size, size_t needed,
                         absl::string_view argument) {
  if (output == 0 || output % OPTIX_ACCEL_BUFFER_BYTE_ALIGNMENT != 0) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(argument, " 0x", absl::Hex(output),
                                   " is null or not OPTIX_ACCEL_BUFFER_BYTE_ALIGNMENT (128) "
                                   "aligned"));
  }
  if (output_size < needed || !m.IsAllocated(output, needed)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(argument, " holds ", output_size,
                                   " bytes (or lies outside one "
                                   "cudaMalloc allocation); the acceleration needs ",
                                   needed));
  }
  return absl::OkStatus();
}

absl::Status CheckRelocationInfo(const OptixRelocationInfo& info) {
  if (info.info[0] != kRelocationMagic || info.info[1] != memory::kAccelFormatVersion) {
    return OptixError(OPTIX_ERROR_NOT_COMPATIBLE,
                      "info is not the relocation info of an acceleration of this Tessera "
                      "(optixAccelGetRelocationInfo)");
  }
  return absl::OkStatus();
}

// An instance build's children after relocation: the handles `input` gives, one per instance.
absl::Status RelocateInstances(HostDeviceMemory& m, CUdeviceptr target, const AccelHeader& h,
                               const OptixRelocateInput& input) {
  if (input.type != OPTIX_BUILD_INPUT_TYPE_INSTANCES &&
      input.type != OPTIX_BUILD_INPUT_TYPE_INSTANCE_POINTERS) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      "relocateInputs[0].type is not an instance type, for an instance build");
  }
  const OptixRelocateInputInstanceArray& ia = input.instanceArray;
  if (ia.numInstances != h.primitive_count) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("relocateInputs[0].instanceArray.numInstances is ",
                                   ia.numInstances, "; the build has ", h.primitive_count));
  }
  if (ia.numInstances == 0) return absl::OkStatus();
  const size_t bytes = sizeof(OptixTraversableHandle) * ia.numInstances;
  if (!m.IsAllocated(ia.traversableHandles, bytes)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      "relocateInputs[0].instanceArray.traversableHandles is not device memory "
                      "holding numInstances handles");
  }
  auto* base = reinterpret_cast<unsigned char*>(target);
  for (unsigned k = 0; k < ia.numInstances; ++k) {
    OptixTraversableHandle handle;
    std::memcpy(&handle, reinterpret_cast<const void*>(ia.traversableHandles + k * sizeof(handle)),
                sizeof(handle));
    std::memcpy(base + h.inputs_offset + k * memory::kInstanceBytes +
                    offsetof(OptixInstance, traversableHandle),
                &handle, sizeof(handle));
  }
  // The content hash names what workers build: new children are a new scene.
  const uint64_t hash = api::Hash64(base + sizeof(AccelHeader), h.total_size - sizeof(AccelHeader));
  std::memcpy(base + offsetof(AccelHeader, content_hash), &hash, sizeof(hash));
  m.MarkWritten(target, h.total_size);
  return absl::OkStatus();
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::HostDeviceMemory;
using tessera::optix7::OptixError;

extern "C" {

OptixResult optixAccelComputeMemoryUsage(OptixDeviceContext context,
                                         const OptixAccelBuildOptions* accelOptions,
                                         const OptixBuildInput* buildInputs,
                                         unsigned int numBuildInputs,
                                         OptixAccelBufferSizes* bufferSizes) {
  return Call("optixAccelComputeMemoryUsage").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(accelOptions, "accelOptions"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(buildInputs, "buildInputs"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(bufferSizes, "bufferSizes"); !s.ok()) return s;
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    absl::StatusOr<OptixAccelBufferSizes> sizes =
        tessera::optix7::AccelBufferSizes(**m, *accelOptions, buildInputs, numBuildInputs);
    if (!sizes.ok()) return sizes.status();
    *bufferSizes = *sizes;
    return absl::OkStatus();
  });
}

OptixResult optixAccelBuild(OptixDeviceContext context, CUstream stream,
                            const OptixAccelBuildOptions* accelOptions,
                            const OptixBuildInput* buildInputs, unsigned int numBuildInputs,
                            CUdeviceptr tempBuffer, size_t tempBufferSizeInBytes,
                            CUdeviceptr outputBuffer, size_t outputBufferSizeInBytes,
                            OptixTraversableHandle* outputHandle,
                            const OptixAccelEmitDesc* emittedProperties,
                            unsigned int numEmittedProperties) {
  (void)stream;  // every call finishes before it returns
  return Call("optixAccelBuild").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(accelOptions, "accelOptions"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(buildInputs, "buildInputs"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(outputHandle, "outputHandle"); !s.ok()) return s;
    if (numEmittedProperties > 0 && emittedProperties == nullptr) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE, "emittedProperties is null");
    }
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    HostDeviceMemory& memory = **m;
    const bool update = accelOptions->operation == OPTIX_BUILD_OPERATION_UPDATE;
    if (!update && accelOptions->operation != OPTIX_BUILD_OPERATION_BUILD) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("accelOptions->operation 0x",
                                     absl::Hex(static_cast<unsigned>(accelOptions->operation)),
                                     " is no OptixBuildOperation"));
    }
    if (update) {
      // An update rebuilds the descriptor in place from the new inputs, which OptiX allows only
      // for a build made with ALLOW_UPDATE.
      absl::StatusOr<const tessera::memory::AccelHeader*> old = tessera::optix7::Descriptor(
          memory, outputBuffer, "outputBuffer (OPTIX_BUILD_OPERATION_UPDATE)");
      if (!old.ok()) return old.status();
      if (((*old)->build_flags & OPTIX_BUILD_FLAG_ALLOW_UPDATE) == 0) {
        return OptixError(OPTIX_ERROR_INVALID_VALUE,
                          "OPTIX_BUILD_OPERATION_UPDATE of an acceleration built without "
                          "OPTIX_BUILD_FLAG_ALLOW_UPDATE");
      }
    }
    absl::StatusOr<OptixAccelBufferSizes> sizes =
        tessera::optix7::AccelBufferSizes(memory, *accelOptions, buildInputs, numBuildInputs);
    if (!sizes.ok()) return sizes.status();
    const size_t temp_needed = update ? sizes->tempUpdateSizeInBytes : sizes->tempSizeInBytes;
    if (tempBufferSizeInBytes < temp_needed || tempBuffer == 0 ||
        !memory.IsAllocated(tempBuffer, temp_needed)) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("tempBuffer 0x", absl::Hex(tempBuffer), " of ",
                                     tempBufferSizeInBytes, " bytes: the build needs ", temp_needed,
                                     " bytes of device memory (optixAccelComputeMemoryUsage)"));
    }
    for (unsigned i = 0; i < numEmittedProperties; ++i) {
      if (absl::Status s = tessera::optix7::CheckEmit(memory, emittedProperties[i],
                                                      absl::StrCat("emittedProperties[", i, "]"));
          !s.ok()) {
        return s;
      }
    }
    absl::StatusOr<OptixTraversableHandle> handle = tessera::optix7::BuildAccel(
        memory, *accelOptions, buildInputs, numBuildInputs, outputBuffer, outputBufferSizeInBytes);
    if (!handle.ok()) return handle.status();
    for (unsigned i = 0; i < numEmittedProperties; ++i) {
      if (absl::Status s = tessera::optix7::Emit(memory, *handle, emittedProperties[i]); !s.ok()) {
        return s;
      }
    }
    *outputHandle = *handle;
    return absl::OkStatus();
  });
}

OptixResult optixAccelEmitProperty(OptixDeviceContext context, CUstream stream,
                                   OptixTraversableHandle handle,
                                   const OptixAccelEmitDesc* emittedProperty) {
  (void)stream;
  return Call("optixAccelEmitProperty").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(emittedProperty, "emittedProperty"); !s.ok()) return s;
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    if (absl::Status s = tessera::optix7::CheckEmit(**m, *emittedProperty, "emittedProperty");
        !s.ok()) {
      return s;
    }
    return tessera::optix7::Emit(**m, handle, *emittedProperty);
  });
}

OptixResult optixAccelCompact(OptixDeviceContext context, CUstream stream,
                              OptixTraversableHandle inputHandle, CUdeviceptr outputBuffer,
                              size_t outputBufferSizeInBytes,
                              OptixTraversableHandle* outputHandle) {
  (void)stream;
  return Call("optixAccelCompact").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(outputHandle, "outputHandle"); !s.ok()) return s;
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    absl::StatusOr<const tessera::memory::AccelHeader*> h =
        tessera::optix7::Descriptor(**m, inputHandle, "inputHandle");
    if (!h.ok()) return h.status();
    const size_t size = (*h)->total_size;
    if (absl::Status s = tessera::optix7::CheckOutput(**m, outputBuffer, outputBufferSizeInBytes,
                                                      size, "outputBuffer");
        !s.ok()) {
      return s;
    }
    std::memmove(reinterpret_cast<void*>(outputBuffer), *h, size);
    (*m)->MarkWritten(outputBuffer, size);
    *outputHandle = outputBuffer;
    return absl::OkStatus();
  });
}

OptixResult optixAccelGetRelocationInfo(OptixDeviceContext context, OptixTraversableHandle handle,
                                        OptixRelocationInfo* info) {
  return Call("optixAccelGetRelocationInfo").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(info, "info"); !s.ok()) return s;
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    absl::StatusOr<const tessera::memory::AccelHeader*> h =
        tessera::optix7::Descriptor(**m, handle, "handle");
    if (!h.ok()) return h.status();
    info->info[0] = tessera::optix7::kRelocationMagic;
    info->info[1] = tessera::memory::kAccelFormatVersion;
    info->info[2] = static_cast<unsigned long long>((*h)->kind);
    info->info[3] = (*h)->total_size;
    return absl::OkStatus();
  });
}

OptixResult optixCheckRelocationCompatibility(OptixDeviceContext context,
                                              const OptixRelocationInfo* info, int* compatible) {
  return Call("optixCheckRelocationCompatibility").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(info, "info"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(compatible, "compatible"); !s.ok()) return s;
    *compatible = tessera::optix7::CheckRelocationInfo(*info).ok() ? 1 : 0;
    return absl::OkStatus();
  });
}

// The application has copied the acceleration to `targetAccel` (as OptiX requires); relocation
// only replaces an instance build's child handles.
OptixResult optixAccelRelocate(OptixDeviceContext context, CUstream stream,
                               const OptixRelocationInfo* info,
                               const OptixRelocateInput* relocateInputs, size_t numRelocateInputs,
                               CUdeviceptr targetAccel, size_t targetAccelSizeInBytes,
                               OptixTraversableHandle* targetHandle) {
  (void)stream;
  return Call("optixAccelRelocate").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(info, "info"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(targetHandle, "targetHandle"); !s.ok()) return s;
    if (absl::Status s = tessera::optix7::CheckRelocationInfo(*info); !s.ok()) return s;
    if (numRelocateInputs > 0 && relocateInputs == nullptr) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE, "relocateInputs is null");
    }
    absl::StatusOr<HostDeviceMemory*> m = tessera::optix7::Memory();
    if (!m.ok()) return m.status();
    if (absl::Status s = tessera::optix7::CheckOutput(**m, targetAccel, targetAccelSizeInBytes,
                                                      info->info[3], "targetAccel");
        !s.ok()) {
      return s;
    }
    absl::StatusOr<const tessera::memory::AccelHeader*> h =
        tessera::optix7::Descriptor(**m, targetAccel, "targetAccel (the copied acceleration)");
    if (!h.ok()) return h.status();
    if (static_cast<unsigned long long>((*h)->kind) != info->info[2] ||
        (*h)->total_size != info->info[3]) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        "targetAccel does not hold a copy of the acceleration `info` describes");
    }
    if ((*h)->kind == tessera::memory::AccelKind::kInstances) {
      if (numRelocateInputs != 1) {
        return OptixError(OPTIX_ERROR_INVALID_VALUE,
                          absl::StrCat("an instance build relocates with 1 relocate input (its "
                                       "instances' new handles); numRelocateInputs is ",
                                       numRelocateInputs));
      }
      if (absl::Status s =
              tessera::optix7::RelocateInstances(**m, targetAccel, **h, relocateInputs[0]);
          !s.ok()) {
        return s;
      }
    } else if (numRelocateInputs != 0 && numRelocateInputs != (*h)->input_count) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("numRelocateInputs is ", numRelocateInputs, "; the build has ",
                                     (*h)->input_count, " build inputs"));
    }
    *targetHandle = targetAccel;
    return absl::OkStatus();
  });
}

}  // extern "C"
