// Program execution: per-thread state, rtTrace through Embree, the intersection/any-hit protocol
// (OptiX guide §4.1.4, §4.8), exceptions and printing. Every TesseraRuntime entry checks that the
// calling program kind may make that call ("Which OptiX calls are supported where?").
#include "runtime.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "callbacks.h"
#include "plan.h"
#include "tessera/rt.h"

namespace tessera::worker {
namespace {

// optix::Ray's layout (internal/optix_datatypes.h).
struct RayData {
  float origin[3];
  float direction[3];
  unsigned ray_type;
  float tmin;
  float tmax;
};
static_assert(sizeof(RayData) == 36, "optix::Ray layout");

using Mat = std::array<float, 16>;
constexpr Mat kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat Mul(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return c;
}

struct Hit {
  float t = 0;
  const InstancePlan* instance = nullptr;
  unsigned material = 0;
  unsigned primitive = 0;
  bool deferred = false;  // native triangle: attributes come from the intersection program later
  RayData object_ray{};
  Mat to_world = kIdentity, to_object = kIdentity;
  alignas(16) unsigned char attributes[AttributeLayout::kMaxBytes];
};

struct Frame {
  RayData ray{};  // world space
  void* payload = nullptr;
  size_t payload_size = 0;
  Hit hit;
  bool terminated = false;
  Mat to_world = kIdentity, to_object = kIdentity;  // current traversal transform
};

enum class IntersectMode { kSearch, kFiltered, kDeferred };

struct IntersectState {
  const InstancePlan* instance = nullptr;
  unsigned primitive = 0;
  RayData ray{};
  IntersectMode mode = IntersectMode::kSearch;
  float forced_t = 0;
  float candidate_t = 0;
  bool candidate_ok = false;
  bool committed = false;
};

struct ExceptionSignal {
  unsigned code;
  std::string details;
};

struct ThreadState {
  const LaunchPlan* plan = nullptr;
  uint64_t plan_serial = 0;
  Index3 index{}, dims{};
  std::vector<Frame> frames;
  std::vector<SlotSnapshot> snapshots;
  ProgramKind kind = ProgramKind::kRayGeneration;
  const BoundProgram* current = nullptr;
  IntersectState is;
  Hit candidate;
  bool ah_ignore = false, ah_terminate = false;
  unsigned exception_code = 0;
  std::string exception_details;
  std::exception_ptr pending;
  v1::TileResult* out = nullptr;
  uint64_t print_sequence = 0;
  std::vector<unsigned char> scratch;
};

thread_local ThreadState t_state;

// Which program kinds may make a call: bit per ProgramKind.
constexpr unsigned Bit(ProgramKind k) { return 1u << static_cast<unsigned>(k); }
constexpr unsigned kAllKinds = 0xFFu;

void CheckCall(unsigned allowed, const char* call) {
  ThreadState& ts = t_state;
  if (allowed & Bit(ts.kind)) return;
  throw FatalError{absl::FailedPreconditionError(absl::StrCat(
      call, " called from ", ts.current ? ts.current->name : "a program", ": not allowed in a ",
      KindName(ts.kind), " program (OptiX 3 guide, \"Which OptiX calls are supported where?\")"))};
}

std::string IndexText(const Index3& i) {
  return absl::StrCat("(", i[0], ", ", i[1], ", ", i[2], ")");
}

// Raises `code` if it is enabled (throws ExceptionSignal); otherwise returns so the caller skips
// the offending operation.
void Raise(unsigned code, std::string details) {
  if (t_state.plan->ExceptionEnabled(code)) throw ExceptionSignal{code, std::move(details)};
}

void WriteSlot(const BoundProgram& p, const std::vector<unsigned>& vars, const void* src,
               size_t size) {
  for (unsigned var : vars) {
    size_t n = std::min(size, p.module->variables()[var].size);
    std::memcpy(p.module->Slots()[var], src, n);
  }
}

// Copies the payload back from the program's payload variable. With several payload variables
// (radiance and shadow, say) the one of the traced payload's size that the program changed wins.
void ReadPayload(const BoundProgram& p, void* dst, size_t size) {
  const unsigned* chosen = nullptr;
  for (const unsigned& var : p.payload) {
    if (p.module->variables()[var].size != size) continue;
    if (chosen == nullptr) chosen = &var;
    if (std::memcmp(p.module->Slots()[var], dst, size) != 0) {
      chosen = &var;
      break;
    }
  }
  if (chosen == nullptr && !p.payload.empty()) chosen = &p.payload.front();
  if (chosen == nullptr) return;
  size_t n = std::min(size, p.module->variables()[*chosen].size);
  std::memcpy(dst, p.module->Slots()[*chosen], n);
}

void LoadAttributes(const BoundProgram& p, const unsigned char* block) {
  void* const* slots = p.module->Slots();
  for (const auto& a : p.attributes) std::memcpy(slots[a.var], block + a.offset, a.size);
}

void StoreAttributes(const BoundProgram& p, unsigned char* block) {
  void* const* slots = p.module->Slots();
  for (const auto& a : p.attributes) std::memcpy(block + a.offset, slots[a.var], a.size);
}

// Makes `p` the running program: loads its bindings and the semantics every kind may read.
void Enter(const BoundProgram& p) {
  ThreadState& ts = t_state;
  ts.kind = p.kind;
  ts.current = &p;
  p.Load();
  uint32_t index[3] = {ts.index[0], ts.index[1], ts.index[2]};
  uint32_t dims[3] = {ts.dims[0], ts.dims[1], ts.dims[2]};
  if (p.kind != ProgramKind::kBoundingBox) WriteSlot(p, p.launch_index, index, sizeof(index));
  WriteSlot(p, p.launch_dim, dims, sizeof(dims));
}

// Runs a closest-hit or miss program on the current frame's payload.
void Shade(const BoundProgram& p, Frame& f) {
  ThreadState& ts = t_state;
  Enter(p);
  WriteSlot(p, p.ray, &f.ray, sizeof(RayData));
  WriteSlot(p, p.payload, f.payload, f.payload_size);
  if (p.kind == ProgramKind::kClosestHit) {
    WriteSlot(p, p.distance, &f.hit.t, sizeof(float));
    LoadAttributes(p, f.hit.attributes);
  }
  reinterpret_cast<void (*)()>(p.function)();
  ReadPayload(p, f.payload, f.payload_size);
  (void)ts;
}

RayData ToObject(const RayData& r, const Mat& inv) {
  RayData o = r;
  for (int i = 0; i < 3; ++i) {
    o.origin[i] = inv[i * 4] * r.origin[0] + inv[i * 4 + 1] * r.origin[1] +
                  inv[i * 4 + 2] * r.origin[2] + inv[i * 4 + 3];
    o.direction[i] = inv[i * 4] * r.direction[0] + inv[i * 4 + 1] * r.direction[1] +
                     inv[i * 4 + 2] * r.direction[2];
  }
  return o;
}

RTCRayHit ToEmbree(const RayData& r) {
  RTCRayHit rh{};
  rh.ray.org_x = r.origin[0];
  rh.ray.org_y = r.origin[1];
  rh.ray.org_z = r.origin[2];
  rh.ray.dir_x = r.direction[0];
  rh.ray.dir_y = r.direction[1];
  rh.ray.dir_z = r.direction[2];
  rh.ray.tnear = r.tmin;
  rh.ray.tfar = r.tmax;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

RayData FromEmbree(const RTCRay& e, unsigned ray_type) {
  return RayData{
      {e.org_x, e.org_y, e.org_z}, {e.dir_x, e.dir_y, e.dir_z}, ray_type, e.tnear, e.tfar};
}

// Intersects the scene of one node; `ray` is in the node's parent space and its tmax is the
// closest hit so far. Hits are committed to the current frame.
void TraverseNode(NodeRef ref, RayData ray);

void RethrowPending() {
  ThreadState& ts = t_state;
  if (ts.pending) {
    std::exception_ptr p = ts.pending;
    ts.pending = nullptr;
    std::rethrow_exception(p);
  }
}

void IntersectScene(RTCScene scene, const RayData& ray, bool geometry_group) {
  ThreadState& ts = t_state;
  Frame& f = ts.frames.back();
  RTCRayHit rh = ToEmbree(ray);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(scene, &ctx, &rh);
  RethrowPending();
  if (!geometry_group || rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || f.terminated) return;
  auto* info =
      static_cast<GeometryInfo*>(rtcGetGeometryUserData(rtcGetGeometry(scene, rh.hit.geomID)));
  if (!info->triangles || info->filter || !(rh.ray.tfar < f.hit.t)) return;
  // A native triangle is the closest so far: its attributes come after traversal.
  f.hit.t = rh.ray.tfar;
  f.hit.instance = info->plan;
  f.hit.primitive = rh.hit.primID;
  f.hit.material = 0;
  f.hit.deferred = true;
  f.hit.object_ray = ray;
  f.hit.to_world = f.to_world;
  f.hit.to_object = f.to_object;
}

void TraverseNode(NodeRef ref, RayData ray) {
  ThreadState& ts = t_state;
  const LaunchPlan& plan = *ts.plan;
  Frame& f = ts.frames.back();
  ray.tmax = std::min(ray.tmax, f.hit.t);
  switch (ref.type) {
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
    case RT_OBJECTTYPE_GROUP: {
      const SceneEntry* e = plan.scenes->Find(ref.id);
      if (e == nullptr) {
        throw FatalError{absl::FailedPreconditionError(
            absl::StrCat("node #", ref.id, " has no acceleration structure on the device"))};
      }
      IntersectScene(e->scene, ray, ref.type == RT_OBJECTTYPE_GEOMETRY_GROUP);
      return;
    }
    case RT_OBJECTTYPE_TRANSFORM: {
      const TransformRec& t = plan.replica->transforms.at(ref.id);
      Mat saved_world = f.to_world, saved_object = f.to_object;
      f.to_world = Mul(f.to_world, t.matrix);
      f.to_object = Mul(t.inverse, f.to_object);
      TraverseNode(t.child, ToObject(ray, t.inverse));
      f.to_world = saved_world;
      f.to_object = saved_object;
      return;
    }
    default:
      throw FatalError{absl::UnimplementedError(
          absl::StrCat("node #", ref.id, " of type ", ref.type, " cannot be traversed yet"))};
  }
}

// Runs the intersection program of `instance` for one primitive. Returns whether it committed.
bool RunIntersection(const InstancePlan* instance, unsigned primitive, const RayData& ray,
                     IntersectMode mode, float forced_t) {
  ThreadState& ts = t_state;
  const BoundProgram& p = *instance->intersection;
  ts.is = IntersectState{instance, primitive, ray, mode, forced_t, 0.f, false, false};
  Enter(p);
  WriteSlot(p, p.ray, &ray, sizeof(RayData));
  WriteSlot(p, p.distance, &ts.frames.back().hit.t, sizeof(float));
  reinterpret_cast<void (*)(int)>(p.function)(static_cast<int>(primitive));
  return ts.is.committed;
}

void Commit(Frame& f, const Hit& candidate, bool terminate) {
  ThreadState& ts = t_state;
  std::memcpy(&f.hit, &candidate, sizeof(Hit));
  f.hit.to_world = f.to_world;
  f.hit.to_object = f.to_object;
  ts.is.committed = true;
  ts.is.ray.tmax = candidate.t;
  if (terminate) f.terminated = true;
}

// ---- TesseraRuntime entries ------------------------------------------------------------------

void RtTrace(unsigned long long node, const void* ray_ptr, void* payload, size_t payload_size) {
  CheckCall(
      Bit(ProgramKind::kRayGeneration) | Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kMiss),
      "rtTrace");
  ThreadState& ts = t_state;
  const LaunchPlan& plan = *ts.plan;
  RayData ray;
  std::memcpy(&ray, ray_ptr, sizeof(ray));
  if (ts.frames.size() >= plan.max_depth) {
    Raise(RT_EXCEPTION_STACK_OVERFLOW,
          absl::StrCat("rtTrace nested ", ts.frames.size() + 1, " deep exceeds the stack size"));
    return;
  }
  bool finite = true;
  for (int i = 0; i < 3; ++i) {
    finite = finite && std::isfinite(ray.origin[i]) && std::isfinite(ray.direction[i]);
  }
  if (!finite || std::isnan(ray.tmin) || std::isnan(ray.tmax) || ray.tmin > ray.tmax ||
      ray.tmin < 0.f) {
    Raise(RT_EXCEPTION_INVALID_RAY,
          absl::StrFormat("invalid ray: origin (%g, %g, %g) direction (%g, %g, %g) tmin %g "
                          "tmax %g",
                          ray.origin[0], ray.origin[1], ray.origin[2], ray.direction[0],
                          ray.direction[1], ray.direction[2], ray.tmin, ray.tmax));
    return;
  }
  if (ray.ray_type >= plan.replica->context().ray_type_count) {
    throw FatalError{absl::InvalidArgumentError(absl::StrCat(
        "rtTrace with ray type ", ray.ray_type, " but the context has ",
        plan.replica->context().ray_type_count, " ray types (", ts.current->name, ")"))};
  }
  uint32_t type = plan.NodeType(node);
  if (type == 0) {
    throw FatalError{absl::InvalidArgumentError(absl::StrCat(
        "rtTrace on object #", node, " which is not a graph node (", ts.current->name, ")"))};
  }

  const BoundProgram* caller = ts.current;
  size_t depth = ts.frames.size();
  if (ts.snapshots.size() <= depth) ts.snapshots.resize(depth + 1);
  ts.snapshots[depth].Save(caller->module);

  ts.frames.emplace_back();
  Frame& f = ts.frames.back();
  f.ray = ray;
  f.payload = payload;
  f.payload_size = payload_size;
  f.hit.t = ray.tmax;
  TraverseNode(NodeRef{node, type}, ray);

  if (f.hit.instance != nullptr) {
    if (f.hit.deferred) {
      Hit& h = f.hit;
      RunIntersection(h.instance, h.primitive, h.object_ray, IntersectMode::kDeferred, h.t);
    }
    const auto& groups = f.hit.instance->materials;
    if (f.hit.material < groups.size()) {
      if (const BoundProgram* ch = groups[f.hit.material][ray.ray_type].closest_hit) Shade(*ch, f);
    }
  } else if (ray.ray_type < plan.miss.size() && plan.miss[ray.ray_type] != nullptr) {
    Shade(*plan.miss[ray.ray_type], f);
  }
  ts.frames.pop_back();
  ts.snapshots[depth].Restore();
  ts.current = caller;
  ts.kind = caller->kind;
}

int RtPotentialIntersection(float t) {
  CheckCall(Bit(ProgramKind::kIntersection), "rtPotentialIntersection");
  IntersectState& is = t_state.is;
  if (is.mode == IntersectMode::kSearch) {
    is.candidate_ok = t > is.ray.tmin && t < is.ray.tmax && !t_state.frames.back().terminated;
    is.candidate_t = t;
  } else {
    // Embree already chose this primitive at forced_t; the program only reports attributes.
    is.candidate_ok = true;
    is.candidate_t = is.forced_t;
  }
  return is.candidate_ok ? 1 : 0;
}

int RtReportIntersection(unsigned material) {
  CheckCall(Bit(ProgramKind::kIntersection), "rtReportIntersection");
  ThreadState& ts = t_state;
  IntersectState& is = ts.is;
  if (!is.candidate_ok) return 0;
  is.candidate_ok = false;
  const InstancePlan* inst = is.instance;
  if (material >= inst->materials.size()) {
    throw FatalError{absl::OutOfRangeError(absl::StrCat(
        "rtReportIntersection(", material, ") from ", ts.current->name, ": geometry instance #",
        inst->id, " has ", inst->materials.size(), " materials"))};
  }
  Frame& f = ts.frames.back();
  const BoundProgram& isp = *ts.current;
  Hit& c = ts.candidate;
  c.t = is.candidate_t;
  c.instance = inst;
  c.material = material;
  c.primitive = is.primitive;
  c.deferred = false;
  StoreAttributes(isp, c.attributes);

  const BoundProgram* ah = inst->materials[material][f.ray.ray_type].any_hit;
  if (is.mode == IntersectMode::kDeferred || ah == nullptr) {
    Commit(f, c, false);
    return 1;
  }
  // The any-hit program may live in the intersection program's module: keep the intersection
  // program's slots intact for when rtReportIntersection returns.
  size_t depth = ts.frames.size();
  if (ts.snapshots.size() <= depth) ts.snapshots.resize(depth + 1);
  ts.snapshots[depth].Save(isp.module);
  Enter(*ah);
  RayData object_ray = is.ray;
  WriteSlot(*ah, ah->ray, &object_ray, sizeof(RayData));
  WriteSlot(*ah, ah->distance, &c.t, sizeof(float));
  WriteSlot(*ah, ah->payload, f.payload, f.payload_size);
  LoadAttributes(*ah, c.attributes);
  ts.ah_ignore = ts.ah_terminate = false;
  reinterpret_cast<void (*)()>(ah->function)();
  ReadPayload(*ah, f.payload, f.payload_size);
  bool accepted = !ts.ah_ignore;
  bool terminate = ts.ah_terminate;
  ts.snapshots[depth].Restore();
  ts.kind = isp.kind;
  ts.current = &isp;
  if (!accepted) return 0;
  Commit(f, c, terminate);
  return 1;
}

void RtIgnoreIntersection() {
  CheckCall(Bit(ProgramKind::kAnyHit), "rtIgnoreIntersection");
  t_state.ah_ignore = true;
}

void RtTerminateRay() {
  CheckCall(Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss), "rtTerminateRay");
  if (t_state.kind == ProgramKind::kAnyHit) t_state.ah_terminate = true;
}

void RtThrow(unsigned code) {
  CheckCall(kAllKinds & ~Bit(ProgramKind::kException), "rtThrow");
  if (code < RT_EXCEPTION_USER || code > 0xFFFF) {
    throw FatalError{absl::InvalidArgumentError(
        absl::StrFormat("rtThrow(0x%X) from %s: user exception codes run from 0x400 to 0xFFFF",
                        code, t_state.current->name))};
  }
  Raise(code, absl::StrFormat("user exception 0x%X", code));
}

unsigned RtExceptionCode() {
  CheckCall(Bit(ProgramKind::kException), "rtGetExceptionCode");
  return t_state.exception_code;
}

bool PrintActive() {
  const ThreadState& ts = t_state;
  if (!ts.plan->print_enabled) return false;
  for (int i = 0; i < 3; ++i) {
    if (ts.plan->print_index[i] >= 0 &&
        static_cast<uint32_t>(ts.plan->print_index[i]) != ts.index[i]) {
      return false;
    }
  }
  return true;
}

void Emit(const std::string& text) {
  ThreadState& ts = t_state;
  if (ts.out == nullptr) return;
  v1::PrintRecord* r = ts.out->add_prints();
  for (uint32_t i : ts.index) r->add_launch_index(i);
  r->set_sequence(ts.print_sequence++);
  r->set_text(text);
}

int RtPrintActive() { return PrintActive() ? 1 : 0; }
void RtPrint(const char* text) {
  if (PrintActive() && text != nullptr) Emit(text);
}

const char* ExceptionName(unsigned code) {
  switch (code) {
    case RT_EXCEPTION_PROGRAM_ID_INVALID:
      return "RT_EXCEPTION_PROGRAM_ID_INVALID";
    case RT_EXCEPTION_TEXTURE_ID_INVALID:
      return "RT_EXCEPTION_TEXTURE_ID_INVALID";
    case RT_EXCEPTION_BUFFER_ID_INVALID:
      return "RT_EXCEPTION_BUFFER_ID_INVALID";
    case RT_EXCEPTION_INDEX_OUT_OF_BOUNDS:
      return "RT_EXCEPTION_INDEX_OUT_OF_BOUNDS";
    case RT_EXCEPTION_STACK_OVERFLOW:
      return "RT_EXCEPTION_STACK_OVERFLOW";
    case RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS:
      return "RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS";
    case RT_EXCEPTION_INVALID_RAY:
      return "RT_EXCEPTION_INVALID_RAY";
    case RT_EXCEPTION_INTERNAL_ERROR:
      return "RT_EXCEPTION_INTERNAL_ERROR";
    default:
      return code >= RT_EXCEPTION_USER ? "RT_EXCEPTION_USER" : "unknown exception";
  }
}

std::string ExceptionText() {
  const ThreadState& ts = t_state;
  return absl::StrFormat("Caught %s (0x%X) at launch index %s: %s\n",
                         ExceptionName(ts.exception_code), ts.exception_code, IndexText(ts.index),
                         ts.exception_details);
}

void RtPrintExceptionDetails() {
  CheckCall(Bit(ProgramKind::kException), "rtPrintExceptionDetails");
  if (PrintActive()) Emit(ExceptionText());
}

const Mat& CurrentTransform(bool to_world) {
  const ThreadState& ts = t_state;
  static const Mat identity = kIdentity;
  if (ts.frames.empty()) return identity;
  const Frame& f = ts.frames.back();
  if (ts.kind == ProgramKind::kClosestHit) return to_world ? f.hit.to_world : f.hit.to_object;
  if (ts.kind == ProgramKind::kMiss) return identity;
  return to_world ? f.to_world : f.to_object;
}

void RtTransform(unsigned kind, unsigned what, const float* in, float* out) {
  CheckCall(Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss) |
                Bit(ProgramKind::kIntersection) | Bit(ProgramKind::kBoundingBox) |
                Bit(ProgramKind::kVisit),
            "rtTransform*");
  bool to_world = kind == RT_OBJECT_TO_WORLD;
  if (!to_world && kind != RT_WORLD_TO_OBJECT) {
    throw FatalError{absl::InvalidArgumentError(
        absl::StrCat("rtTransform* with unknown transform kind ", kind))};
  }
  float v[3] = {in[0], in[1], in[2]};
  if (what == TESSERA_TRANSFORM_NORMAL) {
    // Normals go through the inverse transpose of the matrix that moves points.
    const Mat& inv = CurrentTransform(!to_world);
    for (int i = 0; i < 3; ++i) out[i] = inv[i] * v[0] + inv[4 + i] * v[1] + inv[8 + i] * v[2];
    return;
  }
  const Mat& m = CurrentTransform(to_world);
  float w = what == TESSERA_TRANSFORM_POINT ? 1.f : 0.f;
  float r[4];
  for (int i = 0; i < 4; ++i)
    r[i] = m[i * 4] * v[0] + m[i * 4 + 1] * v[1] + m[i * 4 + 2] * v[2] + m[i * 4 + 3] * w;
  float d = (what == TESSERA_TRANSFORM_POINT && r[3] != 0.f) ? r[3] : 1.f;
  for (int i = 0; i < 3; ++i) out[i] = r[i] / d;
}

