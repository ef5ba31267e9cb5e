#include "optix7_scene.h"

#include <cstring>

#include "absl/strings/str_cat.h"

namespace tessera::worker {
namespace {

using memory::AccelHeader;
using memory::AccelInput;
using memory::AccelKind;

// The user data of a custom-primitive geometry: a pointer to its boxes, six floats a primitive.
void BoundsFromDescriptor(const RTCBoundsFunctionArguments* args) {
  const float* boxes = *static_cast<const float* const*>(args->geometryUserPtr);
  const float* box = boxes + 6ull * args->primID;
  args->bounds_o->lower_x = box[0];
  args->bounds_o->lower_y = box[1];
  args->bounds_o->lower_z = box[2];
  args->bounds_o->upper_x = box[3];
  args->bounds_o->upper_y = box[4];
  args->bounds_o->upper_z = box[5];
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

// The inverse of a 3x4 row-major affine transform, in double precision (zeros for a singular one,
// which places nothing: Embree refuses such an instance anyway).
void InvertAffine(const float m[12], float out[12]) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
               i = m[10];
  const double co[9] = {e * i - f * h, c * h - b * i, b * f - c * e, f * g - d * i, a * i - c * g,
                        c * d - a * f, d * h - e * g, b * g - a * h, a * e - b * d};
  const double det = a * co[0] + b * co[3] + c * co[6];
  if (det == 0) {
    std::memset(out, 0, 12 * sizeof(float));
    return;
  }
  const double t[3] = {m[3], m[7], m[11]};
  for (int r = 0; r < 3; ++r) {
    double translation = 0;
    for (int k = 0; k < 3; ++k) {
      out[r * 4 + k] = static_cast<float>(co[r * 3 + k] / det);
      translation -= co[r * 3 + k] / det * t[k];
    }
    out[r * 4 + 3] = static_cast<float>(translation);
  }
}

RTCBuildQuality QualityOf(uint32_t build_flags) {
  constexpr uint32_t kPreferFastBuild = 1u << 3;  // OPTIX_BUILD_FLAG_PREFER_FAST_BUILD
  return (build_flags & kPreferFastBuild) != 0 ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM;
}

}  // namespace

Optix7Scene::~Optix7Scene() {
  if (scene != nullptr) rtcReleaseScene(scene);
}

absl::StatusOr<const Optix7Scene*> Optix7SceneCache::Get(uint64_t handle) {
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
  if (auto it = by_hash_.find(h.content_hash); it != by_hash_.end()) return it->second.get();

  auto s = std::make_unique<Optix7Scene>();
  s->kind = h.kind;
  s->header = &h;
  s->scene = rtcNewScene(device_);
  // Traces that need per-hit decisions on triangles (any-hit programs, culling, masks) pass a
  // filter in their intersect context; the others pass none and pay nothing for it.
  rtcSetSceneFlags(s->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(s->scene, QualityOf(h.build_flags));
  const auto* bytes = reinterpret_cast<const unsigned char*>(handle);
  if (h.kind == AccelKind::kInstances) {
    s->instances.reserve(h.primitive_count);
    for (uint64_t k = 0; k < h.primitive_count; ++k) {
      const unsigned char* record = bytes + h.inputs_offset + k * memory::kInstanceBytes;
      Optix7Scene::Instance& inst = s->instances.emplace_back();
      float(&transform)[12] = inst.to_world;
      uint64_t child_handle;
      // OptixInstance layout: transform[12], instanceId, sbtOffset, visibilityMask, flags,
      // traversableHandle.
      std::memcpy(transform, record, sizeof(transform));
      std::memcpy(&inst.id, record + 48, 4);
      std::memcpy(&inst.sbt_offset, record + 52, 4);
      std::memcpy(&inst.mask, record + 56, 4);
      std::memcpy(&inst.flags, record + 60, 4);
      std::memcpy(&child_handle, record + 64, sizeof(child_handle));
      inst.child = child_handle;
      InvertAffine(transform, inst.to_object);
      absl::StatusOr<const Optix7Scene*> child = Get(child_handle);
      if (!child.ok()) {
        return absl::InvalidArgumentError(
            absl::StrCat("instance ", k, ": ", child.status().message()));
      }
      if ((*child)->kind == AccelKind::kInstances) {
        return absl::UnimplementedError(
            absl::StrCat("instance ", k,
                         " names an instance acceleration: more than one instance level is "
                         "not supported yet"));
      }
      RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, (*child)->scene);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, transform);
      rtcCommitGeometry(g);
      rtcAttachGeometry(s->scene, g);
      rtcReleaseGeometry(g);
      s->children.push_back(*child);
    }
    // Distinct masks first: instances are many, masks at most 256.
    std::bitset<256> masks;
    for (const Optix7Scene::Instance& inst : s->instances) masks.set(inst.mask & 0xFFu);
    for (unsigned r = 0; r < 256; ++r) {
      bool all = true;
      for (unsigned m = 0; m < 256 && all; ++m) all = !masks.test(m) || (m & r) != 0;
      s->all_visible.set(r, all);
    }
  } else {
    const auto* inputs = reinterpret_cast<const AccelInput*>(bytes + h.inputs_offset);
    s->custom_boxes.reserve(h.input_count);
    uint32_t sbt_base = 0;
    for (uint32_t i = 0; i < h.input_count; ++i) {
      const AccelInput& in = inputs[i];
      s->sbt_bases.push_back(sbt_base);
      const uint32_t input_base = sbt_base;
      sbt_base += in.num_sbt_records;
      if (in.primitive_count == 0) continue;  // nothing to hit
      RTCGeometry g;
      if (h.kind == AccelKind::kTriangles) {
        g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Copies: Embree reads vertices 16 bytes at a time, past the end of the last.
        void* v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12,
                                          in.vertex_count);
        void* x = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12,
                                          in.primitive_count);
        if (v == nullptr || x == nullptr) {
          rtcReleaseGeometry(g);
          return absl::ResourceExhaustedError("Embree could not allocate triangle buffers");
        }
        std::memcpy(v, bytes + in.vertices_offset, 12ull * in.vertex_count);
        std::memcpy(x, bytes + in.indices_offset, 12ull * in.primitive_count);
      } else {
        g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(g, in.primitive_count);
        s->custom_boxes.push_back(reinterpret_cast<const float*>(bytes + in.aabbs_offset));
        rtcSetGeometryUserData(g, &s->custom_boxes.back());
        rtcSetGeometryBoundsFunction(g, &BoundsFromDescriptor, nullptr);
        rtcSetGeometryIntersectFunction(g, intersect_);
      }
      rtcSetGeometryBuildQuality(g, QualityOf(h.build_flags));
      rtcCommitGeometry(g);
      const unsigned id = rtcAttachGeometry(s->scene, g);
      rtcReleaseGeometry(g);
      if (id != s->input_of_geometry.size()) {
        return absl::InternalError("Embree numbered geometries out of order");
      }
      s->input_of_geometry.push_back(i);
      s->geometries.push_back(Optix7Scene::Geometry{in, input_base});
    }
    s->sbt_bases.push_back(sbt_base);
  }
  if (absl::Status st = Committed(device_, s->scene, "an OptiX 7 acceleration"); !st.ok()) {
    return st;
  }
  ++built_;
  const Optix7Scene* result = s.get();
  by_hash_[h.content_hash] = std::move(s);
  return result;
}

}  // namespace tessera::worker
