// Types shared by the tutorial's host code and its programs (the SDK's commonStructs.h).
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_COMMON_STRUCTS_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_COMMON_STRUCTS_H_

#include <optixu/optixu_vector_types.h>

// One point light of the `lights` buffer (RT_FORMAT_USER, element size sizeof(BasicLight)).
struct BasicLight {
  float3 pos;
  float3 color;
  int casts_shadow;
  int padding;  // 32 bytes, as in the SDK
};

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_COMMON_STRUCTS_H_
