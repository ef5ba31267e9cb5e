// A row of geometry instances, one per launch index x: each ray hits its own instance, whose
// closest-hit program writes tint * scale + offset, and the ray generation program adds `frame`.
// tint may be set on the geometry instance or its material; scale on the closest-hit program;
// offset and frame on the context; half_width, which the intersection program reads, on the
// geometry. The INPUT buffer `bias` adds its element x.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float value;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(float, frame, , );
rtDeclareVariable(float, offset, , );
// 1 where no scope sets it (ray generation, miss): instances' tints of 1 then equal it in every
// binding of the module, which share it until one changes.
rtDeclareVariable(float, tint, , ) = 1.f;
rtDeclareVariable(float, scale, , ) = 1.f;
rtDeclareVariable(float, center, , );
rtDeclareVariable(float, half_width, , ) = 0.5f;
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtBuffer<float, 2> result;
rtBuffer<float> bias;  // INPUT, one per launch index x

RT_PROGRAM void row_raygen() {
  Payload p;
  p.value = -100.f;
  Ray r = make_Ray(make_float3(launch_index.x * 2.f, 0.f, -5.f), make_float3(0.f, 0.f, 1.f), 0, 0.f,
                   RT_DEFAULT_MAX);
  rtTrace(top_object, r, p);
  result[launch_index] = p.value + frame + bias[launch_index.x];
}

RT_PROGRAM void row_miss() { payload.value = -1000.f; }

RT_PROGRAM void row_closest_hit() { payload.value = tint * scale + offset; }

// A square at x = center in the plane z = 0, half_width wide each way (at most 0.5, the bounds).
RT_PROGRAM void square_intersect(int) {
  const float t = -ray.origin.z / ray.direction.z;
  const float x = ray.origin.x + t * ray.direction.x;
  if (fabsf(x - center) < half_width && rtPotentialIntersection(t)) rtReportIntersection(0);
}

RT_PROGRAM void square_bounds(int, float box[6]) {
  box[0] = center - 0.5f;
  box[1] = -0.5f;
  box[2] = -0.1f;
  box[3] = center + 0.5f;
  box[4] = 0.5f;
  box[5] = 0.1f;
}
