// Accuracy kernels shared by the OptiX 3 and OptiX 7 engines (docs/accuracy.md):
//  - a watertight ray/triangle test (Woop, Benthin, Wald, "Watertight Ray/Triangle Intersection",
//    JCGT 2013): the ray is sheared so that it runs along +z from the origin, and each edge
//    function depends only on the edge's two transformed vertices, so two triangles that share an
//    edge compute the same value for it with opposite signs and a ray cannot pass between them.
//    Edge functions that come out exactly 0 in float are recomputed in double, as the paper does.
//  - the floating-point error bound of a triangle hit point and the offset that moves a secondary
//    ray's origin past it (pbrt-v4 §6.8.4-6.8.6): no self-intersection without a scene_epsilon.
#ifndef TESSERA_WORKER_CORE_WATERTIGHT_H_
#define TESSERA_WORKER_CORE_WATERTIGHT_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "float_steps.h"

// Contracting a*b - c*d into a fused multiply-add would round the two products differently, and
// the edge function of a shared edge would no longer be exactly the negation of its neighbour's.
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")

namespace tessera::worker {

// A ray prepared for WatertightHit: the axis it mostly runs along (kz), the other two (kx, ky,
// swapped for a negative kz component so that the winding is kept), and the shear.
struct WatertightRay {
  float org[3];
  int kx, ky, kz;
  float sx, sy, sz;
};

inline WatertightRay PrepareWatertight(const float org[3], const float dir[3]) {
  WatertightRay r;
  for (int k = 0; k < 3; ++k) r.org[k] = org[k];
  const float ax = std::fabs(dir[0]), ay = std::fabs(dir[1]), az = std::fabs(dir[2]);
  r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = r.kz == 2 ? 0 : r.kz + 1;
  r.ky = r.kx == 2 ? 0 : r.kx + 1;
  if (dir[r.kz] < 0.f) {
    const int t = r.kx;
    r.kx = r.ky;
    r.ky = t;
  }
  r.sx = dir[r.kx] / dir[r.kz];
  r.sy = dir[r.ky] / dir[r.kz];
  r.sz = 1.f / dir[r.kz];
  return r;
}

// A hit of WatertightHit: t and Embree's barycentrics (the hit is (1-u-v)*a + u*b + v*c), and the
// geometric normal (b - a) x (c - a), unnormalized, as Embree reports it.
struct TriangleHit {
  float t, u, v;
  float ng[3];
};

// Whether `r` hits triangle (a, b, c) at a t with tmin <= t <= tmax, either face. (The OptiX 3
// engine passes the float after its ray's tmin, as it does to Embree's robust mode, which also
// takes t == tnear: (tmin, tmax] in every mode.) A degenerate triangle (zero area seen along the
// ray) is never hit.
inline bool WatertightHit(const WatertightRay& r, const float* a, const float* b, const float* c,
                          float tmin, float tmax, TriangleHit* hit) {
  const float a0 = a[0] - r.org[0], a1 = a[1] - r.org[1], a2 = a[2] - r.org[2];
  const float b0 = b[0] - r.org[0], b1 = b[1] - r.org[1], b2 = b[2] - r.org[2];
  const float c0 = c[0] - r.org[0], c1 = c[1] - r.org[1], c2 = c[2] - r.org[2];
  const float A[3] = {a0, a1, a2}, B[3] = {b0, b1, b2}, C[3] = {c0, c1, c2};
  const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  if (u == 0.f || v == 0.f || w == 0.f) {
    // The products of floats are exact in double: the sign is then the true sign of the edge
    // function of the transformed vertices, the same for both triangles of an edge.
    u = static_cast<float>(double{cx} * by - double{cy} * bx);
    v = static_cast<float>(double{ax} * cy - double{ay} * cx);
    w = static_cast<float>(double{bx} * ay - double{by} * ax);
  }
  if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
  const float det = u + v + w;
  if (det == 0.f || !std::isfinite(det)) return false;
  const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
  const float tscaled = u * az + v * bz + w * cz;
  // A division, not a product with 1/det: it is exact where the hit is (t == tmax exactly when
  // the triangle lies at tmax).
  const float t = tscaled / det;
  const float inv = 1.f / det;
  if (!(t >= tmin && t <= tmax)) return false;  // NaN fails
  hit->t = t;
  hit->u = v * inv;
  hit->v = w * inv;
  const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  hit->ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
  hit->ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
  hit->ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
  return true;
}

// Moves a watertight triangle's box (its vertices' bounds) out to what Embree's traversal needs to
// reach every ray the test hits: Embree's box test is not conservative for user geometry, robust
// or not (rays through the vertices of a sphere of radius 1e-6 missed 48 of 1284 boxes; a ulp of
// each coordinate still missed 24, at coordinates near 0). Two ulps of the box's largest
// coordinate, on every side, missed none at any offset and scale tested (tests/extremes).
inline void PadWatertightBounds(float lo[3], float hi[3]) {
  float extent = std::numeric_limits<float>::min();
  for (int k = 0; k < 3; ++k)
    extent = std::fmax(extent, std::fmax(std::fabs(lo[k]), std::fabs(hi[k])));
  const float pad = extent * 0x1p-22f;
  for (int k = 0; k < 3; ++k) {
    lo[k] -= pad;
    hi[k] += pad;
  }
}

// The box the watertight test's user geometry gives Embree for triangle (a, b, c): its vertices'
// bounds, padded (PadWatertightBounds); an empty box, never hit, for a vertex that is not finite,
// as Embree drops such native triangles.
inline void WatertightBox(const float* a, const float* b, const float* c, float lo[3],
                          float hi[3]) {
  bool finite = true;
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::fmin(a[k], std::fmin(b[k], c[k]));
    hi[k] = std::fmax(a[k], std::fmax(b[k], c[k]));
    finite = finite && std::isfinite(a[k]) && std::isfinite(b[k]) && std::isfinite(c[k]);
  }
  if (finite) {
    PadWatertightBounds(lo, hi);
    return;
  }
  for (int k = 0; k < 3; ++k) lo[k] = 1.f, hi[k] = -1.f;
}