void RtGetTransform(unsigned kind, float* m) {
  CheckCall(Bit(ProgramKind::kClosestHit) | Bit(ProgramKind::kAnyHit) | Bit(ProgramKind::kMiss) |
                Bit(ProgramKind::kIntersection) | Bit(ProgramKind::kBoundingBox) |
                Bit(ProgramKind::kVisit),
            "rtGetTransform");
  const Mat& src = CurrentTransform(kind == RT_OBJECT_TO_WORLD);
  std::memcpy(m, src.data(), sizeof(float) * 16);
}

void* RtBufferIndexError(unsigned slot, unsigned long long x, unsigned long long y,
                         unsigned long long z) {
  ThreadState& ts = t_state;
  const Module* m = ts.current->module;
  const TesseraBufferView& v = m->Views()[slot];
  std::string name = slot < m->buffers().size() ? m->buffers()[slot].name : "?";
  Raise(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS,
        absl::StrCat("buffer '", name, "' index (", x, ", ", y, ", ", z, ") outside size (",
                     v.size[0], ", ", v.size[1], ", ", v.size[2], ") in ", ts.current->name));
  // Disabled: reads see zeros and writes land in scratch memory.
  ts.scratch.assign(std::max<size_t>(v.element_size, 64), 0);
  return ts.scratch.data();
}

