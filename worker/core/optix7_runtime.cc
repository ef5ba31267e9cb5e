// The TesseraOptix7Runtime table that OptiX 7 program modules call through: launch, ray, hit,
// transform, primitive-data, exception and callable queries of the running program, answered from
// the calling thread's state (optix7_thread.h). Tracing lives in optix7_trace.cc, exceptions and
// callables in optix7_calls.cc.
#include <dlfcn.h>

#include <cstring>

#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "optix7_atomics.h"
#include "optix7_engine.h"
#include "optix7_module_init.h"
#include "optix7_thread.h"
#include "optix_types.h"

namespace tessera::worker {
namespace {

constexpr unsigned kTraversalKinds = KindBit(Optix7Kind::kIntersection) |
                                     KindBit(Optix7Kind::kAnyHit) |
                                     KindBit(Optix7Kind::kClosestHit) | KindBit(Optix7Kind::kMiss);
constexpr unsigned kHitKinds = KindBit(Optix7Kind::kIntersection) | KindBit(Optix7Kind::kAnyHit) |
                               KindBit(Optix7Kind::kClosestHit);

// The ray the running program serves (callables see their caller's).
Optix7Frame& FrameOf(Optix7Thread& ts, const char* call) {
  if (ts.ctx.frame == nullptr) Fail(ts, call, "the program serves no ray");
  return *ts.ctx.frame;
}

// The hit (or primitive) the running program sees.
const Optix7Hit& HitOf(Optix7Thread& ts, const char* call) {
  if (ts.ctx.hit == nullptr) Fail(ts, call, "the program has no hit or primitive");
  return *ts.ctx.hit;
}

void LaunchIndex(unsigned int out[3]) {
  const Optix7Thread& ts = Optix7TS();
  for (int i = 0; i < 3; ++i) out[i] = ts.index[i];
}

void LaunchDimensions(unsigned int out[3]) {
  const Optix7Thread& ts = Optix7TS();
  for (int i = 0; i < 3; ++i) out[i] = ts.dims[i];
}

CUdeviceptr SbtDataPointer() {
  const Optix7Thread& ts = Optix7TS();
  return ts.ctx.record != nullptr ? ts.ctx.record->data : 0;
}

unsigned int GetPayload(unsigned int index) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Frame& f = FrameOf(ts, "optixGetPayload");
  if (index >= 32) Fail(ts, "optixGetPayload", absl::StrCat("payload index ", index));
  return f.payload[index];
}

// Values past those the trace passed are kept for the ray's programs and dropped at its end, as
// OptiX drops what a pipeline's numPayloadValues allows but optixTrace did not pass.
void SetPayload(unsigned int index, unsigned int value) {
  Optix7Thread& ts = Optix7TS();
  Optix7Frame& f = FrameOf(ts, "optixSetPayload");
  if (index >= 32) Fail(ts, "optixSetPayload", absl::StrCat("payload index ", index));
  f.payload[index] = value;
}

// Payload types only restrict which values a program may touch, which nvcc checks; the engine
// gives every program all 32.
void SetPayloadTypes(unsigned int) {}

unsigned int UndefinedValue() { return 0; }  // a fixed value: output stays deterministic

// `v` (a point, w = 1, or a vector) through 3x4 row-major `m`.
void Apply(const float m[12], const float v[3], float w, float out[3]) {
  for (int r = 0; r < 3; ++r) {
    out[r] = m[r * 4] * v[0] + m[r * 4 + 1] * v[1] + m[r * 4 + 2] * v[2] + m[r * 4 + 3] * w;
  }
}

// The running program's transform between world and object space: the product of its hit's
// transform list at the ray's time, identity for a GAS traced directly and for programs without a
// hit.
const float* TransformOf(const Optix7Thread& ts, bool to_world) {
  const Optix7Hit* h = ts.ctx.hit;
  if (h == nullptr || h->path.size == 0) return kIdentity3x4;
  return to_world ? h->path.to_world : h->path.to_object;
}

void RayVector(unsigned int which, float out[3]) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Frame& f = FrameOf(ts, "optixGet*Ray*");
  const bool origin =
      which == TESSERA_OPTIX7_WORLD_RAY_ORIGIN || which == TESSERA_OPTIX7_OBJECT_RAY_ORIGIN;
  const float* v = origin ? f.ray.origin : f.ray.direction;
  if (which == TESSERA_OPTIX7_WORLD_RAY_ORIGIN || which == TESSERA_OPTIX7_WORLD_RAY_DIRECTION) {
    std::memcpy(out, v, 3 * sizeof(float));
    return;
  }
  if (which > TESSERA_OPTIX7_OBJECT_RAY_DIRECTION) {
    Fail(ts, "optixGet*Ray*", absl::StrCat("unknown ray vector ", which));
  }
  Apply(TransformOf(ts, false), v, origin ? 1.f : 0.f, out);
}

