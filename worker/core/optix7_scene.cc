#include "optix7_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "absl/hash/hash.h"
#include "absl/strings/str_cat.h"
#include "optix_types.h"
#include "tessera/accuracy.h"
#include "tessera/optix7_ext.h"

namespace tessera::worker {
namespace {

using memory::AccelHeader;
using memory::AccelInput;
using memory::AccelKind;

// The user data of a custom-primitive geometry: its boxes, six floats a primitive, key after key.
void BoundsFromDescriptor(const RTCBoundsFunctionArguments* args) {
  const auto& b = *static_cast<const Optix7Scene::Boxes*>(args->geometryUserPtr);
  const float* box = b.boxes + 6 * (b.per_key * args->timeStep + args->primID);
  args->bounds_o->lower_x = box[0];
  args->bounds_o->lower_y = box[1];
  args->bounds_o->lower_z = box[2];
  args->bounds_o->upper_x = box[3];
  args->bounds_o->upper_y = box[4];
  args->bounds_o->upper_z = box[5];
}

// The user data of a node: its bounds in the IAS's space over every time.
void NodeBounds(const RTCBoundsFunctionArguments* args) {
  const float* b = static_cast<const Optix7Node*>(args->geometryUserPtr)->bounds;
  args->bounds_o->lower_x = b[0];
  args->bounds_o->lower_y = b[1];
  args->bounds_o->lower_z = b[2];
  args->bounds_o->upper_x = b[3];
  args->bounds_o->upper_y = b[4];
  args->bounds_o->upper_z = b[5];
}

absl::Status Committed(RTCDevice device, RTCScene scene, const char* what) {
  rtcCommitScene(scene);
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) {
    return absl::InternalError(
        absl::StrCat("Embree could not build ", what, " (error ", static_cast<int>(e), ")"));
  }
  return absl::OkStatus();
}

// Whether some SBT record of a GAS's inputs asks for one any-hit call per primitive.
bool RequiresSingleAnyHit(const unsigned char* bytes, const AccelHeader& h) {
  if (h.kind == AccelKind::kInstances) return false;
  const auto* inputs = reinterpret_cast<const AccelInput*>(bytes + h.inputs_offset);
  for (uint32_t i = 0; i < h.input_count; ++i) {
    for (uint32_t r = 0; r < inputs[i].num_sbt_records; ++r) {
      uint32_t flags;
      std::memcpy(&flags, bytes + inputs[i].flags_offset + 4ull * r, sizeof(flags));
      if (flags & OPTIX_GEOMETRY_FLAG_REQUIRE_SINGLE_ANYHIT_CALL) return true;
    }
  }
  return false;
}

// PREFER_FAST_TRACE: Embree's high quality (spatial splits), unless some record requires a single
// any-hit call (a split triangle is offered once per piece); PREFER_FAST_BUILD: low; neither:
// medium.
RTCBuildQuality QualityOf(const unsigned char* bytes, const AccelHeader& h) {
  if (h.build_flags & OPTIX_BUILD_FLAG_PREFER_FAST_BUILD) return RTC_BUILD_QUALITY_LOW;
  if ((h.build_flags & OPTIX_BUILD_FLAG_PREFER_FAST_TRACE) && !RequiresSingleAnyHit(bytes, h)) {
    return RTC_BUILD_QUALITY_HIGH;
  }
  return RTC_BUILD_QUALITY_MEDIUM;
}

bool Updatable(const AccelHeader& h) {
  return h.kind != AccelKind::kInstances && (h.build_flags & OPTIX_BUILD_FLAG_ALLOW_UPDATE) != 0;
}

Optix7Motion MotionOf(const AccelHeader& h) {
  if (h.motion_offset == 0) return Optix7Motion{};
  memory::AccelMotion m;
  std::memcpy(&m, reinterpret_cast<const unsigned char*>(&h) + h.motion_offset, sizeof(m));
  return Optix7Motion{m.keys, m.flags, m.time_begin, m.time_end};
}

// The node's bounds in its IAS's space: the child's bounds (over its whole motion) through the
// instance and the transforms at every key time of the transforms and 64 times between. One
// matrix motion transform moves each corner linearly between keys, so its keys bound it exactly;
// rotations (SRT) and products of motions do not, so those bounds grow by 1% of their size.
void ComputeNodeBounds(const Optix7Scene::Instance& inst, Optix7Node& node) {
  RTCLinearBounds lb;
  rtcGetSceneLinearBounds(node.child->scene, &lb);
  const float child[6] = {std::min(lb.bounds0.lower_x, lb.bounds1.lower_x),
                          std::min(lb.bounds0.lower_y, lb.bounds1.lower_y),
                          std::min(lb.bounds0.lower_z, lb.bounds1.lower_z),
                          std::max(lb.bounds0.upper_x, lb.bounds1.upper_x),
                          std::max(lb.bounds0.upper_y, lb.bounds1.upper_y),
                          std::max(lb.bounds0.upper_z, lb.bounds1.upper_z)};
  float* out = node.bounds;
  if (!(child[0] <= child[3] && child[1] <= child[4] && child[2] <= child[5])) {
    // An empty child: bounds Embree skips, so the node is never hit.
    const float inf = std::numeric_limits<float>::infinity();
    const float empty[6] = {inf, inf, inf, -inf, -inf, -inf};
    std::memcpy(out, empty, sizeof(empty));
    return;
  }
  std::vector<float> times;
  unsigned moving = 0;
  bool srt = false;
  float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
  for (const Optix7Transform& t : node.transforms) {
    if (!t.motion.moves()) continue;
    ++moving;
    srt = srt || t.type == 3;  // OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM
    lo = std::min(lo, t.motion.begin);
    hi = std::max(hi, t.motion.end);
    for (uint32_t k = 0; k < t.motion.keys; ++k) {
      times.push_back(t.motion.begin + (t.motion.end - t.motion.begin) * static_cast<float>(k) /
                                           static_cast<float>(t.motion.keys - 1));
    }
  }
  if (moving == 0) times.push_back(0.f);
  if (moving > 0) {
    for (int i = 0; i <= 64; ++i) times.push_back(lo + (hi - lo) * static_cast<float>(i) / 64.f);
  }
  for (int i = 0; i < 3; ++i) {
    out[i] = std::numeric_limits<float>::max();
    out[3 + i] = std::numeric_limits<float>::lowest();
  }
  for (float time : times) {
    float m[12], w[12], o[12];
    std::memcpy(m, inst.to_world, sizeof(m));
    for (const Optix7Transform& t : node.transforms) {
      t.At(time, w, o);
      Compose(m, w, m);
    }
    for (int c = 0; c < 8; ++c) {
      const float p[3] = {child[(c & 1) ? 3 : 0], child[(c & 2) ? 4 : 1], child[(c & 4) ? 5 : 2]};
      for (int r = 0; r < 3; ++r) {
        const float v = m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3];
        out[r] = std::min(out[r], v);
        out[3 + r] = std::max(out[3 + r], v);
      }
    }
  }
  if (srt || moving > 1) {
    const float pad = 0.01f * std::max({out[3] - out[0], out[4] - out[1], out[5] - out[2]});
    for (int r = 0; r < 3; ++r) {
      out[r] -= pad;
      out[3 + r] += pad;
    }
  }
}

}  // namespace

