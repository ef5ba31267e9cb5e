// A sphere with texture coordinates, as the OptiX SDK's sphere_texcoord.cu reports them: u around
// the y axis from atan2, v from the pole, in an attribute the material reads; the sphere is one
// float4 variable (centre, radius) of the geometry.
#include <optix.h>
#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

rtDeclareVariable(float4, sphere, , );

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(float3, texcoord, attribute texcoord, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

static __device__ float3 sphere_uv(const float3& n) {
  const float phi = atan2f(n.x, n.z);
  const float theta = acosf(fminf(fmaxf(n.y, -1.0f), 1.0f));
  return make_float3((phi + M_PIf) * (0.5f * M_1_PIf), theta * M_1_PIf, 0.0f);
}

RT_PROGRAM void intersect(int primIdx) {
  float3 center = make_float3(sphere);
  float3 O = ray.origin - center;
  float3 D = ray.direction;
  float radius = sphere.w;

  float b = dot(O, D);
  float c = dot(O, O) - radius * radius;
  float disc = b * b - c;
  if (disc > 0.0f) {
    float sdisc = sqrtf(disc);
    float root1 = (-b - sdisc);
    bool check_second = true;
    if (rtPotentialIntersection(root1)) {
      shading_normal = geometric_normal = (O + root1 * D) / radius;
      texcoord = sphere_uv(geometric_normal);
      if (rtReportIntersection(0)) check_second = false;
    }
    if (check_second) {
      float root2 = (-b + sdisc);
      if (rtPotentialIntersection(root2)) {
        shading_normal = geometric_normal = (O + root2 * D) / radius;
        texcoord = sphere_uv(geometric_normal);
        rtReportIntersection(0);
      }
    }
  }
}

RT_PROGRAM void bounds(int, float result[6]) {
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