float RayFloat(unsigned int which) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Frame& f = FrameOf(ts, "optixGetRayTmin/Tmax/Time");
  switch (which) {
    case TESSERA_OPTIX7_RAY_TMIN:
      return f.ray.tmin;
    case TESSERA_OPTIX7_RAY_TMAX:
      // Guide 11.2: in intersection programs the closest hit so far, in any-hit programs the
      // candidate's distance, in closest-hit programs the hit's, in miss programs tmax.
      switch (ts.ctx.kind) {
        case Optix7Kind::kIntersection:
          return f.embree != nullptr ? f.embree->ray.tfar : f.ray.tmax;
        case Optix7Kind::kAnyHit:
        case Optix7Kind::kClosestHit:
          return ts.ctx.hit->t;
        default:
          return ts.ctx.hit != nullptr ? ts.ctx.hit->t : f.ray.tmax;
      }
    case TESSERA_OPTIX7_RAY_TIME:
      return f.ray.ray_time;
    default:
      Fail(ts, "optixGetRay*", absl::StrCat("unknown ray value ", which));
  }
}

unsigned int StateUint(unsigned int which) {
  Optix7Thread& ts = Optix7TS();
  switch (which) {
    case TESSERA_OPTIX7_RAY_FLAGS:
      return FrameOf(ts, "optixGetRayFlags").ray.ray_flags;
    case TESSERA_OPTIX7_RAY_VISIBILITY_MASK:
      return FrameOf(ts, "optixGetRayVisibilityMask").ray.visibility_mask;
    case TESSERA_OPTIX7_PRIMITIVE_INDEX:
      return HitOf(ts, "optixGetPrimitiveIndex").primitive;
    case TESSERA_OPTIX7_INSTANCE_ID: {
      // Guide 11.7: ~0u when no instance was visited on the way to the primitive.
      const Optix7Hit& h = HitOf(ts, "optixGetInstanceId");
      return h.instance != nullptr ? h.instance->id : ~0u;
    }
    case TESSERA_OPTIX7_INSTANCE_INDEX:
      return HitOf(ts, "optixGetInstanceIndex").instance_index;
    case TESSERA_OPTIX7_SBT_GAS_INDEX:
      return HitOf(ts, "optixGetSbtGASIndex").sbt_gas_index;
    case TESSERA_OPTIX7_HIT_KIND:
      CheckKind(ts, KindBit(Optix7Kind::kAnyHit) | KindBit(Optix7Kind::kClosestHit),
                "optixGetHitKind");
      HitOf(ts, "optixGetHitKind");
      return Optix7HitKind(*ts.ctx.frame, *ts.ctx.hit);
    case TESSERA_OPTIX7_TRANSFORM_LIST_SIZE:
      return ts.ctx.hit != nullptr ? ts.ctx.hit->path.size : 0;
    default:
      Fail(ts, "optixGet*", absl::StrCat("unknown state value ", which));
  }
}

