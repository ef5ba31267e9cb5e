// Error-bounded hit points of OptiX 7 hits: tesseraOptixGetSpawnPoint (tessera/optix7_accuracy.h)
// and TESSERA_ACCURACY_OFFSET_RAYS, which moves the origin of a ray a closest-hit program traces
// from its hit point to the spawn point (docs/optix7_engine.md, "Speed and accuracy"). The
// arithmetic is watertight.h's, shared with the OptiX 3 engine.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "optix7_thread.h"
#include "optix_types.h"
#include "tessera/accuracy.h"
#include "watertight.h"

namespace tessera::worker {
namespace {

bool IsTriangleHit(const Optix7Hit& h) {
  return h.gas_scene != nullptr && h.gas_scene->kind == memory::AccelKind::kTriangles &&
         h.geometry != nullptr;
}

// The world-space hit point of triangle hit `h` of frame `f` with its error bound, and the
// triangle's world-space normal (unnormalized). `extent`, when given, gets the largest magnitude
// of the triangle's vertices per world component.
BoundedPoint TriangleHitPoint(const Optix7Frame& f, const Optix7Hit& h, float normal[3],
                              float* extent = nullptr) {
  const memory::AccelInput& in = h.geometry->input;
  uint32_t idx[3];
  std::memcpy(idx,
              reinterpret_cast<const void*>(h.gas + in.indices_offset + 12ull * h.local_primitive),
              sizeof(idx));
  float p[3][3];
  const float time = h.gas_scene->time.Normalized(f.ray.ray_time);
  for (int k = 0; k < 3; ++k) Optix7Vertex(h.gas, in, *h.gas_scene, idx[k], time, 3, p[k]);
  if (extent != nullptr) {
    const float* m = h.path.size == 0 ? kIdentity3x4 : h.path.to_world;
    for (int r = 0; r < 3; ++r) {
      extent[r] = 0.f;
      for (const float* q : p) {
        const float* row = m + 4 * r;
        extent[r] = std::max(extent[r], std::fabs(row[0] * q[0]) + std::fabs(row[1] * q[1]) +
                                            std::fabs(row[2] * q[2]) + std::fabs(row[3]));
      }
    }
  }
  float u, v;
  std::memcpy(&u, &h.attributes[0], sizeof(u));
  std::memcpy(&v, &h.attributes[1], sizeof(v));
  BoundedPoint pt = TrianglePoint(p[0], p[1], p[2], u, v);
  if (h.gas_scene->motion.moves()) {
    // Interpolated vertices carry the interpolation's rounding: three more operations each.
    for (int k = 0; k < 3; ++k) {
      pt.err[k] += Gamma(3) * (std::fabs(p[0][k]) + std::fabs(p[1][k]) + std::fabs(p[2][k]));
    }
  }
  const float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  const float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
  const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
  if (h.path.size == 0) {
    std::memcpy(normal, n, sizeof(n));
    return pt;
  }
  // Normals move with the inverse transpose: column k of the world-to-object matrix.
  const float* inv = h.path.to_object;
  for (int k = 0; k < 3; ++k) normal[k] = inv[k] * n[0] + inv[4 + k] * n[1] + inv[8 + k] * n[2];
  BoundedPoint world = TransformPoint(h.path.to_world, pt);
  // Embree moves a traced ray's origin back into object space with a matrix of its own, which
  // rounds as much again: the bound grows by what that costs, seen from world space.
  for (int k = 0; k < 3; ++k) world.err[k] *= 2.f;
  return world;
}

// The point o + t * d of the frame's ray with its bound (three operations a component); the
// program's t is taken as exact.
BoundedPoint RayHitPoint(const Optix7Frame& f, const Optix7Hit& h) {
  BoundedPoint pt;
  for (int k = 0; k < 3; ++k) {
    const float step = h.t * f.ray.direction[k];
    pt.p[k] = f.ray.origin[k] + step;
    pt.err[k] = Gamma(3) * (std::fabs(f.ray.origin[k]) + std::fabs(step));
  }
  return pt;
}

void SpawnPoint(const float direction[3], float out[3]) {
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, KindBit(Optix7Kind::kClosestHit) | KindBit(Optix7Kind::kAnyHit),
            "tesseraOptixGetSpawnPoint");
  const Optix7Frame& f = *ts.ctx.frame;
  const Optix7Hit& h = *ts.ctx.hit;
  if (IsTriangleHit(h)) {
    float n[3];
    const BoundedPoint pt = TriangleHitPoint(f, h, n);
    OffsetRayOrigin(pt, n, direction, out);
    return;
  }
  OffsetRayOrigin(RayHitPoint(f, h), direction, direction, out);
}

}  // namespace

void FillAccuracyTable(TesseraOptix7Runtime& r) { r.spawn_point = &SpawnPoint; }

void OffsetSpawnedRay(const Optix7Thread& ts, TesseraOptix7Trace& ray) {
  if (ts.ctx.kind != Optix7Kind::kClosestHit || ts.ctx.hit == nullptr ||
      !IsTriangleHit(*ts.ctx.hit)) {
    return;
  }
  const Optix7Frame& f = *ts.ctx.frame;
  const Optix7Hit& h = *ts.ctx.hit;
  float n[3], extent[3];
  const BoundedPoint pt = TriangleHitPoint(f, h, n, extent);
  // The program's o + t*d rounds within a few ulps of |o| + |t*d|; Embree's barycentrics, which
  // place `pt`, within a few ulps of the triangle's size: the point may lie that far from `pt`
  // along the surface (an 8x8-square face of a cube of 1e6 put hits 0.01 apart).
  float scale[3];
  for (int k = 0; k < 3; ++k) {
    scale[k] = std::fabs(f.ray.origin[k]) + std::fabs(h.t * f.ray.direction[k]) + extent[k];
  }
  if (!StartsAtHit(pt, ray.origin, scale)) return;
  OffsetRayOrigin(pt, n, ray.direction, ray.origin);
  ray.tmin = 0.f;
}

}  // namespace tessera::worker
