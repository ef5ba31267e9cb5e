#include "accel_build.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "accel_format.h"
#include "hash.h"
#include "host_device_memory.h"
#include "tessera/detail/half.h"
#include "tessera/optix7_ext.h"

namespace tessera::optix7 {
namespace {

using memory::AccelHeader;
using memory::AccelInput;
using memory::AccelKind;

constexpr size_t kTempBytes = 256;

uint64_t Align8(uint64_t n) { return (n + 7) / 8 * 8; }

absl::Status Invalid(unsigned input, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat("build input ", input, ": ", what));
}

// The bytes of one vertex in a format, 0 for an unknown format.
unsigned VertexBytes(OptixVertexFormat f) {
  switch (f) {
    case OPTIX_VERTEX_FORMAT_FLOAT3:
      return 12;
    case OPTIX_VERTEX_FORMAT_FLOAT2:
      return 8;
    case OPTIX_VERTEX_FORMAT_HALF3:
    case OPTIX_VERTEX_FORMAT_SNORM16_3:
      return 6;
    case OPTIX_VERTEX_FORMAT_HALF2:
    case OPTIX_VERTEX_FORMAT_SNORM16_2:
      return 4;
    default:
      return 0;
  }
}

// One vertex of format `f` at `p` as three floats.
void ReadVertex(const unsigned char* p, OptixVertexFormat f, float out[3]) {
  out[2] = 0.f;
  switch (f) {
    case OPTIX_VERTEX_FORMAT_FLOAT3:
    case OPTIX_VERTEX_FORMAT_FLOAT2:
      std::memcpy(out, p, f == OPTIX_VERTEX_FORMAT_FLOAT3 ? 12 : 8);
      return;
    case OPTIX_VERTEX_FORMAT_HALF3:
    case OPTIX_VERTEX_FORMAT_HALF2: {
      const int n = f == OPTIX_VERTEX_FORMAT_HALF3 ? 3 : 2;
      for (int i = 0; i < n; ++i) {
        uint16_t h;
        std::memcpy(&h, p + 2 * i, 2);
        out[i] = ::tessera::detail::HalfBitsToFloat(h);
      }
      return;
    }
    default: {  // SNORM16: max(v / 32767, -1), as graphics APIs define it
      const int n = f == OPTIX_VERTEX_FORMAT_SNORM16_3 ? 3 : 2;
      for (int i = 0; i < n; ++i) {
        int16_t v;
        std::memcpy(&v, p + 2 * i, 2);
        out[i] = std::fmax(static_cast<float>(v) / 32767.f, -1.f);
      }
    }
  }
}

// What one build input becomes in the descriptor.
struct InputPlan {
  const OptixBuildInput* in = nullptr;
  uint32_t primitives = 0, vertices = 0, sbt_records = 1;
  uint32_t vertex_stride = 0, index_stride = 0, sbt_stride = 0, aabb_stride = 0;
  uint32_t radius_stride = 0;  // spheres
  AccelInput record{};
};

struct Plan {
  AccelKind kind = AccelKind::kTriangles;
  std::vector<InputPlan> inputs;
  uint32_t instance_stride = 0;
  uint32_t keys = 1;  // motion keys: every vertex and box buffer comes `keys` times
  uint64_t primitives = 0;
  uint64_t total = 0;
  uint64_t motion_offset = 0;
};

// An extent of device memory the build reads: `count` elements `stride` apart, the last
// `element` bytes long, all in one live allocation.
absl::Status Readable(HostDeviceMemory& m, unsigned input, const char* what, CUdeviceptr p,
                      uint64_t count, uint64_t stride, uint64_t element) {
  if (count == 0) return absl::OkStatus();
  if (p == 0) return Invalid(input, absl::StrCat(what, " is null"));
  const uint64_t bytes = (count - 1) * stride + element;
  if (!m.IsAllocated(p, bytes)) {
    return Invalid(input, absl::StrCat(what, " (", bytes, " bytes at 0x", absl::Hex(p),
                                       ") does not lie in one cudaMalloc allocation"));
  }
  return absl::OkStatus();
}

// The SBT records and per-primitive SBT index offsets of triangles and custom primitives, which
// share these fields.
absl::Status PlanSbt(HostDeviceMemory& m, unsigned i, const unsigned int* flags,
                     unsigned int records, CUdeviceptr offsets, unsigned int offset_size,
                     unsigned int offset_stride, InputPlan& p) {
  if (records == 0) return Invalid(i, "numSbtRecords is 0 (at least 1)");
  if (flags == nullptr) return Invalid(i, "flags is null (one OptixGeometryFlags per SBT record)");
  p.sbt_records = records;
  if (records == 1) return absl::OkStatus();
  if (offset_size != 1 && offset_size != 2 && offset_size != 4) {
    return Invalid(i, absl::StrCat("sbtIndexOffsetSizeInBytes is ", offset_size, " with ", records,
                                   " SBT records (1, 2 or 4)"));
  }
  p.sbt_stride = offset_stride == 0 ? offset_size : offset_stride;
  if (p.sbt_stride < offset_size) return Invalid(i, "sbtIndexOffsetStrideInBytes is too small");
  return Readable(m, i, "sbtIndexOffsetBuffer", offsets, p.primitives, p.sbt_stride, offset_size);
}

// The per-key buffers of a motion build (vertexBuffers, aabbBuffers, radiusBuffers): `keys`
// pointers, none null, each `count` elements `stride` apart in one allocation.
absl::Status ReadableKeys(HostDeviceMemory& m, unsigned input, const char* what,
                          const CUdeviceptr* buffers, uint32_t keys, uint64_t count,
                          uint64_t stride, uint64_t element) {
  if (count == 0) return absl::OkStatus();
  if (buffers == nullptr) return Invalid(input, absl::StrCat(what, " is null"));
  for (uint32_t k = 0; k < keys; ++k) {
    const std::string name = absl::StrCat(what, "[", k, "]");
    if (buffers[k] == 0) {
      return Invalid(input,
                     absl::StrCat(name, " is null", keys > 1 ? " (one per motion key)" : ""));
    }
    if (absl::Status s = Readable(m, input, name.c_str(), buffers[k], count, stride, element);
        !s.ok()) {
      return s;
    }
  }
  return absl::OkStatus();
}

absl::Status PlanTriangles(HostDeviceMemory& m, unsigned i, uint32_t keys, InputPlan& p) {
  const OptixBuildInputTriangleArray& t = p.in->triangleArray;
  if (t.opacityMicromap.opacityMicromapArray != 0 ||
      t.displacementMicromap.displacementMicromapArray != 0) {
    return absl::UnimplementedError(
        absl::StrCat("build input ", i,
                     ": opacity and displacement micromaps are not supported on CPU devices"));
  }
  const unsigned vb = VertexBytes(t.vertexFormat);
  if (t.numVertices > 0 && vb == 0) {
    return Invalid(i, absl::StrCat("vertexFormat 0x", absl::Hex(t.vertexFormat), " is unknown"));
  }
  p.vertices = t.numVertices;
  p.vertex_stride = t.vertexStrideInBytes == 0 ? vb : t.vertexStrideInBytes;
  if (p.vertex_stride < vb) return Invalid(i, "vertexStrideInBytes is smaller than a vertex");
  if (absl::Status s = ReadableKeys(m, i, "vertexBuffers", t.vertexBuffers, keys, t.numVertices,
                                    p.vertex_stride, vb);
      !s.ok()) {
    return s;
  }
  if (t.indexFormat == OPTIX_INDICES_FORMAT_NONE) {
    if (t.numIndexTriplets != 0) return Invalid(i, "numIndexTriplets without an indexFormat");
    if (t.numVertices % 3 != 0) {
      return Invalid(i, absl::StrCat(t.numVertices, " vertices without indices (a multiple of 3)"));
    }
    p.primitives = t.numVertices / 3;
  } else {
    const unsigned ib = t.indexFormat == OPTIX_INDICES_FORMAT_UNSIGNED_INT3     ? 12
                        : t.indexFormat == OPTIX_INDICES_FORMAT_UNSIGNED_SHORT3 ? 6
                                                                                : 0;
    if (ib == 0) {
      return Invalid(i, absl::StrCat("indexFormat 0x", absl::Hex(t.indexFormat), " is unknown"));
    }
    p.index_stride = t.indexStrideInBytes == 0 ? ib : t.indexStrideInBytes;
    if (p.index_stride < ib) return Invalid(i, "indexStrideInBytes is smaller than a triplet");
    p.primitives = t.numIndexTriplets;
    if (absl::Status s =
            Readable(m, i, "indexBuffer", t.indexBuffer, p.primitives, p.index_stride, ib);
        !s.ok()) {
      return s;
    }
  }
  if (t.preTransform != 0) {
    if (t.transformFormat != OPTIX_TRANSFORM_FORMAT_MATRIX_FLOAT12) {
      return Invalid(i,
                     "preTransform without transformFormat OPTIX_TRANSFORM_FORMAT_MATRIX_FLOAT12");
    }
    if (absl::Status s = Readable(m, i, "preTransform", t.preTransform, 1, 48, 48); !s.ok()) {
      return s;
    }
  }
  return PlanSbt(m, i, t.flags, t.numSbtRecords, t.sbtIndexOffsetBuffer,
                 t.sbtIndexOffsetSizeInBytes, t.sbtIndexOffsetStrideInBytes, p);
}

absl::Status PlanCustom(HostDeviceMemory& m, unsigned i, uint32_t keys, InputPlan& p) {
  const OptixBuildInputCustomPrimitiveArray& c = p.in->customPrimitiveArray;
  p.primitives = c.numPrimitives;
  p.aabb_stride = c.strideInBytes == 0 ? sizeof(OptixAabb) : c.strideInBytes;
  if (p.aabb_stride < sizeof(OptixAabb) || p.aabb_stride % OPTIX_AABB_BUFFER_BYTE_ALIGNMENT != 0) {
    return Invalid(
        i, absl::StrCat("strideInBytes ", c.strideInBytes, " (at least 24, a multiple of 8)"));
  }
  if (absl::Status s = ReadableKeys(m, i, "aabbBuffers", c.aabbBuffers, keys, c.numPrimitives,
                                    p.aabb_stride, sizeof(OptixAabb));
      !s.ok()) {
    return s;
  }
  return PlanSbt(m, i, c.flags, c.numSbtRecords, c.sbtIndexOffsetBuffer,
                 c.sbtIndexOffsetSizeInBytes, c.sbtIndexOffsetStrideInBytes, p);
}

// Spheres: a centre (float3) and a radius per sphere and key; singleRadius: one radius per key.
absl::Status PlanSpheres(HostDeviceMemory& m, unsigned i, uint32_t keys, InputPlan& p) {
  const OptixBuildInputSphereArray& sp = p.in->sphereArray;
  p.primitives = p.vertices = sp.numVertices;
  p.vertex_stride = sp.vertexStrideInBytes == 0 ? 12 : sp.vertexStrideInBytes;
  if (p.vertex_stride < 12 || p.vertex_stride % 4 != 0) {
    return Invalid(i, absl::StrCat("vertexStrideInBytes ", sp.vertexStrideInBytes,
                                   " (at least 12, a multiple of 4)"));
  }
  p.radius_stride = sp.radiusStrideInBytes == 0 ? 4 : sp.radiusStrideInBytes;
  if (p.radius_stride < 4 || p.radius_stride % 4 != 0) {
    return Invalid(i, absl::StrCat("radiusStrideInBytes ", sp.radiusStrideInBytes,
                                   " (at least 4, a multiple of 4)"));
  }
  if (absl::Status s = ReadableKeys(m, i, "vertexBuffers", sp.vertexBuffers, keys, sp.numVertices,
                                    p.vertex_stride, 12);
      !s.ok()) {
    return s;
  }
  if (absl::Status s = ReadableKeys(m, i, "radiusBuffers", sp.radiusBuffers, keys,
                                    sp.singleRadius ? std::min(sp.numVertices, 1u) : sp.numVertices,
                                    p.radius_stride, 4);
      !s.ok()) {
    return s;
  }
  return PlanSbt(m, i, sp.flags, sp.numSbtRecords, sp.sbtIndexOffsetBuffer,
                 sp.sbtIndexOffsetSizeInBytes, sp.sbtIndexOffsetStrideInBytes, p);
}

absl::StatusOr<Plan> PlanBuild(HostDeviceMemory& m, const OptixAccelBuildOptions& options,
                               const OptixBuildInput* inputs, unsigned int count) {
  if (inputs == nullptr || count == 0) {
    return absl::InvalidArgumentError("no build inputs (buildInputs is null or numBuildInputs 0)");
  }
  Plan plan;
  // numKeys 0 or 1 builds without motion, ignoring the times and flags (guide 5.10.1).
  const OptixMotionOptions& motion = options.motionOptions;
  if (motion.numKeys > 1) {
    if (!(motion.timeBegin <= motion.timeEnd) || !std::isfinite(motion.timeBegin) ||
        !std::isfinite(motion.timeEnd)) {
      return absl::InvalidArgumentError(absl::StrCat("motionOptions: timeBegin ", motion.timeBegin,
                                                     " is after timeEnd ", motion.timeEnd,
                                                     " (or one is not finite)"));
    }
    if ((motion.flags & ~unsigned{OPTIX_MOTION_FLAG_START_VANISH | OPTIX_MOTION_FLAG_END_VANISH}) !=
        0) {
      return absl::InvalidArgumentError(
          absl::StrCat("motionOptions.flags 0x", absl::Hex(motion.flags), " has unknown bits"));
    }
    plan.keys = motion.numKeys;
  }
  if (options.operation != OPTIX_BUILD_OPERATION_BUILD &&
      options.operation != OPTIX_BUILD_OPERATION_UPDATE) {
    return absl::InvalidArgumentError(
        absl::StrCat("operation 0x", absl::Hex(options.operation), " is unknown"));
  }
  // OptixBuildFlags (bits 0-7) and Tessera's per-acceleration accuracy bits (tessera/optix7_ext.h).
  constexpr unsigned kKnownBuildFlags = 0xFFu | TESSERA_OPTIX_BUILD_FLAG_ROBUST |
                                        TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT |
                                        TESSERA_OPTIX_BUILD_FLAG_COMPACT;
  if ((options.buildFlags & ~kKnownBuildFlags) != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("buildFlags 0x", absl::Hex(options.buildFlags), " has bits 0x",
                     absl::Hex(options.buildFlags & ~kKnownBuildFlags),
                     " that no OptixBuildFlags or TESSERA_OPTIX_BUILD_FLAG_* value has"));
  }
  const OptixBuildInputType type = inputs[0].type;
  switch (type) {
    case OPTIX_BUILD_INPUT_TYPE_TRIANGLES:
      plan.kind = AccelKind::kTriangles;
      break;
    case OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES:
      plan.kind = AccelKind::kCustom;
      break;
    case OPTIX_BUILD_INPUT_TYPE_INSTANCES:
    case OPTIX_BUILD_INPUT_TYPE_INSTANCE_POINTERS:
      plan.kind = AccelKind::kInstances;
      break;
    case OPTIX_BUILD_INPUT_TYPE_SPHERES:
      plan.kind = AccelKind::kSpheres;
      break;
    case OPTIX_BUILD_INPUT_TYPE_CURVES:
      return absl::UnimplementedError(
          "curves are not supported yet (spheres, triangles and custom "
          "primitives are)");
    default:
      return Invalid(0, absl::StrCat("type 0x", absl::Hex(type), " is unknown"));
  }
  for (unsigned i = 1; i < count; ++i) {
    if (inputs[i].type != type) {
      return Invalid(i, "its type differs from build input 0's (one type per build)");
    }
  }
  uint64_t at = sizeof(AccelHeader);
  if (plan.kind == AccelKind::kInstances) {
    if (count != 1) return Invalid(1, "an instance build takes exactly one build input");
    const OptixBuildInputInstanceArray& ia = inputs[0].instanceArray;
    plan.primitives = ia.numInstances;
    if (type == OPTIX_BUILD_INPUT_TYPE_INSTANCES) {
      plan.instance_stride = ia.instanceStride == 0 ? sizeof(OptixInstance) : ia.instanceStride;
      if (plan.instance_stride < sizeof(OptixInstance) ||
          plan.instance_stride % OPTIX_INSTANCE_BYTE_ALIGNMENT != 0) {
        return Invalid(0, "instanceStride (at least 80, a multiple of 16)");
      }
      if (absl::Status s = Readable(m, 0, "instances", ia.instances, ia.numInstances,
                                    plan.instance_stride, sizeof(OptixInstance));
          !s.ok()) {
        return s;
      }
    } else {
      if (absl::Status s = Readable(m, 0, "instances (pointers)", ia.instances, ia.numInstances,
                                    sizeof(CUdeviceptr), sizeof(CUdeviceptr));
          !s.ok()) {
        return s;
      }
      const auto* pointers = reinterpret_cast<const CUdeviceptr*>(ia.instances);
      for (unsigned k = 0; k < ia.numInstances; ++k) {
        if (absl::Status s = Readable(m, 0, absl::StrCat("instance pointer ", k).c_str(),
                                      pointers[k], 1, sizeof(OptixInstance), sizeof(OptixInstance));
            !s.ok()) {
          return s;
        }
      }
    }
    plan.total = at + plan.primitives * memory::kInstanceBytes;
    if (plan.keys > 1) {
      plan.motion_offset = Align8(plan.total);
      plan.total = plan.motion_offset + sizeof(memory::AccelMotion);
    }
    return plan;
  }
  plan.inputs.resize(count);
  at += Align8(sizeof(AccelInput) * count);
  for (unsigned i = 0; i < count; ++i) {
    InputPlan& p = plan.inputs[i];
    p.in = &inputs[i];
    absl::Status s = plan.kind == AccelKind::kTriangles ? PlanTriangles(m, i, plan.keys, p)
                     : plan.kind == AccelKind::kSpheres ? PlanSpheres(m, i, plan.keys, p)
                                                        : PlanCustom(m, i, plan.keys, p);
    if (!s.ok()) return s;
    AccelInput& r = p.record;
    r.primitive_count = p.primitives;
    r.primitive_index_offset =
        plan.kind == AccelKind::kTriangles ? inputs[i].triangleArray.primitiveIndexOffset
        : plan.kind == AccelKind::kSpheres ? inputs[i].sphereArray.primitiveIndexOffset
                                           : inputs[i].customPrimitiveArray.primitiveIndexOffset;
    r.num_sbt_records = p.sbt_records;
    if (plan.kind == AccelKind::kTriangles) {
      r.vertex_count = p.vertices;
      r.vertices_offset = at;
      at += Align8(12ull * p.vertices * plan.keys);
      r.indices_offset = at;
      at += Align8(12ull * p.primitives);
    } else if (plan.kind == AccelKind::kSpheres) {
      r.vertex_count = p.vertices;
      r.vertices_offset = at;
      at += Align8(16ull * p.vertices * plan.keys);
    } else {
      r.aabbs_offset = at;
      at += Align8(24ull * p.primitives * plan.keys);
    }
    r.flags_offset = at;
    at += Align8(4ull * p.sbt_records);
    if (p.sbt_records > 1) {
      r.sbt_index_offsets_offset = at;
      at += Align8(4ull * p.primitives);
    }
    plan.primitives += p.primitives;
  }
  if (plan.keys > 1) {
    plan.motion_offset = at;
    at += sizeof(memory::AccelMotion);
  }
  plan.total = at;
  return plan;
}