// Guide 11.5: 0xFE and 0xFF are triangle faces, kOptix7SphereFrontFace and BackFace spheres';
// 0..127 are custom primitives' own kinds; the lowest bit says the face (0 front) for all.
unsigned int HitKindQuery(unsigned int hit_kind, unsigned int what) {
  if (what == TESSERA_OPTIX7_HIT_KIND_PRIMITIVE_TYPE) {
    if (hit_kind == kOptix7SphereFrontFace || hit_kind == kOptix7SphereBackFace) {
      return OPTIX_PRIMITIVE_TYPE_SPHERE;
    }
    return hit_kind == OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE ||
                   hit_kind == OPTIX_HIT_KIND_TRIANGLE_BACK_FACE
               ? OPTIX_PRIMITIVE_TYPE_TRIANGLE
               : OPTIX_PRIMITIVE_TYPE_CUSTOM;
  }
  return (hit_kind & 1u) == 0 ? 1 : 0;
}

void TriangleBarycentrics(float out[2]) {
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kAnyHit) | KindBit(Optix7Kind::kClosestHit),
            "optixGetTriangleBarycentrics");
  const Optix7Hit& h = HitOf(ts, "optixGetTriangleBarycentrics");
  std::memcpy(out, h.attributes, 2 * sizeof(float));
}

[[noreturn]] void NotBuilt(const char* call, const char* why) {
  Fail(Optix7TS(), call, absl::StrCat("not supported yet: ", why));
}

float CurveParameter() { NotBuilt("optixGetCurveParameter", "Tessera builds no curves"); }
void RibbonParameters(float[2]) {
  NotBuilt("optixGetRibbonParameters", "Tessera builds no curves");
}

unsigned int GetAttribute(unsigned int index) {
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kAnyHit) | KindBit(Optix7Kind::kClosestHit),
            "optixGetAttribute");
  if (index >= 8) Fail(ts, "optixGetAttribute", absl::StrCat("attribute index ", index));
  return HitOf(ts, "optixGetAttribute").attributes[index];
}

template <typename T>
T Read(uint64_t address) {
  T v;
  std::memcpy(&v, reinterpret_cast<const void*>(address), sizeof(v));
  return v;
}

// Guide 11.14: errors of optixGetTriangleVertexData and optixGetInstanceTraversableFromIAS.
[[noreturn]] void RaiseArgument(Optix7Thread& ts, int code, const std::string& what) {
  Optix7Exception e;
  e.code = code;
  Raise(ts, e, what);
}

// optixGetTriangleVertexData and optixGetSphereData: the primitive at `time` (the GAS's keys
// interpolated, time clamped to its range).
void PrimitiveData(OptixPrimitiveType type, OptixTraversableHandle gas, unsigned int prim,
                   unsigned int sbt_gas_index, float time, float* out) {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  const bool sphere = type == OPTIX_PRIMITIVE_TYPE_SPHERE;
  if (type != OPTIX_PRIMITIVE_TYPE_TRIANGLE && !sphere) {
    NotBuilt("optixGet*VertexData", "Tessera builds no curves");
  }
  const char* call = sphere ? "optixGetSphereData" : "optixGetTriangleVertexData";
  const Optix7Scene* s = SceneOf(ts, gas, call);
  if (s->kind != (sphere ? memory::AccelKind::kSpheres : memory::AccelKind::kTriangles)) {
    RaiseArgument(ts, OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_0,
                  absl::StrCat(call, ": 0x", absl::Hex(gas), " is no ",
                               sphere ? "sphere" : "triangle", " GAS"));
  }
  // The build input whose SBT records include sbt_gas_index (guide 7.3.2).
  size_t input = 0;
  while (input + 1 < s->sbt_bases.size() && s->sbt_bases[input + 1] <= sbt_gas_index) ++input;
  if (input + 1 >= s->sbt_bases.size()) {
    RaiseArgument(ts, OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_2,
                  absl::StrCat(call, ": SBT-GAS index ", sbt_gas_index, " past the GAS's ",
                               s->sbt_bases.back(), " records"));
  }
  const auto* header = reinterpret_cast<const memory::AccelHeader*>(gas);
  const memory::AccelInput in =
      Read<memory::AccelInput>(gas + header->inputs_offset + input * sizeof(memory::AccelInput));
  const uint64_t local = uint64_t{prim} - in.primitive_index_offset;
  if (prim < in.primitive_index_offset || local >= in.primitive_count) {
    RaiseArgument(ts, OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_1,
                  absl::StrCat(call, ": primitive ", prim, " is not in build input ", input));
  }
  const float normalized = s->motion.Normalized(time);
  if (sphere) {
    Optix7Vertex(gas, in, *s, static_cast<uint32_t>(local), normalized, 4, out);
    return;
  }
  uint32_t idx[3];
  std::memcpy(idx, reinterpret_cast<const void*>(gas + in.indices_offset + 12 * local),
              sizeof(idx));
  for (int k = 0; k < 3; ++k) Optix7Vertex(gas, in, *s, idx[k], normalized, 3, out + 3 * k);
}

