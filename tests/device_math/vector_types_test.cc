// Layout, constructors and namespace re-export of the CUDA vector types.
#include <gtest/gtest.h>

#include <cstddef>
#include <type_traits>

#include "optixu/optixu_vector_functions.h"
#include "optixu/optixu_vector_types.h"

namespace {

// Sizes and alignments of CUDA's vector_types.h on 64-bit Linux. Buffers of RT_FORMAT_FLOAT3
// etc. are sized by these numbers on the host, so any drift corrupts data silently.
template <typename T, size_t kSize, size_t kAlign>
constexpr bool HasLayout() {
  return sizeof(T) == kSize && alignof(T) == kAlign && std::is_trivially_copyable_v<T> &&
         std::is_standard_layout_v<T>;
}
static_assert(HasLayout<char1, 1, 1>());
static_assert(HasLayout<char2, 2, 2>());
static_assert(HasLayout<char3, 3, 1>());
static_assert(HasLayout<char4, 4, 4>());
static_assert(HasLayout<uchar1, 1, 1>());
static_assert(HasLayout<uchar2, 2, 2>());
static_assert(HasLayout<uchar3, 3, 1>());
static_assert(HasLayout<uchar4, 4, 4>());
static_assert(HasLayout<short1, 2, 2>());
static_assert(HasLayout<short2, 4, 4>());
static_assert(HasLayout<short3, 6, 2>());
static_assert(HasLayout<short4, 8, 8>());
static_assert(HasLayout<ushort1, 2, 2>());
static_assert(HasLayout<ushort2, 4, 4>());
static_assert(HasLayout<ushort3, 6, 2>());
static_assert(HasLayout<ushort4, 8, 8>());
static_assert(HasLayout<int1, 4, 4>());
static_assert(HasLayout<int2, 8, 8>());
static_assert(HasLayout<int3, 12, 4>());
static_assert(HasLayout<int4, 16, 16>());
static_assert(HasLayout<uint1, 4, 4>());
static_assert(HasLayout<uint2, 8, 8>());
static_assert(HasLayout<uint3, 12, 4>());
static_assert(HasLayout<uint4, 16, 16>());
static_assert(HasLayout<long1, 8, 8>());
static_assert(HasLayout<long2, 16, 16>());
static_assert(HasLayout<long3, 24, 8>());
static_assert(HasLayout<long4, 32, 16>());
static_assert(HasLayout<ulong1, 8, 8>());
static_assert(HasLayout<ulong2, 16, 16>());
static_assert(HasLayout<ulong3, 24, 8>());
static_assert(HasLayout<ulong4, 32, 16>());
static_assert(HasLayout<longlong1, 8, 8>());
static_assert(HasLayout<longlong2, 16, 16>());
static_assert(HasLayout<longlong3, 24, 8>());
static_assert(HasLayout<longlong4, 32, 16>());
static_assert(HasLayout<ulonglong1, 8, 8>());
static_assert(HasLayout<ulonglong2, 16, 16>());
static_assert(HasLayout<ulonglong3, 24, 8>());
static_assert(HasLayout<ulonglong4, 32, 16>());
static_assert(HasLayout<float1, 4, 4>());
static_assert(HasLayout<float2, 8, 8>());
static_assert(HasLayout<float3, 12, 4>());
static_assert(HasLayout<float4, 16, 16>());
static_assert(HasLayout<double1, 8, 8>());
static_assert(HasLayout<double2, 16, 16>());
static_assert(HasLayout<double3, 24, 8>());
static_assert(HasLayout<double4, 32, 16>());
static_assert(sizeof(dim3) == 12 && std::is_trivially_copyable_v<dim3>);

// Components are laid out x, y, z, w with no padding between them.
static_assert(offsetof(float4, x) == 0 && offsetof(float4, y) == 4 && offsetof(float4, z) == 8 &&
              offsetof(float4, w) == 12);
static_assert(offsetof(uchar4, w) == 3 && offsetof(int3, z) == 8 && offsetof(double2, y) == 8);

// CUDA's char vectors hold signed char whatever the signedness of plain char.
static_assert(std::is_same_v<decltype(char1::x), signed char>);
static_assert(std::is_same_v<decltype(uchar4::w), unsigned char>);
static_assert(std::is_same_v<decltype(long2::y), long>);

// Aggregates, as in CUDA: brace initialization works and they have no constructors.
static_assert(std::is_aggregate_v<float3> && std::is_aggregate_v<uint2>);
static_assert(std::is_trivially_default_constructible_v<float4>);

// The optix:: names are the global types, not copies.
static_assert(std::is_same_v<optix::float3, ::float3>);
static_assert(std::is_same_v<optix::uchar4, ::uchar4>);
static_assert(std::is_same_v<optix::ulonglong2, ::ulonglong2>);
static_assert(std::is_same_v<optix::dim3, ::dim3>);

TEST(VectorTypesTest, MakeFunctionsFillComponentsInOrder) {
  const float4 f = make_float4(1.0f, 2.0f, 3.0f, 4.0f);
  EXPECT_EQ(f.x, 1.0f);
  EXPECT_EQ(f.y, 2.0f);
  EXPECT_EQ(f.z, 3.0f);
  EXPECT_EQ(f.w, 4.0f);

  const char3 c = make_char3(-1, 2, -128);
  EXPECT_EQ(c.x, -1);
  EXPECT_EQ(c.y, 2);
  EXPECT_EQ(c.z, -128);

  const uchar4 u = make_uchar4(255, 0, 128, 7);
  EXPECT_EQ(u.x, 255);
  EXPECT_EQ(u.z, 128);
  EXPECT_EQ(u.w, 7);

  const ushort2 s = make_ushort2(65535, 1);
  EXPECT_EQ(s.x, 65535);
  EXPECT_EQ(s.y, 1);

  const int3 i = make_int3(-7, 0, 7);
  EXPECT_EQ(i.x, -7);
  EXPECT_EQ(i.z, 7);

  const uint1 u1 = make_uint1(0xFFFFFFFFu);
  EXPECT_EQ(u1.x, 0xFFFFFFFFu);

  const long2 l = make_long2(-(1L << 40), 1L << 40);
  EXPECT_EQ(l.x, -(1L << 40));
  EXPECT_EQ(l.y, 1L << 40);

  const ulonglong4 ull = make_ulonglong4(1, 2, 3, ~0ull);
  EXPECT_EQ(ull.w, ~0ull);

  const longlong2 ll = make_longlong2(-5, 5);
  EXPECT_EQ(ll.x, -5);

  const double2 d = make_double2(0.1, -0.2);
  EXPECT_EQ(d.x, 0.1);
  EXPECT_EQ(d.y, -0.2);

  const short4 sh = make_short4(-32768, 32767, 0, 1);
  EXPECT_EQ(sh.x, -32768);
  EXPECT_EQ(sh.y, 32767);
}

TEST(VectorTypesTest, MakeFunctionsAreConstexpr) {
  constexpr float3 v = make_float3(1.0f, 2.0f, 3.0f);
  static_assert(v.y == 2.0f);
  constexpr uint2 u = make_uint2(4, 5);
  static_assert(u.x + u.y == 9);
  EXPECT_EQ(v.z, 3.0f);
}

TEST(VectorTypesTest, BraceInitialization) {
  float3 v = {0.437f, 0.084f, 0};
  EXPECT_FLOAT_EQ(v.x, 0.437f);
  EXPECT_EQ(v.z, 0.0f);
  float4 zero = {};
  EXPECT_EQ(zero.w, 0.0f);
}

TEST(VectorTypesTest, OptixNamespaceReexportsMakeFunctions) {
  const optix::float3 v = optix::make_float3(1.0f, 2.0f, 3.0f);
  const float3 w = make_float3(1.0f, 2.0f, 3.0f);
  EXPECT_EQ(v.x, w.x);
  EXPECT_EQ(v.y, w.y);
  EXPECT_EQ(v.z, w.z);
  using namespace optix;
  // Both the global and the re-exported declaration are visible here; they name one function.
  const uint4 u = make_uint4(1, 2, 3, 4);
  EXPECT_EQ(u.w, 4u);
}

TEST(VectorTypesTest, Dim3DefaultsAndConversions) {
  const dim3 a;
  EXPECT_EQ(a.x, 1u);
  EXPECT_EQ(a.y, 1u);
  EXPECT_EQ(a.z, 1u);
  const dim3 b(640, 480);
  EXPECT_EQ(b.x, 640u);
  EXPECT_EQ(b.y, 480u);
  EXPECT_EQ(b.z, 1u);
  const dim3 c = make_uint3(2, 3, 4);
  EXPECT_EQ(c.z, 4u);
  const uint3 d = b;
  EXPECT_EQ(d.x, 640u);
  EXPECT_EQ(d.z, 1u);
}

}  // namespace