Optix7Scene::~Optix7Scene() {
  if (scene != nullptr) rtcReleaseScene(scene);
}

absl::StatusOr<const Optix7Scene*> Optix7SceneCache::Get(uint64_t handle, uint64_t serial,
                                                         uint32_t accuracy) {
  if (serial == 0 || serial != serial_) {
    this_launch_.clear();
    keys_this_launch_.clear();
    serial_ = serial;
  }
  accuracy_ = accuracy;
  if (serial != 0) {
    if (auto it = this_launch_.find(handle); it != this_launch_.end()) return it->second;
  }
  absl::StatusOr<const Optix7Scene*> s = GetAt(handle, 0);
  if (s.ok() && serial != 0) this_launch_[handle] = *s;
  return s;
}

uint32_t Optix7SceneCache::AccuracyOf(const AccelHeader& h) const {
  uint32_t a = accuracy_ &
               (TESSERA_ACCURACY_ROBUST | TESSERA_ACCURACY_WATERTIGHT | TESSERA_ACCURACY_COMPACT);
  if (h.build_flags & TESSERA_OPTIX_BUILD_FLAG_ROBUST) a |= TESSERA_ACCURACY_ROBUST;
  if (h.build_flags & TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT) a |= TESSERA_ACCURACY_WATERTIGHT;
  if (h.build_flags & TESSERA_OPTIX_BUILD_FLAG_COMPACT) a |= TESSERA_ACCURACY_COMPACT;
  if (a & TESSERA_ACCURACY_WATERTIGHT) a |= TESSERA_ACCURACY_ROBUST;
  return a;
}