// Writes input `i` of `plan` into `out` (the descriptor being made), `keys` motion keys.
absl::Status WriteInput(const InputPlan& p, unsigned i, AccelKind kind, uint32_t keys,
                        unsigned char* out) {
  const AccelInput& r = p.record;
  if (kind == AccelKind::kTriangles) {
    const OptixBuildInputTriangleArray& t = p.in->triangleArray;
    float m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (t.preTransform != 0) std::memcpy(m, reinterpret_cast<const void*>(t.preTransform), 48);
    for (uint32_t key = 0; key < keys && p.vertices > 0; ++key) {
      auto* v = reinterpret_cast<float*>(out + r.vertices_offset) + 3ull * p.vertices * key;
      const auto* src = reinterpret_cast<const unsigned char*>(t.vertexBuffers[key]);
      for (uint32_t k = 0; k < p.vertices; ++k) {
        float x[3];
        ReadVertex(src + uint64_t{k} * p.vertex_stride, t.vertexFormat, x);
        for (int row = 0; row < 3; ++row) {
          v[3 * k + row] =
              m[4 * row] * x[0] + m[4 * row + 1] * x[1] + m[4 * row + 2] * x[2] + m[4 * row + 3];
        }
      }
    }
    auto* idx = reinterpret_cast<uint32_t*>(out + r.indices_offset);
    const auto* ib = reinterpret_cast<const unsigned char*>(t.indexBuffer);
    for (uint32_t k = 0; k < p.primitives; ++k) {
      for (int c = 0; c < 3; ++c) {
        uint32_t index = 3 * k + c;
        if (t.indexFormat == OPTIX_INDICES_FORMAT_UNSIGNED_INT3) {
          std::memcpy(&index, ib + uint64_t{k} * p.index_stride + 4 * c, 4);
        } else if (t.indexFormat == OPTIX_INDICES_FORMAT_UNSIGNED_SHORT3) {
          uint16_t s;
          std::memcpy(&s, ib + uint64_t{k} * p.index_stride + 2 * c, 2);
          index = s;
        }
        if (index >= p.vertices) {
          return Invalid(i,
                         absl::StrCat("triangle ", k, " uses vertex ", index, " of ", p.vertices));
        }
        idx[3 * k + c] = index;
      }
    }
  } else if (kind == AccelKind::kSpheres) {
    const OptixBuildInputSphereArray& sp = p.in->sphereArray;
    for (uint32_t key = 0; key < keys && p.primitives > 0; ++key) {
      auto* v = reinterpret_cast<float*>(out + r.vertices_offset) + 4ull * p.primitives * key;
      const auto* centres = reinterpret_cast<const unsigned char*>(sp.vertexBuffers[key]);
      const auto* radii = reinterpret_cast<const unsigned char*>(sp.radiusBuffers[key]);
      for (uint32_t k = 0; k < p.primitives; ++k) {
        std::memcpy(v + 4ull * k, centres + uint64_t{k} * p.vertex_stride, 12);
        std::memcpy(v + 4ull * k + 3, radii + (sp.singleRadius ? 0 : uint64_t{k} * p.radius_stride),
                    4);
        if (!(v[4ull * k + 3] >= 0.f)) {
          return Invalid(i, absl::StrCat("sphere ", k, " has radius ", v[4ull * k + 3]));
        }
      }
    }
  } else {
    const OptixBuildInputCustomPrimitiveArray& c = p.in->customPrimitiveArray;
    for (uint32_t key = 0; key < keys && p.primitives > 0; ++key) {
      const auto* src = reinterpret_cast<const unsigned char*>(c.aabbBuffers[key]);
      unsigned char* dst = out + r.aabbs_offset + 24ull * p.primitives * key;
      for (uint32_t k = 0; k < p.primitives; ++k) {
        std::memcpy(dst + 24ull * k, src + uint64_t{k} * p.aabb_stride, 24);
      }
    }
  }
  const unsigned int* flags = kind == AccelKind::kTriangles ? p.in->triangleArray.flags
                              : kind == AccelKind::kSpheres ? p.in->sphereArray.flags
                                                            : p.in->customPrimitiveArray.flags;
  std::memcpy(out + r.flags_offset, flags, 4ull * p.sbt_records);
  if (p.sbt_records > 1) {
    const CUdeviceptr base =
        kind == AccelKind::kTriangles ? p.in->triangleArray.sbtIndexOffsetBuffer
        : kind == AccelKind::kSpheres ? p.in->sphereArray.sbtIndexOffsetBuffer
                                      : p.in->customPrimitiveArray.sbtIndexOffsetBuffer;
    const unsigned size =
        kind == AccelKind::kTriangles ? p.in->triangleArray.sbtIndexOffsetSizeInBytes
        : kind == AccelKind::kSpheres ? p.in->sphereArray.sbtIndexOffsetSizeInBytes
                                      : p.in->customPrimitiveArray.sbtIndexOffsetSizeInBytes;
    auto* offsets = reinterpret_cast<uint32_t*>(out + r.sbt_index_offsets_offset);
    for (uint32_t k = 0; k < p.primitives; ++k) {
      uint32_t value = 0;
      std::memcpy(&value, reinterpret_cast<const unsigned char*>(base) + uint64_t{k} * p.sbt_stride,
                  size);  // little-endian: the low bytes
      if (value >= p.sbt_records) {
        return Invalid(i, absl::StrCat("primitive ", k, " has SBT index offset ", value, " of ",
                                       p.sbt_records, " SBT records"));
      }
      offsets[k] = value;
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<OptixAccelBufferSizes> AccelBufferSizes(HostDeviceMemory& memory,
                                                       const OptixAccelBuildOptions& options,
                                                       const OptixBuildInput* inputs,
                                                       unsigned int count) {
  absl::StatusOr<Plan> plan = PlanBuild(memory, options, inputs, count);
  if (!plan.ok()) return plan.status();
  OptixAccelBufferSizes sizes{};
  sizes.outputSizeInBytes = plan->total;
  sizes.tempSizeInBytes = kTempBytes;
  sizes.tempUpdateSizeInBytes = kTempBytes;
  return sizes;
}

absl::StatusOr<OptixTraversableHandle> BuildAccel(HostDeviceMemory& memory,
                                                  const OptixAccelBuildOptions& options,
                                                  const OptixBuildInput* inputs, unsigned int count,
                                                  CUdeviceptr output, size_t output_size) {
  absl::StatusOr<Plan> plan = PlanBuild(memory, options, inputs, count);
  if (!plan.ok()) return plan.status();
  if (output == 0 || output % OPTIX_ACCEL_BUFFER_BYTE_ALIGNMENT != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("outputBuffer 0x", absl::Hex(output), " is null or not 128-byte aligned"));
  }
  if (output_size < plan->total || !memory.IsAllocated(output, plan->total)) {
    return absl::InvalidArgumentError(absl::StrCat("outputBuffer holds ", output_size,
                                                   " bytes in its allocation, the build needs ",
                                                   plan->total, " (optixAccelComputeMemoryUsage)"));
  }
  std::vector<unsigned char> bytes(plan->total, 0);
  AccelHeader& h = *reinterpret_cast<AccelHeader*>(bytes.data());
  std::memcpy(h.magic, memory::kAccelMagic, sizeof(h.magic));
  h.version = memory::kAccelFormatVersion;
  h.kind = plan->kind;
  h.total_size = plan->total;
  h.build_flags = options.buildFlags;
  h.primitive_count = plan->primitives;
  h.inputs_offset = sizeof(AccelHeader);
  if (plan->kind == AccelKind::kInstances) {
    h.input_count = 1;
    const OptixBuildInputInstanceArray& ia = inputs[0].instanceArray;
    for (unsigned k = 0; k < ia.numInstances; ++k) {
      const void* src =
          inputs[0].type == OPTIX_BUILD_INPUT_TYPE_INSTANCES
              ? reinterpret_cast<const void*>(ia.instances + uint64_t{k} * plan->instance_stride)
              : reinterpret_cast<const void*>(
                    reinterpret_cast<const CUdeviceptr*>(ia.instances)[k]);
      std::memcpy(bytes.data() + h.inputs_offset + k * memory::kInstanceBytes, src,
                  memory::kInstanceBytes);
    }
  } else {
    h.input_count = count;
    for (unsigned i = 0; i < count; ++i) {
      AccelInput record = plan->inputs[i].record;
      // Workers refit the scene they built of the same buffer instead of building a new one.
      if (options.operation == OPTIX_BUILD_OPERATION_UPDATE)
        record.flags |= memory::kAccelInputUpdate;
      std::memcpy(bytes.data() + h.inputs_offset + i * sizeof(AccelInput), &record,
                  sizeof(AccelInput));
      if (absl::Status s = WriteInput(plan->inputs[i], i, plan->kind, plan->keys, bytes.data());
          !s.ok()) {
        return s;
      }
    }
  }
  if (plan->keys > 1) {
    h.motion_offset = plan->motion_offset;
    const memory::AccelMotion motion{plan->keys, options.motionOptions.flags,
                                     options.motionOptions.timeBegin,
                                     options.motionOptions.timeEnd};
    std::memcpy(bytes.data() + plan->motion_offset, &motion, sizeof(motion));
  }
  h.content_hash =
      api::Hash64(bytes.data() + sizeof(AccelHeader), bytes.size() - sizeof(AccelHeader));
  std::memcpy(reinterpret_cast<void*>(output), bytes.data(), bytes.size());
  memory.MarkWritten(output, bytes.size());
  return static_cast<OptixTraversableHandle>(output);
}

}  // namespace tessera::optix7
