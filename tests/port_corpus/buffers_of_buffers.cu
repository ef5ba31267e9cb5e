// Buffers of buffer ids, as the OptiX SDK's bindless samples (optixBuffersOfBuffers) use them: one
// buffer of RT_FORMAT_BUFFER_ID holds, per mesh, the id of that mesh's own buffer of per-face
// colours; the closest-hit program picks the mesh's with the instance's mesh_id and the face
// with rtGetPrimitiveIndex.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "sample_common.h"

using namespace optix;

rtBuffer<rtBufferId<float3, 1>, 1> face_colors;
rtDeclareVariable(int, mesh_id, , );
rtDeclareVariable(PerRayData_radiance, prd_radiance, rtPayload, );

RT_PROGRAM void closest_hit_face_color() {
  const rtBufferId<float3, 1> colors = face_colors[mesh_id];
  prd_radiance.result = colors[rtGetPrimitiveIndex() % colors.size()];
}

RT_PROGRAM void miss_black() { prd_radiance.result = make_float3(0.0f); }