// pbrt's gamma(n): a bound on the relative error of n float operations.
constexpr float Gamma(int n) {
  constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (n * eps) / (1 - n * eps);
}

// A point with a per-component absolute error bound.
struct BoundedPoint {
  float p[3];
  float err[3];
};

// The hit point (1-u-v)*a + u*b + v*c of a triangle and its error bound (pbrt-v4 §6.8.5: the
// point lies on the triangle's plane within `err`, whatever error u and v carry).
inline BoundedPoint TrianglePoint(const float* a, const float* b, const float* c, float u,
                                  float v) {
  BoundedPoint out;
  const float w = 1.f - u - v;
  for (int k = 0; k < 3; ++k) {
    out.p[k] = w * a[k] + u * b[k] + v * c[k];
    out.err[k] = Gamma(7) * (std::fabs(w * a[k]) + std::fabs(u * b[k]) + std::fabs(v * c[k]));
  }
  return out;
}

// `pt` moved by the affine 3x4 row-major matrix `m`, with the error bound carried through
// (pbrt-v4 Transform::operator()(Point3fi)).
inline BoundedPoint TransformPoint(const float* m, const BoundedPoint& pt) {
  BoundedPoint out;
  for (int r = 0; r < 3; ++r) {
    const float* row = m + 4 * r;
    out.p[r] = row[0] * pt.p[0] + row[1] * pt.p[1] + row[2] * pt.p[2] + row[3];
    out.err[r] = Gamma(3) * (std::fabs(row[0] * pt.p[0]) + std::fabs(row[1] * pt.p[1]) +
                             std::fabs(row[2] * pt.p[2]) + std::fabs(row[3])) +
                 (Gamma(3) + 1.f) * (std::fabs(row[0]) * pt.err[0] + std::fabs(row[1]) * pt.err[1] +
                                     std::fabs(row[2]) * pt.err[2]);
  }
  return out;
}

// What OffsetRayOrigin computes of a point and its surface normal before it looks at a ray's
// direction: a hit's rays (a path tracer's shadow rays and next bounce) share it.
struct SpawnBase {
  float p[3];
  float m[3];   // the normal scaled by a power of two
  float scale;  // the error bound projected on the normal, over |m|^2: the offset is scale * m
  bool valid;   // false: the normal is zero, infinite or NaN, and rays start at p itself
};

