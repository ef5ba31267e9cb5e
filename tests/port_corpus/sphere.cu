// Spheres in the style of the SDK's sphere.cu, as an SDK project includes them: optixu/ is on the
// include path, so the helpers come without their prefix.
#include <optix.h>
#include <optixu_aabb_namespace.h>
#include <optixu_math_namespace.h>
#include <optixu_matrix_namespace.h>

using namespace optix;

rtBuffer<float4> spheres;  // center, radius

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

template <bool use_robust_method>
static __device__ void intersect_sphere(int primIdx) {
  const float4 sphere = spheres[primIdx];
  float3 center = make_float3(sphere);
  float3 O = ray.origin - center;
  float l = 1 / length(ray.direction);
  float3 D = ray.direction * l;
  float radius = sphere.w;

  float b = dot(O, D);
  float c = dot(O, O) - radius * radius;
  float disc = b * b - c;
  if (disc > 0.0f) {
    float sdisc = sqrtf(disc);
    float root1 = (-b - sdisc);
    bool do_refine = false;
    float root11 = 0.0f;
    if (use_robust_method && fabsf(root1) > 10.f * radius) {
      do_refine = true;
    }
    if (do_refine) {
      float3 O1 = O + root1 * D;
      b = dot(O1, D);
      c = dot(O1, O1) - radius * radius;
      disc = b * b - c;
      if (disc > 0.0f) {
        sdisc = sqrtf(disc);
        root11 = (-b - sdisc);
      }
    }
    bool check_second = true;
    if (rtPotentialIntersection((root1 + root11) * l)) {
      shading_normal = geometric_normal = (O + (root1 + root11) * D) / radius;
      if (rtReportIntersection(0)) check_second = false;
    }
    if (check_second) {
      float root2 = (-b + sdisc) + (do_refine ? root1 : 0);
      if (rtPotentialIntersection(root2 * l)) {
        shading_normal = geometric_normal = (O + root2 * D) / radius;
        rtReportIntersection(0);
      }
    }
  }
}

RT_PROGRAM void intersect(int primIdx) { intersect_sphere<false>(primIdx); }
RT_PROGRAM void robust_intersect(int primIdx) { intersect_sphere<true>(primIdx); }

RT_PROGRAM void bounds(int primIdx, float result[6]) {
  const float4 sphere = spheres[primIdx];
  const float3 cen = make_float3(sphere);
  const float3 rad = make_float3(sphere.w);
  optix::Aabb* aabb = (optix::Aabb*)result;
  if (rad.x > 0.0f && !isinf(rad.x)) {
    aabb->m_min = cen - rad;
    aabb->m_max = cen + rad;
  } else {
    aabb->invalidate();
  }
}
