// CUDA intrinsics and optixu math evaluated the same way in a program (intrinsics.cu) and in host
// code (port_corpus_test.cc): each case writes one float, and the two must agree to the bit.
#pragma once

#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>
#include <optixu/optixu_matrix_namespace.h>

constexpr unsigned kIntrinsicCases = 64;

static __host__ __device__ __inline__ void intrinsic_cases(float* out) {
  using namespace optix;
  unsigned k = 0;
  // Single-precision intrinsics.
  out[k++] = __saturatef(1.5f) + __saturatef(-0.5f) + __saturatef(0.25f);
  out[k++] = __fdividef(1.0f, 3.0f);
  out[k++] = __expf(1.5f);
  out[k++] = __sinf(0.7f) + __cosf(0.7f) + __tanf(0.3f);
  out[k++] = __powf(2.5f, 1.7f);
  out[k++] = __logf(7.0f) + __log2f(7.0f) + __log10f(7.0f);
  out[k++] = __exp10f(0.3f);
  float s = 0.0f, c = 0.0f;
  __sincosf(1.1f, &s, &c);
  out[k++] = s - c;
  out[k++] = __frcp_rn(3.0f) + __fsqrt_rn(2.0f) + __frsqrt_rn(4.0f);
  out[k++] = __fmul_rn(1.1f, 3.3f) + __fadd_rn(0.1f, 0.2f) + __fsub_rn(1.0f, 0.3f);
  out[k++] = __fmaf_rn(1.5f, 2.5f, 0.25f) + __fdiv_rn(1.0f, 7.0f);
  out[k++] = rsqrtf(9.0f) + rcbrtf(27.0f) + fdividef(5.0f, 2.0f);
  out[k++] =
      norm3df(1.0f, 2.0f, 2.0f) + rnorm3df(0.0f, 3.0f, 4.0f) + norm4df(1.0f, 1.0f, 1.0f, 1.0f);
  out[k++] = sinpif(0.25f) + cospif(0.25f);
  // Conversions with rounding modes (2.5 and -2.5 tell the modes apart), saturating.
  out[k++] = float(__float2int_rn(2.5f) * 1000 + __float2int_rz(-2.5f) * 100 +
                   __float2int_ru(2.5f) * 10 + __float2int_rd(-2.5f));
  out[k++] = float(__float2uint_rn(3.5f) + __float2uint_rz(3.7f) + __float2uint_ru(3.2f) +
                   __float2uint_rd(3.9f) + __float2uint_rn(-5.0f));
  out[k++] = float(__float2int_rz(1e20f) == 2147483647) + float(__float2int_rn(NAN) == 0);
  out[k++] = __int2float_rn(16777217) + __uint2float_rn(3u) + __ll2float_rn(-5ll);
  out[k++] = __int_as_float(0x3f800000) + float(__float_as_int(2.0f) == 0x40000000) +
             float(__float_as_uint(-0.0f) == 0x80000000u);
  // Integer intrinsics.
  out[k++] = float(__brev(1u) == 0x80000000u) + float(__brevll(1ull) == 0x8000000000000000ull);
  out[k++] = float(__popc(0xF0F0u) + __popcll(0xFFFFFFFFFull));
  out[k++] = float(__clz(1) + __clz(0) + __clzll(1ll) + __clzll(0ll));
  out[k++] = float(__ffs(0) + __ffs(0x100) + __ffsll(0) + __ffsll(1ll << 40));
  out[k++] = float(__mul24(0x1000001, 3) + __umul24(0x1000002u, 5u));
  out[k++] = float(__mulhi(0x40000000, 16) + static_cast<int>(__umulhi(0x80000000u, 6u)));
  out[k++] = float(min(3, -4) + max(3u, 4u) + min(2.5f, 1.5f) + max(7ll, 8ll));
  // Vector math: float, int, unsigned and 64-bit families.
  const float3 a = make_float3(1.0f, -2.0f, 0.5f), b = make_float3(0.25f, 4.0f, -1.0f);
  const float3 n = normalize(make_float3(0.0f, 1.0f, 1.0f));
  out[k++] = dot(cross(a, b), make_float3(1.0f, 2.0f, 3.0f));
  out[k++] = length(reflect(a, n)) + getByIndex(faceforward(n, a, b), 2);
  float3 r = make_float3(0.0f);
  out[k++] = float(refract(r, normalize(a), n, 1.5f)) + r.x + r.y * 2.0f + r.z * 3.0f;
  out[k++] = luminance(a) + luminanceCIE(b) + fresnel_schlick(0.3f) +
             fresnel_schlick(0.2f, 4.0f, make_float3(0.1f), make_float3(0.9f)).y;
  out[k++] = dot(temperature(0.3f), make_float3(1.0f, 10.0f, 100.0f)) + temperature(0.9f).x;
  out[k++] = dot(cart_to_pol(make_float3(-1.0f, -1.0f, 0.5f)), make_float3(1.0f, 2.0f, 3.0f));
  out[k++] = smoothstep(0.0f, 2.0f, 0.5f) + lerp(1.0f, 3.0f, 0.25f) +
             bilerp(0.0f, 1.0f, 2.0f, 3.0f, 0.5f, 0.25f);
  out[k++] = dot(lerp(a, b, 0.3f), make_float3(1.0f)) +
             dot(bilerp(make_float4(a, 1.0f), make_float4(b, 2.0f), make_float4(0.5f),
                        make_float4(1.5f), 0.2f, 0.7f),
                 make_float4(1.0f));
  out[k++] =
      dot(clamp(a, -1.0f, 0.75f), b) + dot(clamp(a, b, make_float3(2.0f)), make_float3(1.0f));
  out[k++] = fminf(a) + fmaxf(b) + dot(fminf(a, b), fmaxf(a, b));
  out[k++] = dot(expf(make_float2(0.5f, -0.5f)), make_float2(1.0f)) + dot(floor(a), b) +
             dot(frac(b), make_float3(1.0f));
  out[k++] = dot(copysignf(a, b), make_float3(1.0f)) + dot(fabs(b), make_float3(1.0f)) +
             dot(fmodf(b, make_float3(0.3f)), make_float3(1.0f));
  float3 p;
  cosine_sample_hemisphere(0.3f, 0.6f, p);
  const float2 disk = square_to_disk(make_float2(0.8f, 0.1f));
  out[k++] = p.x + 2.0f * p.y + 3.0f * p.z + disk.x - disk.y;
  Onb onb(n);
  float3 q = make_float3(0.2f, 0.3f, 0.9f);
  onb.inverse_transform(q);
  out[k++] = q.x + 2.0f * q.y + 3.0f * q.z;
  const int3 i3 = make_int3(make_float3(2.7f, -3.2f, 1e10f));  // truncates, saturates
  const uint4 u4 = make_uint4(make_uint2(1u, 2u), make_uint2(3u)) * 2u;
  out[k++] = float(i3.x + i3.y) + float(i3.z == 2147483647) + float(u4.x + u4.y + u4.z + u4.w) +
             float(max(make_int2(1, 5), make_int2(3, 2)).x);
  const longlong3 l3 = clamp(make_longlong3(-5ll, 10ll, 3ll), -2ll, 4ll) * 3ll;
  const ulonglong2 u2 = min(make_ulonglong2(7ull, 9ull), make_ulonglong2(8ull));
  out[k++] =
      float(l3.x + l3.y + l3.z + getByIndex(u2, 1)) + float(-l3 == make_longlong3(6, -12, -9));
  out[k++] =
      dot(make_float4(make_float2(1.0f, 2.0f), 3.0f, 4.0f), make_float4(1.0f)) +
      dot(make_float4(make_float3(1.0f), 2.0f), make_float4(make_float2(1.0f), make_float2(2.0f))) +
      dot(make_float3(1.0f, make_float2(2.0f, 3.0f)),
          make_float3(make_float4(1.0f, 1.0f, 1.0f, 9.0f)));
  // Matrices and boxes.
  const Matrix4x4 m = Matrix4x4::translate(make_float3(1.0f, 2.0f, 3.0f)) *
                      Matrix4x4::rotate(0.5f, make_float3(0.0f, 0.0f, 1.0f)) *
                      Matrix4x4::scale(make_float3(2.0f));
  const float4 mv = m * make_float4(1.0f, 1.0f, 1.0f, 1.0f);
  out[k++] = mv.x + 2.0f * mv.y + 3.0f * mv.z + 4.0f * mv.w;
  out[k++] = m.det() + m.inverse()[5] + m.transpose()[3] + make_matrix3x3(m).det();
  const Matrix3x3 m3 = make_matrix3x3(m) * Matrix3x3::identity() * 2.0f;
  const float3 row = m3.getRow(1), col = m3.getCol(2);
  out[k++] = dot(row, col) + (make_float3(1.0f) * m3).z;
  Aabb box(make_float3(0.0f), make_float3(1.0f, 2.0f, 3.0f));
  box.include(make_float3(-1.0f, 0.5f, 4.0f));
  out[k++] = box.area() + box.volume() + float(box.longestAxis()) + box.maxExtent() +
             box.distance(make_float3(5.0f, 0.0f, 0.0f)) + box.signedDistance(make_float3(0.0f)) +
             float(box.contains(make_float3(0.5f))) + box.center(1) + box.extent(2);
  Aabb other(make_float3(0.5f), make_float3(9.0f), make_float3(2.0f, -3.0f, 1.0f));
  other.intersection(box);
  out[k++] = float(other.valid()) + other.halfArea() + float(other.intersects(box)) +
             float(other.isFlat());
  while (k < kIntrinsicCases) out[k++] = 0.0f;
}