void RibbonNormal(OptixTraversableHandle, unsigned int, unsigned int, float, const float[2],
                  float[3]) {
  NotBuilt("optixGetRibbonNormal", "Tessera builds no curves");
}
void MicroTriangleVertexData(float[9]) {
  NotBuilt("optixGetMicroTriangleVertexData", "Tessera builds no displaced micro-meshes");
}
void MicroTriangleBarycentricsData(float[6]) {
  NotBuilt("optixGetMicroTriangleBarycentricsData", "Tessera builds no displaced micro-meshes");
}

OptixTraversableHandle GasTraversableHandle() {
  Optix7Thread& ts = Optix7TS();
  return HitOf(ts, "optixGetGASTraversableHandle").gas;
}

// The GAS's motion options: a GAS built without motion has one step, from time 0 to 0.
float GasMotionTime(OptixTraversableHandle gas, int end) {
  const Optix7Scene* s = SceneOf(Optix7TS(), gas, "optixGetGASMotionTime*");
  if (!s->motion.moves()) return 0.f;
  return end ? s->motion.end : s->motion.begin;
}
unsigned int GasMotionStepCount(OptixTraversableHandle gas) {
  return SceneOf(Optix7TS(), gas, "optixGetGASMotionStepCount")->motion.keys;
}

// An instance's handle in a transform list is the address of its OptixInstance record in the
// IAS descriptor, which optixGetInstance*FromHandle read like OptiX's.
uint64_t InstanceRecord(uint64_t ias, uint32_t index) {
  const auto* header = reinterpret_cast<const memory::AccelHeader*>(ias);
  return ias + header->inputs_offset + uint64_t{index} * memory::kInstanceBytes;
}

OptixTraversableHandle TransformListHandle(unsigned int index) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Hit& h = HitOf(ts, "optixGetTransformListHandle");
  if (index >= h.path.size) {
    Fail(ts, "optixGetTransformListHandle",
         absl::StrCat("index ", index, " past the transform list's ", h.path.size, " entries"));
  }
  return h.path.handles[index];
}

// The instance whose record is at `handle`: one of the running program's transform list, or one
// of the root IAS's; null when neither.
const Optix7Scene::Instance* InstanceAt(const Optix7Thread& ts, uint64_t handle) {
  if (const Optix7Hit* h = ts.ctx.hit; h != nullptr) {
    for (uint32_t i = 0; i < h->path.size; ++i) {
      if (h->path.handles[i] == handle && h->path.instances[i] != nullptr) {
        return h->path.instances[i];
      }
    }
  }
  const Optix7Frame* f = ts.ctx.frame;
  if (f == nullptr || f->root == nullptr || f->root->kind != memory::AccelKind::kInstances) {
    return nullptr;
  }
  const uint64_t first = InstanceRecord(f->root_handle, 0);
  if (handle < first || (handle - first) % memory::kInstanceBytes != 0) return nullptr;
  const uint64_t k = (handle - first) / memory::kInstanceBytes;
  return k < f->root->instances.size() ? &f->root->instances[k] : nullptr;
}

OptixTransformType TransformTypeFromHandle(OptixTraversableHandle handle) {
  const uint32_t tag = TransformTag(handle);
  if (tag >= OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM &&
      tag <= OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM) {
    return static_cast<OptixTransformType>(tag);
  }
  return InstanceAt(Optix7TS(), handle) != nullptr ? OPTIX_TRANSFORM_TYPE_INSTANCE
                                                   : OPTIX_TRANSFORM_TYPE_NONE;
}

