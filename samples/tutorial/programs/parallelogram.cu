// A parallelogram (the floor): bounding box and intersection programs (the SDK's
// parallelogram.cu). The host passes v1 and v2 scaled by 1/|v|^2 so that dot(v, p - anchor)
// is the parametric coordinate directly.
#include <optix.h>
#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>

#include <cmath>

using namespace optix;

rtDeclareVariable(float4, plane, , );
rtDeclareVariable(float3, v1, , );
rtDeclareVariable(float3, v2, , );
rtDeclareVariable(float3, anchor, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

rtDeclareVariable(float3, texcoord, attribute texcoord, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );

RT_PROGRAM void intersect(int primIdx) {
  float3 n = make_float3(plane);
  float dt = dot(ray.direction, n);
  float t = (plane.w - dot(n, ray.origin)) / dt;
  if (t > ray.tmin && t < ray.tmax) {
    float3 p = ray.origin + ray.direction * t;
    float3 vi = p - anchor;
    float a1 = dot(v1, vi);
    if (a1 >= 0 && a1 <= 1) {
      float a2 = dot(v2, vi);
      if (a2 >= 0 && a2 <= 1) {
        if (rtPotentialIntersection(t)) {
          shading_normal = geometric_normal = n;
          texcoord = make_float3(a1, a2, 0);
          rtReportIntersection(0);
        }
      }
    }
  }
}

RT_PROGRAM void bounds(int, float result[6]) {
  // v1 and v2 are scaled by 1/length^2: scale them back for the bounds.
  const float3 tv1 = v1 / dot(v1, v1);
  const float3 tv2 = v2 / dot(v2, v2);
  const float3 p00 = anchor;
  const float3 p01 = anchor + tv1;
  const float3 p10 = anchor + tv2;
  const float3 p11 = anchor + tv1 + tv2;
  const float area = length(cross(tv1, tv2));

  optix::Aabb* aabb = (optix::Aabb*)result;
  if (area > 0.0f && !std::isinf(area)) {
    aabb->m_min = fminf(fminf(p00, p01), fminf(p10, p11));
    aabb->m_max = fmaxf(fmaxf(p00, p01), fmaxf(p10, p11));
  } else {
    aabb->invalidate();
  }
}
