// Launch parameters of the accuracy test (accuracy.cu, main.cc).
#ifndef TESSERA_TESTS_OPTIX7_ACCURACY_PARAMS_H_
#define TESSERA_TESTS_OPTIX7_ACCURACY_PARAMS_H_

#include <optix_types.h>
#include <vector_types.h>

// One primary ray per launch index. `report`: the distance the intersection program reports on
// custom primitives.
struct TestRay {
  float3 origin;
  float3 direction;
  float tmin, tmax;
  float report;
};

struct TestResult {
  unsigned hit;     // 1: the closest-hit program ran
  float t;          // optixGetRayTmax there
  unsigned prim;    // optixGetPrimitiveIndex
  unsigned shadow;  // 1: the shadow ray (shadow_mode) hit something
};

// How the closest-hit program traces its shadow ray, along the primary ray's direction (out of
// the closed mesh: anything it hits is the surface it left).
enum ShadowMode : unsigned {
  kNoShadow = 0,
  kSpawnPoint = 1,  // from tesseraOptixGetSpawnPoint, tmin 0
  kHitPoint = 2,    // from origin + t * direction, tmin scene_epsilon (OFFSET_RAYS may move it)
};

struct Params {
  OptixTraversableHandle handle;
  const TestRay* rays;
  TestResult* results;
  unsigned count;
  unsigned shadow_mode;
  float scene_epsilon;
};

#endif  // TESSERA_TESTS_OPTIX7_ACCURACY_PARAMS_H_
