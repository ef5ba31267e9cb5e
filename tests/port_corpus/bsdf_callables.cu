// BSDF evaluation as bindless callable programs (RT_CALLABLE_PROGRAM in a module of their own),
// as community path tracers write them: the host puts their rtProgramGetId ids in a buffer of
// RT_FORMAT_PROGRAM_ID, and the closest-hit program calls the one a material's indexBSDF picks.
// Each returns the light reflected towards wo from a unit light along wi.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include "material_parameter.h"

using namespace optix;

// An emitter: its albedo whatever the directions (an area light seen directly, unlit).
RT_CALLABLE_PROGRAM float3 eval_bsdf_emissive(MaterialParameter const& parameters,
                                              State const& state, float3 const& wo,
                                              float3 const& wi) {
  return parameters.albedo;
}

// Lambert: albedo / pi times the cosine at the light.
RT_CALLABLE_PROGRAM float3 eval_bsdf_diffuse_reflection(MaterialParameter const& parameters,
                                                        State const& state, float3 const& wo,
                                                        float3 const& wi) {
  const float cosTheta = optix::dot(state.normal, wi);
  if (cosTheta <= 0.0f) return make_float3(0.0f);
  return parameters.albedo * (M_1_PIf * cosTheta);
}

// The normal as a colour, the debug view every renderer grows.
RT_CALLABLE_PROGRAM float3 eval_bsdf_normal_debug(MaterialParameter const& parameters,
                                                  State const& state, float3 const& wo,
                                                  float3 const& wi) {
  return state.normal * 0.5f + 0.5f;
}
