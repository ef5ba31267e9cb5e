// A parallelogram as the OptiX SDK's parallelogram.cu intersects it: a plane (normal, offset), an
// anchor and two edge vectors the host scales by 1 / |v|^2, so that the dot products with them
// are the texture coordinates.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(float4, plane, , );
rtDeclareVariable(float3, v1, , );
rtDeclareVariable(float3, v2, , );
rtDeclareVariable(float3, anchor, , );
rtDeclareVariable(int, lgt_instance, , ) = {0};

rtDeclareVariable(float3, texcoord, attribute texcoord, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(int, lgt_idx, attribute lgt_idx, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

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
          lgt_idx = lgt_instance;
          rtReportIntersection(0);
        }
      }
    }
  }
}

RT_PROGRAM void bounds(int, float result[6]) {
  // v1 and v2 are scaled by 1 / |v|^2: scale them back for the box.
  const float3 tv1 = v1 / dot(v1, v1);
  const float3 tv2 = v2 / dot(v2, v2);
  const float3 p00 = anchor;
  const float3 p01 = anchor + tv1;
  const float3 p10 = anchor + tv2;
  const float3 p11 = anchor + tv1 + tv2;
  const float area = length(cross(tv1, tv2));

  optix::Aabb* aabb = (optix::Aabb*)result;
  if (area > 0.0f && !isinf(area)) {
    aabb->m_min = fminf(fminf(p00, p01), fminf(p10, p11));
    aabb->m_max = fmaxf(fmaxf(p00, p01), fmaxf(p10, p11));
  } else {
    aabb->invalidate();
  }
}