uint64_t Optix7SceneCache::GasKey(uint64_t handle, const AccelHeader& h) const {
  return absl::HashOf(h.content_hash, h.build_flags, AccuracyOf(h),
                      Updatable(h) ? handle : uint64_t{0});
}

// What identifies the scene of `handle`: a GAS's GasKey; for an IAS, its content hash with
// its children's keys, so that a child rebuilt in place (the IAS's bytes unchanged) gives a new
// key; for a transform, its handle (programs see it in transform lists), its bytes and its
// child's key.
absl::StatusOr<uint64_t> Optix7SceneCache::KeyOf(uint64_t handle, unsigned depth) {
  if (depth > kMaxGraphDepth) {
    return absl::InvalidArgumentError(absl::StrCat("traversable graph deeper than ", kMaxGraphDepth,
                                                   " levels (or with a cycle) at 0x",
                                                   absl::Hex(handle)));
  }
  if (serial_ != 0) {
    if (auto it = keys_this_launch_.find(handle); it != keys_this_launch_.end()) return it->second;
  }
  uint64_t key;
  if (IsTransformHandle(handle)) {
    absl::StatusOr<Optix7Transform> t = ReadTransform(handle, readable_(TransformAddress(handle)));
    if (!t.ok()) return t.status();
    absl::StatusOr<uint64_t> child = KeyOf(t->child, depth + 1);
    if (!child.ok()) return child.status();
    key = absl::HashOf(handle, t->motion.keys, t->motion.flags, t->motion.begin, t->motion.end,
                       t->data, *child);
  } else {
    const size_t available = handle == 0 ? 0 : readable_(handle);
    absl::StatusOr<const AccelHeader*> read =
        memory::ReadAccelHeader(reinterpret_cast<const void*>(handle), available);
    if (available == 0 || !read.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat("traversable handle 0x", absl::Hex(handle), ": ",
                       available == 0 ? "not in device memory" : read.status().message()));
    }
    const AccelHeader& h = **read;
    key = h.kind == AccelKind::kInstances
              ? absl::HashOf(h.content_hash, h.build_flags, AccuracyOf(h))
              : GasKey(handle, h);
    if (h.kind == AccelKind::kInstances) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(handle);
      for (uint64_t k = 0; k < h.primitive_count; ++k) {
        uint64_t child;
        std::memcpy(&child, bytes + h.inputs_offset + k * memory::kInstanceBytes + 64,
                    sizeof(child));
        absl::StatusOr<uint64_t> ck = KeyOf(child, depth + 1);
        if (!ck.ok()) {
          return absl::InvalidArgumentError(absl::StrCat(
              "instance ", k, " of 0x", absl::Hex(handle), ": ", ck.status().message()));
        }
        key = absl::HashOf(key, *ck);
      }
    }
  }
  if (serial_ != 0) keys_this_launch_[handle] = key;
  return key;
}

