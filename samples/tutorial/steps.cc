#include "tutorial/steps.h"

#include <string>

#include "tutorial/rt_check.h"

namespace tessera::tutorial {
namespace {

constexpr ProgramRef kNone{nullptr, nullptr};
constexpr ProgramRef kMiss{"tutorial_miss", "miss"};
constexpr ProgramRef kGradientMiss{"tutorial_miss", "gradient_miss"};
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

// Step 5 would add an environment map; until textures exist it keeps step 4's shading and the
// miss program draws a sky gradient instead. Step 9 shows the convex hull with an opaque,
// Schlick-reflective metal; step 10 turns it into glass with glass shadows.
constexpr StepConfig kSteps[] = {
    {0, "normal shader", kMiss, kNormal, kNormal, kNone, kNone, kNone},
    {1, "Lambertian diffuse", kMiss, kLambert, kLambert, kNone, kNone, kNone},
    {2, "Phong highlights", kMiss, kPhong, kPhong, kNone, kNone, kNone},
    {3, "shadows", kMiss, kShadowed, kShadowed, kOpaqueShadow, kNone, kNone},
    {4, "reflections", kMiss, kShadowed, kFloorReflect, kOpaqueShadow, kNone, kNone},
    {5, "environment map (sky gradient stand-in)", kGradientMiss, kShadowed, kFloorReflect,
     kOpaqueShadow, kNone, kNone},
    {6, "Schlick Fresnel reflection", kGradientMiss, kShadowed, kFloorSchlick, kOpaqueShadow, kNone,
     kNone},
    {7, "procedurally tiled floor", kGradientMiss, kShadowed, kFloorTiles, kOpaqueShadow, kNone,
     kNone},
    {8, "rusty metal", kGradientMiss, kRust, kFloorTiles, kOpaqueShadow, kNone, kNone},
    {9, "convex hull primitive", kGradientMiss, kRust, kFloorTiles, kOpaqueShadow, kFloorSchlick,
     kOpaqueShadow},
    {10, "glass", kGradientMiss, kRust, kFloorTiles, kOpaqueShadow, kGlass, kGlassShadow},
};
static_assert(sizeof(kSteps) / sizeof(kSteps[0]) == kLastStep - kFirstStep + 1);

}  // namespace

const StepConfig& GetStep(int step) {
  if (step == 11) {
    throw TutorialError("step 11 (environment camera) needs textures (later issue)");
  }
  if (step < kFirstStep || step > kLastStep) {
    throw TutorialError("unknown step " + std::to_string(step) + " (steps " +
                        std::to_string(kFirstStep) + " to " + std::to_string(kLastStep) +
                        " are available)");
  }
  return kSteps[step - kFirstStep];
}

}  // namespace tessera::tutorial
