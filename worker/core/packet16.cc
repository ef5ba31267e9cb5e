#include "packet16.h"

namespace tessera::worker {

void IntersectPacket16(RTCScene scene, const int* valid, RTCRayHit* const* rays) {
  constexpr int kLanes = 16;
  alignas(64) RTCRayHit16 packet;
  alignas(64) int mask[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    mask[k] = valid[k];
    if (!valid[k]) continue;
    const RTCRay& r = rays[k]->ray;
    packet.ray.org_x[k] = r.org_x;
    packet.ray.org_y[k] = r.org_y;
    packet.ray.org_z[k] = r.org_z;
    packet.ray.tnear[k] = r.tnear;
    packet.ray.dir_x[k] = r.dir_x;
    packet.ray.dir_y[k] = r.dir_y;
    packet.ray.dir_z[k] = r.dir_z;
    packet.ray.time[k] = r.time;
    packet.ray.tfar[k] = r.tfar;
    packet.ray.mask[k] = r.mask;
    packet.ray.id[k] = r.id;
    packet.ray.flags[k] = r.flags;
    packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect16(mask, scene, &context, &packet);
  for (int k = 0; k < kLanes; ++k) {
    if (!valid[k]) continue;
    RTCRayHit& rh = *rays[k];
    rh.ray.tfar = packet.ray.tfar[k];
    rh.hit.geomID = packet.hit.geomID[k];
    rh.hit.primID = packet.hit.primID[k];
    rh.hit.instID[0] = packet.hit.instID[0][k];
    rh.hit.u = packet.hit.u[k];
    rh.hit.v = packet.hit.v[k];
    rh.hit.Ng_x = packet.hit.Ng_x[k];
    rh.hit.Ng_y = packet.hit.Ng_y[k];
    rh.hit.Ng_z = packet.hit.Ng_z[k];
  }
}

}  // namespace tessera::worker