absl::Status Optix7SceneCache::BuildInstances(uint64_t handle, unsigned depth, Optix7Scene& s) {
  const AccelHeader& h = *s.header;
  const auto* bytes = reinterpret_cast<const unsigned char*>(handle);
  s.instances.reserve(h.primitive_count);
  std::bitset<256> masks;
  bool nested_masks = false;
  std::bitset<256> nested_visible;
  nested_visible.set();
  s.single_level = true;
  s.any_motion = s.motion.moves();
  for (uint64_t k = 0; k < h.primitive_count; ++k) {
    const unsigned char* record = bytes + h.inputs_offset + k * memory::kInstanceBytes;
    Optix7Scene::Instance& inst = s.instances.emplace_back();
    // OptixInstance layout: transform[12], instanceId, sbtOffset, visibilityMask, flags,
    // traversableHandle.
    std::memcpy(inst.to_world, record, sizeof(inst.to_world));
    std::memcpy(&inst.id, record + 48, 4);
    std::memcpy(&inst.sbt_offset, record + 52, 4);
    std::memcpy(&inst.mask, record + 56, 4);
    std::memcpy(&inst.flags, record + 60, 4);
    std::memcpy(&inst.child, record + 64, sizeof(inst.child));
    InvertAffine(inst.to_world, inst.to_object);
    masks.set(inst.mask & 0xFFu);
    auto fail = [&](const absl::Status& st) {
      return absl::Status(st.code(), absl::StrCat("instance ", k, ": ", st.message()));
    };
    // The transforms on the way to the child acceleration.
    std::vector<Optix7Transform> chain;
    uint64_t c = inst.child;
    while (IsTransformHandle(c)) {
      if (depth + 1 + chain.size() > kMaxGraphDepth) {
        return fail(absl::InvalidArgumentError(
            absl::StrCat("more than ", kMaxGraphDepth, " transforms and instances in a row")));
      }
      absl::StatusOr<Optix7Transform> t = ReadTransform(c, readable_(TransformAddress(c)));
      if (!t.ok()) return fail(t.status());
      c = t->child;
      chain.push_back(*std::move(t));
    }
    absl::StatusOr<const Optix7Scene*> child = GetAt(c, depth + 1 + chain.size());
    if (!child.ok()) return fail(child.status());
    const Optix7Scene& cs = **child;
    s.primitive_types |= cs.primitive_types;
    s.any_motion = s.any_motion || cs.any_motion;
    for (const Optix7Transform& t : chain) s.any_motion = s.any_motion || t.motion.moves();
    s.single_level = s.single_level && chain.empty() && cs.kind != AccelKind::kInstances;
    // A moving GAS is an Embree instance when its range is the IAS's time (the first such GAS
    // sets it) and it never vanishes; anything else is a node.
    bool native = chain.empty() && cs.kind != AccelKind::kInstances;
    if (native && cs.motion.moves()) {
      if (cs.motion.flags != 0) {
        native = false;
      } else if (!s.time.moves()) {
        s.time = Optix7Motion{2, 0, cs.motion.begin, cs.motion.end};
      } else {
        native = s.time.begin == cs.motion.begin && s.time.end == cs.motion.end;
      }
    }
    RTCGeometry g;
    if (native) {
      g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, cs.scene);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, inst.to_world);
    } else {
      if (node_intersect_ == nullptr) {
        return fail(absl::UnimplementedError("no node intersection function (engine not set)"));
      }
      auto node = std::make_unique<Optix7Node>();
      node->instance = static_cast<uint32_t>(k);
      node->transforms = std::move(chain);
      node->child = &cs;
      node->child_handle = c;
      ComputeNodeBounds(inst, *node);
      g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(g, 1);
      rtcSetGeometryUserData(g, node.get());
      rtcSetGeometryBoundsFunction(g, &NodeBounds, nullptr);
      rtcSetGeometryIntersectFunction(g, node_intersect_);
      inst.node = node.get();
      s.nodes.push_back(std::move(node));
      s.deep = true;
      if (cs.kind == AccelKind::kInstances) {
        nested_masks = true;
        nested_visible &= cs.all_visible;
      }
    }
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(s.scene, g);
    rtcReleaseGeometry(g);
    if (id != k) return absl::InternalError("Embree numbered instances out of order");
    s.children.push_back(&cs);
  }
  // Distinct masks first: instances are many, masks at most 256.
  for (unsigned r = 0; r < 256; ++r) {
    bool all = true;
    for (unsigned m = 0; m < 256 && all; ++m) all = !masks.test(m) || (m & r) != 0;
    s.all_visible.set(r, all && (!nested_masks || nested_visible.test(r)));
  }
  return absl::OkStatus();
}

