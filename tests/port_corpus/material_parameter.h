// Material parameters and the shading state of a bindless-callable renderer, in the style of the
// OptiX Advanced Samples' introduction path tracer (rtBuffer<MaterialParameter> indexed by a
// per-instance material index, BSDF callables chosen by an index in the parameters). Host code
// fills the parameter buffer, so both sides include it.
#pragma once

#include <optixu/optixu_vector_types.h>

// The BSDFs, in the order of the buffer of callable program ids (sysEvalBSDF).
enum FunctionIndex {
  INDEX_BSDF_EMISSIVE = 0,
  INDEX_BSDF_DIFFUSE_REFLECTION = 1,
  INDEX_BSDF_NORMAL_DEBUG = 2,
  NUMBER_OF_BSDF_INDICES = 3
};

struct MaterialParameter {
  optix::float3 albedo;
  int indexBSDF;
};

// What the closest-hit program hands each BSDF.
struct State {
  optix::float3 geoNormal;
  optix::float3 normal;
  optix::float3 texcoord;
};

static_assert(sizeof(MaterialParameter) == 16, "the layout host code fills");
