// The closest-hit program of a bindless-callable renderer (OptiX Advanced Samples style): one
// program for every instance; the instance's parMaterialIndex picks a MaterialParameter, whose
// indexBSDF picks a callable program id from sysEvalBSDF, a buffer of RT_FORMAT_PROGRAM_ID.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "material_parameter.h"
#include "sample_common.h"

using namespace optix;

rtDeclareVariable(optix::Ray, theRay, rtCurrentRay, );
rtDeclareVariable(float, theIntersectionDistance, rtIntersectionDistance, );
rtDeclareVariable(PerRayData_radiance, thePrd, rtPayload, );

rtDeclareVariable(float3, geometric_normal, attribute geometric_normal, );
rtDeclareVariable(float3, shading_normal, attribute shading_normal, );
rtDeclareVariable(float3, texcoord, attribute texcoord, );

rtBuffer<MaterialParameter> sysMaterialParameters;
rtDeclareVariable(int, parMaterialIndex, , );
rtDeclareVariable(float3, sysLightDirection, , );  // towards the light
rtDeclareVariable(float3, sysLightColor, , );

typedef rtCallableProgramId<float3(MaterialParameter const&, State const&, float3 const&,
                                   float3 const&)>
    EvalBSDF;
rtBuffer<EvalBSDF> sysEvalBSDF;

RT_PROGRAM void closesthit() {
  State state;
  state.geoNormal = optix::normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, geometric_normal));
  state.normal = optix::normalize(rtTransformNormal(RT_OBJECT_TO_WORLD, shading_normal));
  state.texcoord = texcoord;

  const float3 wo = -theRay.direction;
  if (0.0f > optix::dot(wo, state.geoNormal)) {  // the back of a surface: flip to the viewer
    state.geoNormal = -state.geoNormal;
    state.normal = -state.normal;
  }

  MaterialParameter parameters = sysMaterialParameters[parMaterialIndex];
  const float3 wi = optix::normalize(sysLightDirection);
  thePrd.result = sysEvalBSDF[parameters.indexBSDF](parameters, state, wo, wi) * sysLightColor;
}