absl::Status Optix7SceneCache::BuildPrimitives(const unsigned char* bytes, Optix7Scene& s) {
  const AccelHeader& h = *s.header;
  s.time = s.motion;
  s.any_motion = s.motion.moves();
  s.primitive_types = h.kind == AccelKind::kCustom    ? OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM
                      : h.kind == AccelKind::kSpheres ? OPTIX_PRIMITIVE_TYPE_FLAGS_SPHERE
                                                      : OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE;
  const unsigned keys = s.motion.keys;
  const RTCBuildQuality quality = Updatable(h) ? RTC_BUILD_QUALITY_REFIT : QualityOf(bytes, h);
  // Motion triangles stay native in watertight mode: Embree interpolates their vertices.
  const bool watertight = (s.accuracy & TESSERA_ACCURACY_WATERTIGHT) != 0 &&
                          h.kind == AccelKind::kTriangles && keys == 1;
  const auto* inputs = reinterpret_cast<const AccelInput*>(bytes + h.inputs_offset);
  s.custom_boxes.reserve(h.input_count);
  uint32_t sbt_base = 0;
  for (uint32_t i = 0; i < h.input_count; ++i) {
    const AccelInput& in = inputs[i];
    s.sbt_bases.push_back(sbt_base);
    const uint32_t input_base = sbt_base;
    sbt_base += in.num_sbt_records;
    if (in.primitive_count == 0) continue;  // nothing to hit
    RTCGeometry g;
    std::unique_ptr<Optix7WatertightMesh> mesh;
    if (watertight) {
      mesh = std::make_unique<Optix7WatertightMesh>();
      g = NewWatertightGeometry(device_, bytes, in, mesh.get());
      if (g == nullptr) return absl::ResourceExhaustedError("Embree could not make a geometry");
    } else if (h.kind == AccelKind::kTriangles || h.kind == AccelKind::kSpheres) {
      const bool spheres = h.kind == AccelKind::kSpheres;
      g = rtcNewGeometry(device_,
                         spheres ? RTC_GEOMETRY_TYPE_SPHERE_POINT : RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetGeometryTimeStepCount(g, keys);
      // Copies: Embree reads vertices 16 bytes at a time, past the end of the last.
      const size_t vertex_bytes = spheres ? 16 : 12;
      bool allocated = true;
      for (unsigned k = 0; k < keys; ++k) {
        void* v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, k,
                                          spheres ? RTC_FORMAT_FLOAT4 : RTC_FORMAT_FLOAT3,
                                          vertex_bytes, in.vertex_count);
        if (v == nullptr) {
          allocated = false;
          break;
        }
        std::memcpy(v, bytes + in.vertices_offset + vertex_bytes * in.vertex_count * k,
                    vertex_bytes * in.vertex_count);
      }
      if (allocated && !spheres) {
        void* x = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12,
                                          in.primitive_count);
        if (x != nullptr) {
          std::memcpy(x, bytes + in.indices_offset, 12ull * in.primitive_count);
        } else {
          allocated = false;
        }
      }
      if (!allocated) {
        rtcReleaseGeometry(g);
        return absl::ResourceExhaustedError("Embree could not allocate vertex buffers");
      }
    } else {
      g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryTimeStepCount(g, keys);
      rtcSetGeometryUserPrimitiveCount(g, in.primitive_count);
      s.custom_boxes.push_back(Optix7Scene::Boxes{
          reinterpret_cast<const float*>(bytes + in.aabbs_offset), in.primitive_count});
      rtcSetGeometryUserData(g, &s.custom_boxes.back());
      rtcSetGeometryBoundsFunction(g, &BoundsFromDescriptor, nullptr);
      rtcSetGeometryIntersectFunction(g, intersect_);
    }
    rtcSetGeometryBuildQuality(g, quality);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(s.scene, g);
    rtcReleaseGeometry(g);
    if (id != s.input_of_geometry.size()) {
      return absl::InternalError("Embree numbered geometries out of order");
    }
    s.input_of_geometry.push_back(i);
    s.geometries.push_back(Optix7Scene::Geometry{in, input_base});
    s.watertight.push_back(std::move(mesh));
  }
  s.sbt_bases.push_back(sbt_base);
  return absl::OkStatus();
}

