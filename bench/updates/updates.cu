// Programs of tessera-bench-updates: a row of unit squares, one geometry instance each (its
// `center`), traced one ray per launch index; the closest hit writes the instance's `tint`, the
// ray generation program adds the context's `frame`.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float value;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, frame, , );
rtDeclareVariable(float, tint, , );
rtDeclareVariable(float, center, , );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtBuffer<float, 2> result;

RT_PROGRAM void row_raygen() {
  Payload p;
  p.value = -1000.f;
  Ray r = make_Ray(make_float3(launch_index.x * 2.f, 0.f, -5.f), make_float3(0.f, 0.f, 1.f), 0, 0.f,
                   RT_DEFAULT_MAX);
  rtTrace(top_object, r, p);
  result[launch_index] = p.value + frame;
}

RT_PROGRAM void row_miss() {}

RT_PROGRAM void row_closest_hit() { payload.value = tint; }

RT_PROGRAM void square_intersect(int) {
  const float t = -ray.origin.z / ray.direction.z;
  const float x = ray.origin.x + t * ray.direction.x;
  if (fabsf(x - center) < 0.5f && rtPotentialIntersection(t)) rtReportIntersection(0);
}

RT_PROGRAM void square_bounds(int, float box[6]) {
  box[0] = center - 0.5f;
  box[1] = -0.5f;
  box[2] = -0.1f;
  box[3] = center + 0.5f;
  box[4] = 0.5f;
  box[5] = 0.1f;
}