const Optix7Scene::Instance& InstanceOrFail(Optix7Thread& ts, uint64_t handle, const char* call) {
  const Optix7Scene::Instance* inst = InstanceAt(ts, handle);
  if (inst == nullptr) {
    Fail(
        ts, call,
        absl::StrCat("0x", absl::Hex(handle),
                     " is no instance of the traced IAS (optixGetTransformListHandle gives them)"));
  }
  return *inst;
}

const void* TransformDataFromHandle(OptixTraversableHandle handle, unsigned int what) {
  Optix7Thread& ts = Optix7TS();
  switch (what) {
    case TESSERA_OPTIX7_INSTANCE_TRANSFORM:
      return InstanceOrFail(ts, handle, "optixGetInstanceTransformFromHandle").to_world;
    case TESSERA_OPTIX7_INSTANCE_INVERSE_TRANSFORM:
      return InstanceOrFail(ts, handle, "optixGetInstanceInverseTransformFromHandle").to_object;
    default: {
      // The traversable itself, in device memory (the same address on every device); null for
      // a handle of another type, as OptiX leaves that undefined.
      const uint32_t want = what == TESSERA_OPTIX7_STATIC_TRANSFORM
                                ? OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM
                            : what == TESSERA_OPTIX7_MATRIX_MOTION_TRANSFORM
                                ? OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM
                                : OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM;
      if (TransformTag(handle) != want) return nullptr;
      return reinterpret_cast<const void*>(TransformAddress(handle));
    }
  }
}

unsigned int InstanceIdFromHandle(OptixTraversableHandle handle) {
  Optix7Thread& ts = Optix7TS();
  return InstanceOrFail(ts, handle, "optixGetInstanceIdFromHandle").id;
}

OptixTraversableHandle InstanceChildFromHandle(OptixTraversableHandle handle) {
  Optix7Thread& ts = Optix7TS();
  return InstanceOrFail(ts, handle, "optixGetInstanceChildFromHandle").child;
}

OptixTraversableHandle InstanceTraversableFromIas(OptixTraversableHandle ias, unsigned int index) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Scene* s = SceneOf(ts, ias, "optixGetInstanceTraversableFromIAS");
  if (s->kind != memory::AccelKind::kInstances) {
    RaiseArgument(
        ts, OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_0,
        absl::StrCat("optixGetInstanceTraversableFromIAS: 0x", absl::Hex(ias), " is no IAS"));
  }
  if (index >= s->instances.size()) {
    RaiseArgument(ts, OPTIX_EXCEPTION_CODE_INVALID_VALUE_ARGUMENT_1,
                  absl::StrCat("optixGetInstanceTraversableFromIAS: instance ", index, " of ",
                               s->instances.size()));
  }
  return s->instances[index].child;
}

void CurrentTransform(unsigned int direction, float out[12]) {
  const Optix7Thread& ts = Optix7TS();
  std::memcpy(out, TransformOf(ts, direction == TESSERA_OPTIX7_OBJECT_TO_WORLD),
              12 * sizeof(float));
}

void Transform(unsigned int kind, unsigned int direction, const float in[3], float out[3]) {
  Optix7Thread& ts = Optix7TS();
  const bool to_world = direction == TESSERA_OPTIX7_OBJECT_TO_WORLD;
  if (kind == TESSERA_OPTIX7_TRANSFORM_NORMAL) {
    // Normals go through the inverse transpose of the matrix that moves points.
    const float* inv = TransformOf(ts, !to_world);
    for (int i = 0; i < 3; ++i) out[i] = inv[i] * in[0] + inv[4 + i] * in[1] + inv[8 + i] * in[2];
    return;
  }
  Apply(TransformOf(ts, to_world), in, kind == TESSERA_OPTIX7_TRANSFORM_POINT ? 1.f : 0.f, out);
}

