// Layout and construction of optix::Ray.
#include <gtest/gtest.h>

#include <cstddef>
#include <type_traits>

#include "internal/optix_datatypes.h"

namespace {

using optix::Ray;

// The engine moves rays between programs as raw bytes in this exact layout.
static_assert(sizeof(Ray) == 36 && alignof(Ray) == 4);
static_assert(offsetof(Ray, origin) == 0 && offsetof(Ray, direction) == 12 &&
              offsetof(Ray, ray_type) == 24 && offsetof(Ray, tmin) == 28 &&
              offsetof(Ray, tmax) == 32);
static_assert(std::is_trivially_copyable_v<Ray> && std::is_standard_layout_v<Ray> &&
              std::is_trivially_default_constructible_v<Ray>);

TEST(RayTest, DefaultMax) {
  EXPECT_EQ(RT_DEFAULT_MAX, 1.e27f);
  static_assert(std::is_same_v<decltype(RT_DEFAULT_MAX), float>);
}

TEST(RayTest, MakeRayFillsEveryMember) {
  const Ray ray = optix::make_Ray(make_float3(1.0f, 2.0f, 3.0f), make_float3(0.0f, 0.0f, -1.0f), 2u,
                                  0.01f, 100.0f);
  EXPECT_EQ(ray.origin.x, 1.0f);
  EXPECT_EQ(ray.origin.z, 3.0f);
  EXPECT_EQ(ray.direction.z, -1.0f);
  EXPECT_EQ(ray.ray_type, 2u);
  EXPECT_EQ(ray.tmin, 0.01f);
  EXPECT_EQ(ray.tmax, 100.0f);
}

TEST(RayTest, ConstructorDefaultsTmaxToDefaultMax) {
  const Ray ray(make_float3(0.0f, 0.0f, 0.0f), make_float3(1.0f, 0.0f, 0.0f), 1u, 0.5f);
  EXPECT_EQ(ray.ray_type, 1u);
  EXPECT_EQ(ray.tmin, 0.5f);
  EXPECT_EQ(ray.tmax, RT_DEFAULT_MAX);
  constexpr Ray constant(make_float3(0.0f, 0.0f, 0.0f), make_float3(1.0f, 0.0f, 0.0f), 0u, 0.0f);
  static_assert(constant.tmax == RT_DEFAULT_MAX);
}

TEST(RayTest, ValueInitializationZeroes) {
  const Ray ray = {};
  EXPECT_EQ(ray.origin.x, 0.0f);
  EXPECT_EQ(ray.ray_type, 0u);
  EXPECT_EQ(ray.tmax, 0.0f);
}

}  // namespace
