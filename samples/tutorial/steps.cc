#include "tutorial/steps.h"

#include <string>

#include "tutorial/rt_check.h"

namespace tessera::tutorial {
namespace {

constexpr ProgramRef kNone{nullptr, nullptr};
constexpr ProgramRef kMiss{"tutorial_miss", "miss"};
constexpr ProgramRef kEnvmapMiss{"tutorial_miss", "envmap_miss"};
constexpr ProgramRef kEnvCamera{"tutorial_camera", "env_camera"};
constexpr ProgramRef kNormal{"tutorial_normal", "closest_hit_radiance0"};
constexpr ProgramRef kLambert{"tutorial_phong", "closest_hit_radiance1"};
constexpr ProgramRef kPhong{"tutorial_phong", "closest_hit_radiance2"};
constexpr ProgramRef kShadowed{"tutorial_phong", "closest_hit_radiance3"};
constexpr ProgramRef kFloorReflect{"tutorial_floor", "floor_closest_hit_radiance4"};
constexpr ProgramRef kFloorSchlick{"tutorial_floor", "floor_closest_hit_radiance5"};
constexpr ProgramRef kFloorTiles{"tutorial_floor", "floor_closest_hit_radiance"};
constexpr ProgramRef kRust{"tutorial_rust", "box_closest_hit_radiance"};
constexpr ProgramRef kGlass{"tutorial_glass", "glass_closest_hit_radiance"};
constexpr ProgramRef kOpaqueShadow{"tutorial_shadow", "any_hit_shadow"};
constexpr ProgramRef kGlassShadow{"tutorial_shadow", "glass_any_hit_shadow"};

// From step 5 on, rays that miss read an environment map (an HDR image through a texture
// sampler); step 8's rust reads a 3D noise texture. Step 9 shows the convex hull with an opaque,
// Schlick-reflective metal; step 10 turns it into glass with glass shadows.
constexpr StepConfig kSteps[] = {
    {0, "normal shader", kMiss, kNormal, kNormal, kNone, kNone, kNone},
    {1, "Lambertian diffuse", kMiss, kLambert, kLambert, kNone, kNone, kNone},
    {2, "Phong highlights", kMiss, kPhong, kPhong, kNone, kNone, kNone},
    {3, "shadows", kMiss, kShadowed, kShadowed, kOpaqueShadow, kNone, kNone},
    {4, "reflections", kMiss, kShadowed, kFloorReflect, kOpaqueShadow, kNone, kNone},
    {5, "environment map", kEnvmapMiss, kShadowed, kFloorReflect, kOpaqueShadow, kNone, kNone},
    {6, "Schlick Fresnel reflection", kEnvmapMiss, kShadowed, kFloorSchlick, kOpaqueShadow, kNone,
     kNone},
    {7, "procedurally tiled floor", kEnvmapMiss, kShadowed, kFloorTiles, kOpaqueShadow, kNone,
     kNone},
    {8, "rusty metal", kEnvmapMiss, kRust, kFloorTiles, kOpaqueShadow, kNone, kNone},
    {9, "convex hull primitive", kEnvmapMiss, kRust, kFloorTiles, kOpaqueShadow, kFloorSchlick,
     kOpaqueShadow},
    {10, "glass", kEnvmapMiss, kRust, kFloorTiles, kOpaqueShadow, kGlass, kGlassShadow},
    {11, "environment camera", kEnvmapMiss, kRust, kFloorTiles, kOpaqueShadow, kGlass, kGlassShadow,
     kEnvCamera},
};
static_assert(sizeof(kSteps) / sizeof(kSteps[0]) == kEnvironmentCameraStep - kFirstStep + 1);

}  // namespace

const StepConfig& GetStep(int step) {
  if (step < kFirstStep || step > kEnvironmentCameraStep) {
    throw TutorialError("unknown step " + std::to_string(step) + " (steps " +
                        std::to_string(kFirstStep) + " to " +
                        std::to_string(kEnvironmentCameraStep) + " are available)");
  }
  return kSteps[step - kFirstStep];
}

}  // namespace tessera::tutorial