Optix7Scene* Optix7SceneCache::Refit(uint64_t handle, const AccelHeader& h, uint64_t key) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(handle);
  const auto* inputs = reinterpret_cast<const AccelInput*>(bytes + h.inputs_offset);
  for (uint32_t i = 0; i < h.input_count; ++i) {
    if ((inputs[i].flags & memory::kAccelInputUpdate) == 0) return nullptr;  // a build
  }
  auto u = updatable_.find(handle);
  if (u == updatable_.end()) return nullptr;
  auto it = by_hash_.find(u->second);
  if (it == by_hash_.end()) return nullptr;
  Optix7Scene& s = *it->second;
  // OptiX requires an update's inputs to match the build's but for positions (and boxes); one
  // that does not is built anew.
  const AccelHeader& old = *s.header;
  const Optix7Motion motion = MotionOf(h);
  if (s.updatable != handle || s.kind != h.kind || old.input_count != h.input_count ||
      old.build_flags != h.build_flags || s.accuracy != AccuracyOf(h) ||
      s.motion.keys != motion.keys || s.motion.flags != motion.flags ||
      s.motion.begin != motion.begin || s.motion.end != motion.end ||
      s.geometries.size() > h.input_count) {
    return nullptr;
  }
  for (size_t gi = 0; gi < s.geometries.size(); ++gi) {
    const AccelInput& was = s.geometries[gi].input;
    const AccelInput& in = inputs[s.input_of_geometry[gi]];
    if (was.primitive_count != in.primitive_count || was.vertex_count != in.vertex_count ||
        was.num_sbt_records != in.num_sbt_records) {
      return nullptr;
    }
    if (h.kind == AccelKind::kTriangles) {
      RTCGeometry g = rtcGetGeometry(s.scene, static_cast<unsigned>(gi));
      const void* indices = s.watertight[gi] != nullptr
                                ? static_cast<const void*>(s.watertight[gi]->indices.data())
                                : rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0);
      if (std::memcmp(indices, bytes + in.indices_offset, 12ull * in.primitive_count) != 0) {
        return nullptr;
      }
    }
  }
  // The same topology: new positions into the geometries Embree holds, then a refit.
  for (size_t gi = 0; gi < s.geometries.size(); ++gi) {
    const uint32_t input = s.input_of_geometry[gi];
    const AccelInput& in = inputs[input];
    RTCGeometry g = rtcGetGeometry(s.scene, static_cast<unsigned>(gi));
    if (s.watertight[gi] != nullptr) {
      std::memcpy(s.watertight[gi]->vertices.data(), bytes + in.vertices_offset,
                  12ull * in.vertex_count);
    } else if (h.kind == AccelKind::kTriangles || h.kind == AccelKind::kSpheres) {
      const size_t vertex_bytes = h.kind == AccelKind::kSpheres ? 16 : 12;
      for (unsigned k = 0; k < motion.keys; ++k) {
        std::memcpy(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, k),
                    bytes + in.vertices_offset + vertex_bytes * in.vertex_count * k,
                    vertex_bytes * in.vertex_count);
        rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, k);
      }
    } else {
      // Custom primitives read their boxes from the descriptor, which an update rewrote in place.
      auto* boxes = static_cast<Optix7Scene::Boxes*>(rtcGetGeometryUserData(g));
      boxes->boxes = reinterpret_cast<const float*>(bytes + in.aabbs_offset);
    }
    rtcCommitGeometry(g);
    s.geometries[gi].input = in;
  }
  s.header = &h;
  if (!Committed(device_, s.scene, "a refit OptiX 7 acceleration").ok()) return nullptr;
  ++s.refits;
  ++refitted_;
  // IAS scenes over the refit scene hold its old bounds: forget them (their keys named the
  // scene's old content, so no launch from now on asks for them), and those over them.
  std::vector<const Optix7Scene*> stale{&s};
  for (bool more = true; more;) {
    more = false;
    for (auto e = by_hash_.begin(); e != by_hash_.end();) {
      const Optix7Scene& ias = *e->second;
      const bool over = ias.kind == AccelKind::kInstances &&
                        std::any_of(ias.children.begin(), ias.children.end(), [&](const auto* c) {
                          return std::find(stale.begin(), stale.end(), c) != stale.end();
                        });
      if (!over) {
        ++e;
        continue;
      }
      stale.push_back(&ias);
      for (auto l = this_launch_.begin(); l != this_launch_.end();) {
        l = l->second == &ias ? this_launch_.erase(l) : std::next(l);
      }
      e = by_hash_.erase(e);
      more = true;
    }
  }
  std::unique_ptr<Optix7Scene> owned = std::move(by_hash_[u->second]);
  by_hash_.erase(u->second);
  u->second = key;
  Optix7Scene* result = owned.get();
  by_hash_[key] = std::move(owned);
  return result;
}