inline SpawnBase PrepareSpawn(const BoundedPoint& pt, const float n[3]) {
  // The bound projected on the unit normal, times the unit normal, is (sum |n_k| err_k) n / |n|^2:
  // no square root, and n scaled exactly by the power of two that brings its largest component
  // into [1, 2) keeps |n|^2 in [1, 12) whatever the triangle's size, for one division.
  SpawnBase b;
  for (int k = 0; k < 3; ++k) b.p[k] = pt.p[k];
  const float sum = std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]);  // NaN stays NaN
  b.valid = sum > 0.f && sum <= std::numeric_limits<float>::max();
  if (!b.valid) return b;
  // No NaN gets here (the sum is finite), so plain compares, not libm's out-of-line fmaxf.
  const float a0 = std::fabs(n[0]), a1 = std::fabs(n[1]), a2 = std::fabs(n[2]);
  const float a01 = a0 > a1 ? a0 : a1;
  const float largest = a01 > a2 ? a01 : a2;
  uint32_t largest_bits;
  std::memcpy(&largest_bits, &largest, sizeof(largest_bits));
  // 2^-e for largest in [2^e, 2^(e+1)): the exponent field mirrored about 127. A subnormal
  // largest is scaled by 2^126 (to at least 2^-23) and one of 2^127 or more by 2^-126 (below 4).
  const uint32_t e = std::clamp<uint32_t>(largest_bits >> 23, 1u, 253u);
  const uint32_t inv_bits = (254u - e) << 23;
  float inv;
  std::memcpy(&inv, &inv_bits, sizeof(inv));
  for (int k = 0; k < 3; ++k) b.m[k] = n[k] * inv;
  const float norm2 = b.m[0] * b.m[0] + b.m[1] * b.m[1] + b.m[2] * b.m[2];
  b.scale = (std::fabs(b.m[0]) * pt.err[0] + std::fabs(b.m[1]) * pt.err[1] +
             std::fabs(b.m[2]) * pt.err[2]) /
            norm2;
  return b;
}

// The origin for a ray leaving in direction `dir`: the point moved along the normal to the side
// `dir` points to, each component then rounded away from the point.
inline void SpawnToward(const SpawnBase& b, const float dir[3], float out[3]) {
  if (!b.valid) {
    for (int k = 0; k < 3; ++k) out[k] = b.p[k];
    return;
  }
  float scale = b.scale;
  if (dir[0] * b.m[0] + dir[1] * b.m[1] + dir[2] * b.m[2] < 0.f) scale = -scale;
  for (int k = 0; k < 3; ++k) {
    const float offset = scale * b.m[k];
    const float o = b.p[k] + offset;
    out[k] = offset > 0.f ? NextFloatUp(o) : offset < 0.f ? NextFloatDown(o) : o;
  }
}

// The origin for a ray leaving `pt` in direction `dir` from a surface with normal `n` (any
// length, either orientation): `pt` moved along n, to the side `dir` points to, by the error
// bound projected on n, each component then rounded away from the point (pbrt-v4
// OffsetRayOrigin). A ray from there cannot hit the surface `pt` lies on again at t >= 0.
inline void OffsetRayOrigin(const BoundedPoint& pt, const float n[3], const float dir[3],
                            float out[3]) {
  SpawnToward(PrepareSpawn(pt, n), dir, out);
}

// TESSERA_ACCURACY_OFFSET_RAYS: whether a ray a hit program traces from `origin` starts at that
// program's hit point `hit` (world space), so that it should start at the spawn point instead. A
// program computes the point as o + t*d of the ray it was hit by, which rounds within a few ulps of
// `scale` (|o| + |t*d| per component, that ray's): within 4 error bounds plus Gamma(16) * scale
// counts. A program that moves the origin off the surface itself (by a scene_epsilon along the
// normal, say) is left alone.
inline bool StartsAtHit(const BoundedPoint& hit, const float origin[3], const float scale[3]) {
  for (int k = 0; k < 3; ++k) {
    const float tolerance = 4.f * hit.err[k] + Gamma(16) * scale[k];
    if (!(std::fabs(origin[k] - hit.p[k]) <= tolerance)) return false;
  }
  return true;
}

}  // namespace tessera::worker

#pragma GCC pop_options

#endif  // TESSERA_WORKER_CORE_WATERTIGHT_H_
