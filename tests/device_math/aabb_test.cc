// Numeric tests of optix::Aabb.
#include <gtest/gtest.h>

#include <cmath>
#include <new>
#include <type_traits>

#include "optixu/optixu_aabb.h"
#include "optixu/optixu_aabb_namespace.h"

namespace {

using optix::Aabb;

// A bounding box program writes float result[6]; Aabb is exactly those six floats.
static_assert(sizeof(Aabb) == 6 * sizeof(float));
static_assert(std::is_standard_layout_v<Aabb> && std::is_trivially_copyable_v<Aabb>);

#define EXPECT_FLOAT3_EQ(v, ex, ey, ez) \
  do {                                  \
    EXPECT_FLOAT_EQ((v).x, ex);         \
    EXPECT_FLOAT_EQ((v).y, ey);         \
    EXPECT_FLOAT_EQ((v).z, ez);         \
  } while (0)

TEST(AabbTest, DefaultIsInvalidAndEmpty) {
  const Aabb box;
  EXPECT_FALSE(box.valid());
  EXPECT_EQ(box.volume(), 0.0f);
  EXPECT_EQ(box.area(), 0.0f);
  EXPECT_EQ(box.halfArea(), 0.0f);
  EXPECT_FALSE(box.contains(make_float3(0.0f)));
  EXPECT_FALSE(box.intersects(Aabb(make_float3(-1e30f), make_float3(1e30f))));
}

TEST(AabbTest, IncludePointsAndBoxes) {
  Aabb box;
  box.include(make_float3(1.0f, 2.0f, 3.0f));
  EXPECT_TRUE(box.valid());
  EXPECT_FLOAT3_EQ(box.m_min, 1.0f, 2.0f, 3.0f);
  EXPECT_FLOAT3_EQ(box.m_max, 1.0f, 2.0f, 3.0f);
  EXPECT_TRUE(box.isFlat());
  box.include(make_float3(-1.0f, 5.0f, 3.5f));
  EXPECT_FLOAT3_EQ(box.m_min, -1.0f, 2.0f, 3.0f);
  EXPECT_FLOAT3_EQ(box.m_max, 1.0f, 5.0f, 3.5f);
  EXPECT_FALSE(box.isFlat());

  box.include(Aabb(make_float3(0.0f, 0.0f, 0.0f), make_float3(0.5f, 0.5f, 10.0f)));
  EXPECT_FLOAT3_EQ(box.m_min, -1.0f, 0.0f, 0.0f);
  EXPECT_FLOAT3_EQ(box.m_max, 1.0f, 5.0f, 10.0f);

  box.include(make_float3(-2.0f), make_float3(2.0f));
  EXPECT_FLOAT3_EQ(box.m_min, -2.0f, -2.0f, -2.0f);
  EXPECT_FLOAT3_EQ(box.m_max, 2.0f, 5.0f, 10.0f);

  // Including an invalid box changes nothing.
  const Aabb before = box;
  box.include(Aabb());
  EXPECT_TRUE(box == before);
}

TEST(AabbTest, TriangleConstructor) {
  const Aabb box(make_float3(0.0f, 1.0f, 2.0f), make_float3(3.0f, -1.0f, 2.0f),
                 make_float3(1.0f, 0.0f, 5.0f));
  EXPECT_FLOAT3_EQ(box.m_min, 0.0f, -1.0f, 2.0f);
  EXPECT_FLOAT3_EQ(box.m_max, 3.0f, 1.0f, 5.0f);
}

TEST(AabbTest, SetInvalidateAndIndexing) {
  Aabb box(make_float3(0.0f), make_float3(1.0f));
  EXPECT_TRUE(box.valid());
  box.invalidate();
  EXPECT_FALSE(box.valid());
  box.set(make_float3(1.0f), make_float3(2.0f));
  EXPECT_TRUE(box.valid());
  EXPECT_EQ(box[0].x, 1.0f);
  EXPECT_EQ(box[1].z, 2.0f);
  box[1] = make_float3(4.0f);
  EXPECT_EQ(box.m_max.y, 4.0f);
  // min above max on one axis is invalid.
  box.set(make_float3(0.0f, 2.0f, 0.0f), make_float3(1.0f, 1.0f, 1.0f));
  EXPECT_FALSE(box.valid());
}

TEST(AabbTest, ContainsIsClosed) {
  const Aabb box(make_float3(0.0f), make_float3(1.0f, 2.0f, 3.0f));
  EXPECT_TRUE(box.contains(make_float3(0.5f, 1.0f, 1.5f)));
  EXPECT_TRUE(box.contains(make_float3(0.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(box.contains(make_float3(1.0f, 2.0f, 3.0f)));
  EXPECT_FALSE(box.contains(make_float3(1.0f, 2.0f, 3.0001f)));
  EXPECT_FALSE(box.contains(make_float3(-0.1f, 1.0f, 1.0f)));
  EXPECT_TRUE(box.contains(Aabb(make_float3(0.25f), make_float3(1.0f))));
  EXPECT_TRUE(box.contains(box));
  EXPECT_FALSE(box.contains(Aabb(make_float3(0.25f), make_float3(1.5f))));
}

TEST(AabbTest, MeasuresAndCenter) {
  const Aabb box(make_float3(-1.0f, 0.0f, 2.0f), make_float3(1.0f, 3.0f, 6.0f));
  EXPECT_FLOAT3_EQ(box.center(), 0.0f, 1.5f, 4.0f);
  EXPECT_FLOAT_EQ(box.center(2), 4.0f);
  EXPECT_FLOAT3_EQ(box.extent(), 2.0f, 3.0f, 4.0f);
  EXPECT_FLOAT_EQ(box.extent(1), 3.0f);
  EXPECT_FLOAT_EQ(box.volume(), 24.0f);
  EXPECT_FLOAT_EQ(box.halfArea(), 6.0f + 12.0f + 8.0f);
  EXPECT_FLOAT_EQ(box.area(), 52.0f);
  EXPECT_EQ(box.longestAxis(), 2);
  EXPECT_FLOAT_EQ(box.maxExtent(), 4.0f);
  EXPECT_EQ(Aabb(make_float3(0.0f), make_float3(5.0f, 1.0f, 1.0f)).longestAxis(), 0);
  EXPECT_EQ(Aabb(make_float3(0.0f), make_float3(1.0f, 5.0f, 1.0f)).longestAxis(), 1);
  // Ties as in OptiX: a cube gives z, x == y > z gives y, x == z > y gives z.
  EXPECT_EQ(Aabb(make_float3(0.0f), make_float3(1.0f)).longestAxis(), 2);
  EXPECT_EQ(Aabb(make_float3(0.0f), make_float3(2.0f, 2.0f, 1.0f)).longestAxis(), 1);
  EXPECT_EQ(Aabb(make_float3(0.0f), make_float3(2.0f, 1.0f, 2.0f)).longestAxis(), 2);
}

TEST(AabbTest, IntersectsAndIntersection) {
  Aabb a(make_float3(0.0f), make_float3(2.0f));
  const Aabb b(make_float3(1.0f), make_float3(3.0f));
  const Aabb touching(make_float3(2.0f, 0.0f, 0.0f), make_float3(4.0f, 1.0f, 1.0f));
  const Aabb apart(make_float3(2.5f), make_float3(3.0f));
  EXPECT_TRUE(a.intersects(b));
  EXPECT_TRUE(b.intersects(a));
  EXPECT_TRUE(a.intersects(touching));  // Closed boxes sharing a face intersect.
  EXPECT_FALSE(a.intersects(apart));

  Aabb c = a;
  c.intersection(b);
  EXPECT_TRUE(c.valid());
  EXPECT_FLOAT3_EQ(c.m_min, 1.0f, 1.0f, 1.0f);
  EXPECT_FLOAT3_EQ(c.m_max, 2.0f, 2.0f, 2.0f);
  a.intersection(apart);
  EXPECT_FALSE(a.valid());
  EXPECT_EQ(a.volume(), 0.0f);
}

TEST(AabbTest, EnlargeAndDistances) {
  Aabb box(make_float3(0.0f), make_float3(1.0f));
  box.enlarge(0.5f);
  EXPECT_FLOAT3_EQ(box.m_min, -0.5f, -0.5f, -0.5f);
  EXPECT_FLOAT3_EQ(box.m_max, 1.5f, 1.5f, 1.5f);

  const Aabb unit(make_float3(0.0f), make_float3(1.0f));
  EXPECT_EQ(unit.distance(make_float3(0.5f)), 0.0f);
  EXPECT_FLOAT_EQ(unit.distance(make_float3(4.0f, 0.5f, 0.5f)), 3.0f);
  EXPECT_FLOAT_EQ(unit.distance2(make_float3(-3.0f, 5.0f, 0.5f)), 9.0f + 16.0f);
  EXPECT_FLOAT_EQ(unit.distance(make_float3(-3.0f, 5.0f, 0.5f)), 5.0f);
  EXPECT_FLOAT_EQ(unit.signedDistance(make_float3(0.5f, 0.5f, 0.9f)), -0.1f);
  EXPECT_FLOAT_EQ(unit.signedDistance(make_float3(0.5f, 0.5f, 3.0f)), 2.0f);
  EXPECT_EQ(unit.signedDistance(make_float3(0.5f, 0.5f, 1.0f)), 0.0f);
}

TEST(AabbTest, EqualityComparesBothCorners) {
  const Aabb a(make_float3(0.0f), make_float3(1.0f));
  EXPECT_TRUE(a == Aabb(make_float3(0.0f), make_float3(1.0f)));
  EXPECT_FALSE(a == Aabb(make_float3(0.0f), make_float3(1.0f, 1.0f, 2.0f)));
  EXPECT_FALSE(a == Aabb(make_float3(0.0f, -1.0f, 0.0f), make_float3(1.0f)));
}

TEST(AabbTest, AliasesBoundingBoxProgramResult) {
  // What a bounding box program does with its float result[6].
  alignas(Aabb) float result[6];
  Aabb* aabb = new (result) Aabb(make_float3(-1.0f), make_float3(2.0f, 3.0f, 4.0f));
  EXPECT_EQ(result[0], -1.0f);
  EXPECT_EQ(result[3], 2.0f);
  EXPECT_EQ(result[5], 4.0f);
  EXPECT_TRUE(aabb->valid());
}

}  // namespace