void RtIntersectChild(unsigned index) {
  CheckCall(Bit(ProgramKind::kVisit), "rtIntersectChild");
  throw FatalError{absl::UnimplementedError("selectors are not supported yet")};
}

const TesseraRuntime kRuntime = {
    TESSERA_MODULE_ABI_VERSION,
    &RtTrace,
    &RtPotentialIntersection,
    &RtReportIntersection,
    &RtIgnoreIntersection,
    &RtTerminateRay,
    &RtThrow,
    &RtExceptionCode,
    &RtPrintExceptionDetails,
    &RtPrintActive,
    &RtPrint,
    &RtTransform,
    &RtGetTransform,
    &RtBufferIndexError,
    &RtIntersectChild,
};

template <typename F>
void Guard(F&& f) {
  ThreadState& ts = t_state;
  if (ts.pending) return;
  try {
    f();
  } catch (...) {
    ts.pending = std::current_exception();
  }
}

}  // namespace

const TesseraRuntime* EngineRuntime() { return &kRuntime; }

void IntersectUserGeometry(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  Guard([&] {
    ThreadState& ts = t_state;
    Frame& f = ts.frames.back();
    if (f.terminated) return;
    auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    RayData ray = FromEmbree(rh->ray, f.ray.ray_type);
    ray.tmax = std::min(ray.tmax, f.hit.t);
    if (RunIntersection(info->plan, args->primID, ray, IntersectMode::kSearch, 0.f)) {
      rh->ray.tfar = f.hit.t;
      rh->hit.geomID = args->geomID;
      rh->hit.primID = args->primID;
    }
  });
}

