// optix::Aabb: an axis-aligned bounding box with the members OptiX 3 gives it, for bounding box
// programs and host-side scene code.
//
// A box is valid when m_min <= m_max on every axis; a single point is a valid, empty box. A
// default-constructed box is invalid with m_min at +FLT_MAX and m_max at -FLT_MAX, so that
// include() of anything makes it exactly that thing. FLT_MAX rather than infinity keeps this
// working under -ffast-math.
#ifndef OPTIXU_OPTIXU_AABB_NAMESPACE_H_
#define OPTIXU_OPTIXU_AABB_NAMESPACE_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include <cfloat>
#include <cmath>

#include "optixu_math_namespace.h"
#include "optixu_vector_types.h"

namespace optix {

class Aabb {
 public:
  Aabb() { invalidate(); }
  Aabb(const float3& min, const float3& max) { set(min, max); }
  // The bounds of a triangle.
  Aabb(const float3& v0, const float3& v1, const float3& v2) { set(v0, v1, v2); }

  bool operator==(const Aabb& other) const {
    return m_min.x == other.m_min.x && m_min.y == other.m_min.y && m_min.z == other.m_min.z &&
           m_max.x == other.m_max.x && m_max.y == other.m_max.y && m_max.z == other.m_max.z;
  }

  // 0 is m_min, 1 is m_max.
  float3& operator[](int i) { return i == 0 ? m_min : m_max; }
  const float3& operator[](int i) const { return i == 0 ? m_min : m_max; }

  // Takes min and max as given: a min above max makes an invalid box.
  void set(const float3& min, const float3& max) {
    m_min = min;
    m_max = max;
  }
  void set(const float3& v0, const float3& v1, const float3& v2) {
    m_min = fminf(v0, fminf(v1, v2));
    m_max = fmaxf(v0, fmaxf(v1, v2));
  }

  void invalidate() {
    m_min = make_float3(FLT_MAX);
    m_max = make_float3(-FLT_MAX);
  }
  bool valid() const { return m_min.x <= m_max.x && m_min.y <= m_max.y && m_min.z <= m_max.z; }

  // Closed-interval tests: points on the boundary are inside.
  bool contains(const float3& p) const {
    return p.x >= m_min.x && p.x <= m_max.x && p.y >= m_min.y && p.y <= m_max.y && p.z >= m_min.z &&
           p.z <= m_max.z;
  }
  bool contains(const Aabb& bb) const { return contains(bb.m_min) && contains(bb.m_max); }

  // Grows the box to cover p, another box, or the box [min, max].
  void include(const float3& p) {
    m_min = fminf(m_min, p);
    m_max = fmaxf(m_max, p);
  }
  void include(const Aabb& other) {
    m_min = fminf(m_min, other.m_min);
    m_max = fmaxf(m_max, other.m_max);
  }
  void include(const float3& min, const float3& max) {
    m_min = fminf(m_min, min);
    m_max = fmaxf(m_max, max);
  }

  float3 center() const { return 0.5f * (m_min + m_max); }
  float center(int dim) const { return 0.5f * (getByIndex(m_min, dim) + getByIndex(m_max, dim)); }
  float3 extent() const { return m_max - m_min; }
  float extent(int dim) const { return getByIndex(m_max, dim) - getByIndex(m_min, dim); }

  // Sizes of an invalid box are 0, not the meaningless products of negative extents.
  float volume() const {
    if (!valid()) return 0.0f;
    const float3 d = extent();
    return d.x * d.y * d.z;
  }
  float area() const { return 2.0f * halfArea(); }
  // Half the surface area: the quantity surface-area heuristics compare.
  float halfArea() const {
    if (!valid()) return 0.0f;
    const float3 d = extent();
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
  // The axis (0, 1, 2 for x, y, z) of the largest extent. Ties go as in OptiX: x only when it
  // is strictly longer than y and z, else y only when strictly longer than z, else z (a cube
  // gives 2).
  int longestAxis() const {
    const float3 d = extent();
    if (d.x > d.y) return d.x > d.z ? 0 : 2;
    return d.y > d.z ? 1 : 2;
  }
  float maxExtent() const { return extent(longestAxis()); }

  // Whether the two closed boxes share at least one point; invalid boxes intersect nothing.
  bool intersects(const Aabb& other) const {
    const float3 lo = fmaxf(m_min, other.m_min);
    const float3 hi = fminf(m_max, other.m_max);
    return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
  }
  // Shrinks this box to its intersection with other; disjoint boxes leave it invalid.
  void intersection(const Aabb& other) {
    m_min = fmaxf(m_min, other.m_min);
    m_max = fminf(m_max, other.m_max);
  }

  // Moves every face outward by amount (inward when negative).
  void enlarge(float amount) {
    m_min -= make_float3(amount);
    m_max += make_float3(amount);
  }

  // Whether the box has zero extent along some axis.
  bool isFlat() const { return m_min.x == m_max.x || m_min.y == m_max.y || m_min.z == m_max.z; }

  // Squared and plain Euclidean distance from x to the box; 0 inside.
  float distance2(const float3& x) const {
    const float3 outside = fmaxf(make_float3(0.0f), fmaxf(m_min - x, x - m_max));
    return dot(outside, outside);
  }
  float distance(const float3& x) const { return tessera_detail::Sqrt(distance2(x)); }
  // Like distance() outside the box; inside, minus the distance to the nearest face.
  float signedDistance(const float3& x) const {
    if (!contains(x)) return distance(x);
    const float3 to_faces = fminf(x - m_min, m_max - x);
    return -fminf(to_faces);
  }

  float3 m_min;
  float3 m_max;
};

}  // namespace optix

#endif  // OPTIXU_OPTIXU_AABB_NAMESPACE_H_