void TexFootprint2D(unsigned long long, unsigned int, float, float, unsigned int*,
                    unsigned int[4]) {
  NotBuilt("optixTexFootprint2D", "texture footprints");
}
void TexFootprint2DGrad(unsigned long long, unsigned int, float, float, float, float, float, float,
                        int, unsigned int*, unsigned int[4]) {
  NotBuilt("optixTexFootprint2DGrad", "texture footprints");
}
void TexFootprint2DLod(unsigned long long, unsigned int, float, float, float, int, unsigned int*,
                       unsigned int[4]) {
  NotBuilt("optixTexFootprint2DLod", "texture footprints");
}

TesseraOptix7Runtime MakeRuntime() {
  TesseraOptix7Runtime r = {};
  r.abi_version = TESSERA_OPTIX7_MODULE_ABI_VERSION;
  r.launch_index = &LaunchIndex;
  r.launch_dimensions = &LaunchDimensions;
  r.sbt_data_pointer = &SbtDataPointer;
  r.trace = &Optix7Trace;
  r.get_payload = &GetPayload;
  r.set_payload = &SetPayload;
  r.set_payload_types = &SetPayloadTypes;
  r.undefined_value = &UndefinedValue;
  r.ray_vector = &RayVector;
  r.ray_float = &RayFloat;
  r.state_uint = &StateUint;
  r.hit_kind_query = &HitKindQuery;
  r.triangle_barycentrics = &TriangleBarycentrics;
  r.curve_parameter = &CurveParameter;
  r.ribbon_parameters = &RibbonParameters;
  r.report_intersection = &Optix7ReportIntersection;
  r.get_attribute = &GetAttribute;
  r.ignore_intersection = &Optix7IgnoreIntersection;
  r.terminate_ray = &Optix7TerminateRay;
  r.primitive_data = &PrimitiveData;
  r.ribbon_normal = &RibbonNormal;
  r.micro_triangle_vertex_data = &MicroTriangleVertexData;
  r.micro_triangle_barycentrics_data = &MicroTriangleBarycentricsData;
  r.gas_traversable_handle = &GasTraversableHandle;
  r.gas_motion_time = &GasMotionTime;
  r.gas_motion_step_count = &GasMotionStepCount;
  r.transform_list_handle = &TransformListHandle;
  r.transform_type_from_handle = &TransformTypeFromHandle;
  r.transform_data_from_handle = &TransformDataFromHandle;
  r.instance_id_from_handle = &InstanceIdFromHandle;
  r.instance_child_from_handle = &InstanceChildFromHandle;
  r.instance_traversable_from_ias = &InstanceTraversableFromIas;
  r.current_transform = &CurrentTransform;
  r.transform = &Transform;
  FillCallsTable(r);
  r.tex_footprint_2d = &TexFootprint2D;
  r.tex_footprint_2d_grad = &TexFootprint2DGrad;
  r.tex_footprint_2d_lod = &TexFootprint2DLod;
  r.atomics_noted = AtomicsNotedFlag();
  r.note_atomic = &NoteAtomic;
  FillAccuracyTable(r);
  return r;
}

}  // namespace

const TesseraOptix7Runtime* Optix7Runtime() {
  static const TesseraOptix7Runtime runtime = MakeRuntime();
  return &runtime;
}

absl::StatusOr<bool> InitOptix7Module(void* handle, const std::string& path) {
  auto init = reinterpret_cast<TesseraOptix7ModuleInitFn>(dlsym(handle, kOptix7ModuleInitSymbol));
  if (init == nullptr) return false;
  const unsigned int theirs = init(Optix7Runtime(), TESSERA_OPTIX7_MODULE_ABI_VERSION);
  if (theirs != 0) {
    return absl::FailedPreconditionError(absl::StrCat(
        "OptiX 7 program module ", path, " was built against OptiX 7 device headers of module ABI ",
        theirs, ", this Tessera's is ", TESSERA_OPTIX7_MODULE_ABI_VERSION,
        ": rebuild it against this Tessera's api/include7"));
  }
  return true;
}

}  // namespace tessera::worker