void IntersectChild(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  Guard([&] {
    ThreadState& ts = t_state;
    Frame& f = ts.frames.back();
    if (f.terminated) return;
    auto* info = static_cast<const ChildInfo*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    float before = f.hit.t;
    TraverseNode(info->child, FromEmbree(rh->ray, f.ray.ray_type));
    if (f.hit.t < before) {
      rh->ray.tfar = f.hit.t;
      rh->hit.geomID = args->geomID;
      rh->hit.primID = 0;
    }
  });
}

void FilterTriangles(const RTCFilterFunctionNArguments* args) {
  if (!args->valid[0]) return;
  bool accepted = false;
  Guard([&] {
    ThreadState& ts = t_state;
    Frame& f = ts.frames.back();
    if (f.terminated) return;
    auto* info = static_cast<const GeometryInfo*>(args->geometryUserPtr);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    auto* hit = reinterpret_cast<RTCHit*>(args->hit);
    RayData r = FromEmbree(*ray, f.ray.ray_type);
    float t = ray->tfar;
    r.tmax = f.hit.t;
    accepted = RunIntersection(info->plan, hit->primID, r, IntersectMode::kFiltered, t);
  });
  if (!accepted) args->valid[0] = 0;
}

// Binds the calling thread to `plan`.
void UsePlan(ThreadState& ts, const LaunchPlan& plan) {
  ts.plan = &plan;
  if (ts.plan_serial != plan.serial) {
    ts.plan_serial = plan.serial;
    ResetLoadedBindings();
  }
}