absl::StatusOr<const Optix7Scene*> Optix7SceneCache::GetAt(uint64_t handle, unsigned depth) {
  if (IsTransformHandle(handle)) {
    return absl::InvalidArgumentError(
        absl::StrCat("traversable handle 0x", absl::Hex(handle),
                     " is a transform: optixTrace and the primitive queries take an acceleration"));
  }
  const size_t available = handle == 0 ? 0 : readable_(handle);
  if (available == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("traversable handle 0x", absl::Hex(handle), " is not in device memory"));
  }
  absl::StatusOr<const AccelHeader*> read =
      memory::ReadAccelHeader(reinterpret_cast<const void*>(handle), available);
  if (!read.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("traversable handle 0x", absl::Hex(handle), ": ", read.status().message()));
  }
  const AccelHeader& h = **read;
  uint64_t key;
  if (h.kind == AccelKind::kInstances) {
    absl::StatusOr<uint64_t> k = KeyOf(handle, depth);
    if (!k.ok()) return k.status();
    key = *k;
  } else {
    key = GasKey(handle, h);
  }
  if (auto it = by_hash_.find(key); it != by_hash_.end()) return it->second.get();
  if (Updatable(h)) {
    if (Optix7Scene* refit = Refit(handle, h, key); refit != nullptr) return refit;
  }

  const auto* bytes = reinterpret_cast<const unsigned char*>(handle);
  auto s = std::make_unique<Optix7Scene>();
  s->kind = h.kind;
  s->header = &h;
  s->motion = MotionOf(h);
  s->accuracy = AccuracyOf(h);
  s->scene = rtcNewScene(device_);
  // Traces that need per-hit decisions on triangles (any-hit programs, culling, masks) pass a
  // filter in their intersect context; the others pass none and pay nothing for it.
  int flags = RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;
  if (s->accuracy & TESSERA_ACCURACY_ROBUST) flags |= RTC_SCENE_FLAG_ROBUST;
  if (s->accuracy & TESSERA_ACCURACY_COMPACT) flags |= RTC_SCENE_FLAG_COMPACT;
  // Embree refits geometries of REFIT quality in a dynamic scene when only their buffers changed.
  if (Updatable(h)) {
    flags |= RTC_SCENE_FLAG_DYNAMIC;
    s->updatable = handle;
  }
  rtcSetSceneFlags(s->scene, static_cast<RTCSceneFlags>(flags));
  rtcSetSceneBuildQuality(s->scene, QualityOf(bytes, h));
  if (h.kind == AccelKind::kInstances) {
    if (absl::Status st = BuildInstances(handle, depth, *s); !st.ok()) return st;
  } else {
    if (absl::Status st = BuildPrimitives(bytes, *s); !st.ok()) return st;
  }
  if (absl::Status st = Committed(device_, s->scene, "an OptiX 7 acceleration"); !st.ok()) {
    return st;
  }
  s->packets = std::none_of(s->watertight.begin(), s->watertight.end(),
                            [](const auto& mesh) { return mesh != nullptr; });
  if (s->kind == AccelKind::kCustom) s->packets = false;
  if (s->kind == AccelKind::kInstances) {
    s->packets = !s->deep && std::all_of(s->children.begin(), s->children.end(),
                                         [](const Optix7Scene* c) { return c->packets; });
  }
  ++built_;
  const Optix7Scene* result = s.get();
  by_hash_[key] = std::move(s);
  if (Updatable(h)) updatable_[handle] = key;
  return result;
}

}  // namespace tessera::worker
