// The attribute program of the scene's triangle meshes (OptiX 6 built-in triangles): Embree finds
// the hit, and this program turns its primitive index and barycentrics into what the closest-hit
// program shades with, all in object space (material.cu moves them to world space).
#include "common.h"

// The mesh's vertex data, bound on its GeometryTriangles. The optional ones are empty (size 0)
// when the mesh has none.
rtBuffer<float3> vertex_buffer;
rtBuffer<uint3> index_buffer;
rtBuffer<float3> normal_buffer;
rtBuffer<float2> texcoord_buffer;
rtBuffer<float4> tangent_buffer;

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(float2, texcoord, attribute texcoord, );
rtDeclareVariable(float4, tangent, attribute tangent, );  // w: bitangent sign; 0 0 0 0 if none

template <typename T>
static __device__ __inline__ T Interpolate(const T& a, const T& b, const T& c, const float2& bary) {
  return (1.0f - bary.x - bary.y) * a + bary.x * b + bary.y * c;
}

RT_PROGRAM void mesh_attributes() {
  const uint3 tri = index_buffer[rtGetPrimitiveIndex()];
  const float2 bary = rtGetTriangleBarycentrics();  // weights of vertices 1 and 2
  const float3 p0 = vertex_buffer[tri.x], p1 = vertex_buffer[tri.y], p2 = vertex_buffer[tri.z];
  const float3 e1 = p1 - p0, e2 = p2 - p0;
  // The front face winds counter-clockwise, as glTF says.
  geometric_normal = cross(e1, e2);

  shading_normal = geometric_normal;
  if (normal_buffer.size() != 0) {
    const float3 n =
        Interpolate(normal_buffer[tri.x], normal_buffer[tri.y], normal_buffer[tri.z], bary);
    if (dot(n, n) > 0.0f) shading_normal = n;
  }

  texcoord = make_float2(0.0f);  // textures need texture coordinates: one texel then
  tangent = make_float4(0.0f);
  if (texcoord_buffer.size() != 0) {
    const float2 t0 = texcoord_buffer[tri.x], t1 = texcoord_buffer[tri.y],
                 t2 = texcoord_buffer[tri.z];
    texcoord = Interpolate(t0, t1, t2, bary);
    if (tangent_buffer.size() != 0) {
      tangent =
          Interpolate(tangent_buffer[tri.x], tangent_buffer[tri.y], tangent_buffer[tri.z], bary);
      tangent.w = tangent.w < 0.0f ? -1.0f : 1.0f;
    } else {
      // No tangents in the file: the direction in which u grows across the triangle, as glTF's
      // MikkTSpace tangents would give for a flat triangle.
      const float2 d1 = t1 - t0, d2 = t2 - t0;
      const float det = d1.x * d2.y - d2.x * d1.y;
      if (det != 0.0f) {
        const float3 t = (e1 * d2.y - e2 * d1.y) * (1.0f / det);
        const float3 b = (e2 * d1.x - e1 * d2.x) * (1.0f / det);
        const float handedness = dot(cross(geometric_normal, t), b) < 0.0f ? -1.0f : 1.0f;
        tangent = make_float4(t, handedness);
      }
    }
  }
}
