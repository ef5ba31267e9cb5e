// Renders one step of the tutorial in-process: the logic behind tessera-tutorial, also used by
// the tests.
#ifndef TESSERA_SAMPLES_TUTORIAL_RENDER_H_
#define TESSERA_SAMPLES_TUTORIAL_RENDER_H_

#include <string>

#include "tutorial/image.h"

namespace tessera::tutorial {

struct RenderOptions {
  int step = 0;
  int width = 512;
  int height = 384;
  std::string module_dir;  // holds tutorial_*.so
};

// Colors the context sets, for tests that recognize them in the image.
inline constexpr float kBackgroundColor[3] = {0.34f, 0.55f, 0.85f};  // bg_color
inline constexpr float kBadColor[3] = {1.0f, 0.0f, 1.0f};            // exception pixels

// The module directory: `flag` if not empty, else $TESSERA_MODULE_DIR, else the build's.
std::string ResolveModuleDir(const std::string& flag);

// Renders `options.step`. Throws TutorialError (with the rt* error message) on failure.
Image RenderStep(const RenderOptions& options);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_RENDER_H_
