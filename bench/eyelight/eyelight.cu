// Programs of the eyelight benchmark: a pinhole camera, a triangle mesh (vertex_buffer /
// index_buffer, as OptiX SDK meshes) with an intersection program (OptiX 3) or an attribute
// program (OptiX 6 built-in triangles), and the eyelight shader of Embree's viewer:
// color = |dot(normalize(Ng), ray.direction)|, the direction normalized by the camera, as the
// viewer's camera normalizes it and its shader uses it as it is.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct PerRayData {
  float result;
  unsigned hit;
};

rtDeclareVariable(float3, eye, , );
rtDeclareVariable(float3, U, , );
rtDeclareVariable(float3, V, , );
rtDeclareVariable(float3, W, , );
rtDeclareVariable(float, scene_epsilon, , ) = 0.f;
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtDeclareVariable(PerRayData, prd, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );

// Row 0 is the bottom of the image, as in OptiX; the host flips rows when it writes a file.
rtBuffer<uchar4, 2> output_buffer;
rtBuffer<float3> vertex_buffer;
rtBuffer<int3> index_buffer;

RT_PROGRAM void pinhole_camera() {
  float2 d = (make_float2(launch_index) + 0.5f) / make_float2(launch_dim) * 2.f - 1.f;
  Ray r = make_Ray(eye, normalize(d.x * U + d.y * V + W), 0, scene_epsilon, RT_DEFAULT_MAX);
  PerRayData p;
  p.result = 0.f;
  p.hit = 0;
  rtTrace(top_object, r, p);
  // Embree's viewer converts with 255.01 * clamp(c, 0, 1); do the same so images compare.
  // Alpha tells hits (255) from misses (0), for --check.
  unsigned char c = static_cast<unsigned char>(255.01f * clamp(p.result, 0.f, 1.f));
  output_buffer[launch_index] = make_uchar4(c, c, c, p.hit ? 255 : 0);
}

RT_PROGRAM void miss() {
  prd.result = 0.f;
  prd.hit = 0;
}

RT_PROGRAM void eyelight() {
  prd.result = fabsf(dot(normalize(geometric_normal), ray.direction));
  prd.hit = 1;
}

// The OptiX SDK's intersect_triangle: edges from p0, t and barycentrics by Cramer's rule.
RT_PROGRAM void mesh_intersect(int primitive) {
  int3 v = index_buffer[primitive];
  float3 p0 = vertex_buffer[v.x];
  float3 p1 = vertex_buffer[v.y];
  float3 p2 = vertex_buffer[v.z];
  float3 e0 = p1 - p0;
  float3 e1 = p0 - p2;
  float3 n = cross(e1, e0);
  float denom = dot(n, ray.direction);
  if (denom == 0.f) return;  // the ray is parallel to the triangle
  float3 e2 = (1.0f / denom) * (p0 - ray.origin);
  float3 i = cross(ray.direction, e2);
  float beta = dot(i, e1);
  float gamma = dot(i, e0);
  float t = dot(n, e2);
  if (t < ray.tmax && t > ray.tmin && beta >= 0.f && gamma >= 0.f && beta + gamma <= 1.f) {
    if (rtPotentialIntersection(t)) {
      geometric_normal = n;
      rtReportIntersection(0);
    }
  }
}

// With built-in triangles (OptiX 6 GeometryTriangles) Embree finds the hit itself; the attribute
// program computes the same normal for the closest hit.
RT_PROGRAM void mesh_attributes() {
  int3 v = index_buffer[rtGetPrimitiveIndex()];
  float3 p0 = vertex_buffer[v.x];
  float3 p1 = vertex_buffer[v.y];
  float3 p2 = vertex_buffer[v.z];
  geometric_normal = cross(p0 - p2, p1 - p0);
}

RT_PROGRAM void mesh_bounds(int primitive, float result[6]) {
  int3 v = index_buffer[primitive];
  float3 p0 = vertex_buffer[v.x];
  float3 p1 = vertex_buffer[v.y];
  float3 p2 = vertex_buffer[v.z];
  float3 lo = fminf(fminf(p0, p1), p2);
  float3 hi = fmaxf(fmaxf(p0, p1), p2);
  result[0] = lo.x;
  result[1] = lo.y;
  result[2] = lo.z;
  result[3] = hi.x;
  result[4] = hi.y;
  result[5] = hi.z;
}
