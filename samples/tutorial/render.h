// Renders one step of the tutorial in-process: the logic behind tessera-tutorial, also used by
// the tests.
#ifndef TESSERA_SAMPLES_TUTORIAL_RENDER_H_
#define TESSERA_SAMPLES_TUTORIAL_RENDER_H_

#include <string>

#include "tessera/rt.h"
#include "tutorial/envmap.h"
#include "tutorial/image.h"

namespace tessera::tutorial {

struct RenderOptions {
  int step = 0;
  int width = 512;
  int height = 384;
  std::string module_dir;  // holds tutorial_*.so
  std::string envmap;      // the environment map of steps 5 on: an image file; empty: the build's
  EnvmapLoader load_envmap = &ComputedSky;  // what makes it (envmap.h)
};

// Colors the context sets, for tests that recognize them in the image.
inline constexpr float kBackgroundColor[3] = {0.34f, 0.55f, 0.85f};  // bg_color
inline constexpr float kBadColor[3] = {1.0f, 0.0f, 1.0f};            // exception pixels

// The module directory: `flag` if not empty, else $TESSERA_MODULE_DIR, else the build's.
std::string ResolveModuleDir(const std::string& flag);

// What SetUpStep made that a host may want to touch between launches.
struct StepBuffers {
  RTbuffer output = nullptr;  // float4, width x height, launch row 0 at the bottom
  RTbuffer lights = nullptr;  // INPUT, one BasicLight
};

// Sets `context` up for `options.step`: ray types, stack, variables, camera, programs from
// `options.module_dir`, the scene; validated and compiled, ready to launch at the options' size.
// Throws TutorialError (with the rt* error message) on failure.
StepBuffers SetUpStep(RTcontext context, const RenderOptions& options);

// Renders `options.step` in a context of its own. Throws TutorialError on failure.
Image RenderStep(const RenderOptions& options);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_RENDER_H_
