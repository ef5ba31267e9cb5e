// Convex hull given as a set of planes (the tutorial's step 9 procedural primitive). Each plane
// is float4(n, d) with dot(n, x) + d = 0 and n pointing out of the hull.
#include <optix.h>
#include <optixu/optixu_aabb_namespace.h>
#include <optixu/optixu_math_namespace.h>

#include <cfloat>

using namespace optix;

rtBuffer<float4> planes;
rtDeclareVariable(float3, chull_bbmin, , );
rtDeclareVariable(float3, chull_bbmax, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );

RT_PROGRAM void chull_intersect(int primIdx) {
  // The hull is the interval between the last plane entered and the first plane exited.
  const unsigned int nplanes = static_cast<unsigned int>(planes.size());
  float t0 = -FLT_MAX;
  float t1 = FLT_MAX;
  float3 t0_normal = make_float3(0);
  float3 t1_normal = make_float3(0);
  for (unsigned int i = 0; i < nplanes && t0 < t1; ++i) {
    float4 plane = planes[i];
    float3 n = make_float3(plane);
    float d = plane.w;

    float denom = dot(n, ray.direction);
    float t = -(d + dot(n, ray.origin)) / denom;
    if (denom < 0) {
      // enter
      if (t > t0) {
        t0 = t;
        t0_normal = n;
      }
    } else {
      // exit
      if (t < t1) {
        t1 = t;
        t1_normal = n;
      }
    }
  }

  if (t0 > t1) return;

  // Unlike the slide, the exit is also tried when an any-hit program ignored the entry, so a
  // glass shadow ray is attenuated by both surfaces (as box_intersect does).
  bool check_second = true;
  if (rtPotentialIntersection(t0)) {
    shading_normal = geometric_normal = t0_normal;
    if (rtReportIntersection(0)) check_second = false;
  }
  if (check_second && rtPotentialIntersection(t1)) {
    shading_normal = geometric_normal = t1_normal;
    rtReportIntersection(0);
  }
}

RT_PROGRAM void chull_bounds(int, float result[6]) {
  optix::Aabb* aabb = (optix::Aabb*)result;
  aabb->m_min = chull_bbmin;
  aabb->m_max = chull_bbmax;
}
