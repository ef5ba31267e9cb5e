#include "optix7_watertight.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "watertight.h"

namespace tessera::worker {
namespace {

const float* Vertex(const Optix7WatertightMesh& m, uint32_t index) {
  return m.vertices.data() + 3 * size_t{index};
}

// A triangle's box, padded so that Embree's traversal reaches every triangle the watertight test
// would hit (PadWatertightBounds says why).
void WatertightBounds(const RTCBoundsFunctionArguments* args) {
  const auto& m = *static_cast<const Optix7WatertightMesh*>(args->geometryUserPtr);
  const uint32_t* tri = m.indices.data() + 3 * size_t{args->primID};
  float lo[3], hi[3];
  WatertightBox(Vertex(m, tri[0]), Vertex(m, tri[1]), Vertex(m, tri[2]), lo, hi);
  *args->bounds_o = RTCBounds{lo[0], lo[1], lo[2], 0.f, hi[0], hi[1], hi[2], 0.f};
}

// Embree's intersection function of a watertight mesh (one ray: rtcIntersect1). The hit takes
// the place of a native triangle's: Embree's closed interval [tnear, tfar], the context's filter
// (the engine's per-hit decisions) offered it with tfar at its distance, then the ray and hit
// updated as Embree updates them. Non-finite distances are never hits.
void IntersectWatertight(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto& m = *static_cast<const Optix7WatertightMesh*>(args->geometryUserPtr);
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  const float org[3] = {rh->ray.org_x, rh->ray.org_y, rh->ray.org_z};
  const float dir[3] = {rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z};
  const WatertightRay r = PrepareWatertight(org, dir);
  const uint32_t* tri = m.indices.data() + 3 * size_t{args->primID};
  TriangleHit hit;
  if (!WatertightHit(r, Vertex(m, tri[0]), Vertex(m, tri[1]), Vertex(m, tri[2]), rh->ray.tnear,
                     rh->ray.tfar, &hit) ||
      !std::isfinite(hit.t)) {
    return;
  }
  RTCHit candidate;
  candidate.Ng_x = hit.ng[0];
  candidate.Ng_y = hit.ng[1];
  candidate.Ng_z = hit.ng[2];
  candidate.u = hit.u;
  candidate.v = hit.v;
  candidate.primID = args->primID;
  candidate.geomID = args->geomID;
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) {
    candidate.instID[l] = args->context->instID[l];
  }
  const float tfar = rh->ray.tfar;
  rh->ray.tfar = hit.t;
  if (args->context->filter != nullptr) {
    int valid = -1;
    RTCFilterFunctionNArguments filter;
    filter.valid = &valid;
    filter.geometryUserPtr = args->geometryUserPtr;
    filter.context = args->context;
    filter.ray = reinterpret_cast<RTCRayN*>(&rh->ray);
    filter.hit = reinterpret_cast<RTCHitN*>(&candidate);
    filter.N = 1;
    rtcFilterIntersection(args, &filter);
    if (valid == 0) {
      rh->ray.tfar = tfar;
      return;
    }
  }
  rh->hit = candidate;
}

}  // namespace

RTCGeometry NewWatertightGeometry(RTCDevice device, const unsigned char* descriptor,
                                  const memory::AccelInput& in, Optix7WatertightMesh* mesh) {
  mesh->vertices.resize(3 * size_t{in.vertex_count});
  mesh->indices.resize(3 * size_t{in.primitive_count});
  std::memcpy(mesh->vertices.data(), descriptor + in.vertices_offset,
              mesh->vertices.size() * sizeof(float));
  std::memcpy(mesh->indices.data(), descriptor + in.indices_offset,
              mesh->indices.size() * sizeof(uint32_t));
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  if (g == nullptr) return nullptr;
  rtcSetGeometryUserPrimitiveCount(g, in.primitive_count);
  rtcSetGeometryUserData(g, mesh);
  rtcSetGeometryBoundsFunction(g, &WatertightBounds, nullptr);
  rtcSetGeometryIntersectFunction(g, &IntersectWatertight);
  return g;
}

}  // namespace tessera::worker
