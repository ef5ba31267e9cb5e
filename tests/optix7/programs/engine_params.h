// The launch parameters of the engine tests' programs (engine_trace.cu, engine_calls.cu), shared
// with the test that fills them (engine_test.cc). Needs optix_types.h and vector_types.h.
#ifndef TESSERA_TESTS_OPTIX7_PROGRAMS_ENGINE_PARAMS_H_
#define TESSERA_TESTS_OPTIX7_PROGRAMS_ENGINE_PARAMS_H_

// Words each launch index writes to EngineParams::out.
#define ENGINE_WORDS 16u

struct EngineParams {
  OptixTraversableHandle handle;
  unsigned int* out;      // ENGINE_WORDS per launch index, x fastest
  const float4* spheres;  // custom primitives: centre and radius, by primitive index
  float3 origin;          // of launch index (0, 0)
  float3 step;            // origin offset per launch index x
  float3 direction;
  float tmin, tmax;
  unsigned int ray_flags;
  unsigned int visibility_mask;
  unsigned int sbt_offset, sbt_stride, miss_index;
  unsigned int recursion;  // __closesthit__recurse traces until this depth
  float time;              // the ray time of __raygen__trace
};

// The data block of every SBT record of the tests: a value programs report.
struct RecordData {
  unsigned int value;
};

#endif  // TESSERA_TESTS_OPTIX7_PROGRAMS_ENGINE_PARAMS_H_
