// Programs of tessera-bench-specialize: an orthographic camera over a heightfield mesh, an OptiX 3
// mesh intersection program, and any-hit programs that ignore nothing.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float3 color;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(unsigned int, traced_ray_type, , );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtBuffer<float4, 2> output;
rtBuffer<float3> vertex_buffer;
rtBuffer<int3> index_buffer;

// Rays along +z from z = -4 through [-1, 1]^2.
RT_PROGRAM void camera() {
  const float x = (launch_index.x + 0.5f) / launch_dim.x * 2.f - 1.f;
  const float y = (launch_index.y + 0.5f) / launch_dim.y * 2.f - 1.f;
  const Ray r = make_Ray(make_float3(x, y, -4.f), make_float3(0.f, 0.f, 1.f), traced_ray_type, 0.f,
                         RT_DEFAULT_MAX);
  Payload p;
  p.color = make_float3(0.f);
  rtTrace(top_object, r, p);
  output[launch_index] = make_float4(p.color, 1.f);
}

RT_PROGRAM void miss() { payload.color = make_float3(0.f); }

// The world-space normal, as a color: it goes through the hit's transforms.
RT_PROGRAM void shade() {
  const float3 n = normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, geometric_normal));
  payload.color = n * 0.5f + make_float3(0.5f);
}

RT_PROGRAM void any_hit_empty() {}

// Ignores nothing, though it reads the hit's distance: it cannot be told from an empty one.
RT_PROGRAM void any_hit_accepting() {
  if (t_hit < 0.f) rtIgnoreIntersection();
}

RT_PROGRAM void mesh_intersect(int prim) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  float3 n;
  float t, beta, gamma;
  if (intersect_triangle(ray, p0, p1, p2, n, t, beta, gamma) && rtPotentialIntersection(t)) {
    geometric_normal = n;
    rtReportIntersection(0);
  }
}

RT_PROGRAM void mesh_bounds(int prim, float result[6]) {
  const int3 v = index_buffer[prim];
  const float3 p0 = vertex_buffer[v.x], p1 = vertex_buffer[v.y], p2 = vertex_buffer[v.z];
  const float3 lo = fminf(fminf(p0, p1), p2), hi = fmaxf(fmaxf(p0, p1), p2);
  result[0] = lo.x;
  result[1] = lo.y;
  result[2] = lo.z;
  result[3] = hi.x;
  result[4] = hi.y;
  result[5] = hi.z;
}