void RunLaunchIndex(const LaunchPlan& plan, unsigned entry, const Index3& index, const Index3& dims,
                    v1::TileResult& out) {
  ThreadState& ts = t_state;
  UsePlan(ts, plan);
  ts.index = index;
  ts.dims = dims;
  ts.out = &out;
  ts.print_sequence = 0;
  ts.frames.clear();
  ts.frames.reserve(plan.max_depth + 1);
  ts.pending = nullptr;
  const BoundProgram* rg =
      entry < plan.ray_generation.size() ? plan.ray_generation[entry] : nullptr;
  if (rg == nullptr) {
    throw FatalError{absl::FailedPreconditionError(
        absl::StrCat("entry point ", entry, " has no ray generation program"))};
  }
  try {
    Enter(*rg);
    reinterpret_cast<void (*)()>(rg->function)();
  } catch (ExceptionSignal& e) {
    ts.frames.clear();
    ts.exception_code = e.code;
    ts.exception_details = std::move(e.details);
    const BoundProgram* ex = entry < plan.exception.size() ? plan.exception[entry] : nullptr;
    if (ex != nullptr) {
      try {
        Enter(*ex);
        reinterpret_cast<void (*)()>(ex->function)();
      } catch (ExceptionSignal&) {
        // An exception inside the exception program ends this launch index.
      }
    } else {
      v1::ExceptionReport* r = out.add_exceptions();
      for (uint32_t i : index) r->add_launch_index(i);
      r->set_code(ts.exception_code);
      r->set_details(ExceptionText());
    }
  }
  ts.out = nullptr;
}

void RunBoundsProgram(const LaunchPlan& plan, const BoundProgram& program, unsigned primitive,
                      float result[6]) {
  ThreadState& ts = t_state;
  UsePlan(ts, plan);
  ts.out = nullptr;
  ts.frames.clear();
  try {
    Enter(program);
    reinterpret_cast<void (*)(int, float*)>(program.function)(static_cast<int>(primitive), result);
  } catch (ExceptionSignal& e) {
    throw FatalError{absl::FailedPreconditionError(absl::StrCat(
        program.name, " raised an exception for primitive ", primitive, ": ", e.details))};
  }
}

}  // namespace tessera::worker
