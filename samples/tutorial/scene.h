// The tutorial scene: a box, a floor parallelogram and, from step 9, a convex hull, each in its
// own GeometryGroup with its own acceleration, under one top Group.
#ifndef TESSERA_SAMPLES_TUTORIAL_SCENE_H_
#define TESSERA_SAMPLES_TUTORIAL_SCENE_H_

#include <optixu/optixu_vector_types.h>

#include "tessera/rt.h"
#include "tutorial/programs.h"
#include "tutorial/steps.h"

namespace tessera::tutorial {

// Scene dimensions, shared with tests that look for the objects in the image.
inline constexpr float3 kBoxMin = {-2.0f, 0.0f, -2.0f};
inline constexpr float3 kBoxMax = {2.0f, 7.0f, 2.0f};
inline constexpr float kFloorHeight = 0.01f;
inline constexpr float3 kChullCenter = {-1.4f, 0.0f, -3.7f};  // of its base
inline constexpr float kChullRadius = 1.0f;
inline constexpr float kChullMinY = 0.02f;
inline constexpr float kChullMaxY = 3.5f;
inline constexpr float3 kTileV0 = {0.25f, 0.0f, 0.15f};
inline constexpr float3 kTileV1 = {-0.15f, 0.0f, 0.25f};
inline constexpr float3 kLightPos = {-5.0f, 60.0f, -16.0f};

// Creates the objects of `step`, binds top_object and top_shadower on the context.
// Throws TutorialError.
void BuildScene(RTcontext context, const StepConfig& step, ProgramLoader& programs);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_SCENE_H_
