// The end-to-end scene, built through the public C API: spheres from an INPUT buffer, a camera
// writing an OUTPUT image and an INPUT_OUTPUT accumulator, and a 4.7 MiB INPUT noise buffer that
// travels in more than one chunk (outputs of 640×480 float4 exceed one 4 MiB message as well).
#ifndef TESSERA_TESTS_E2E_E2E_SCENE_H_
#define TESSERA_TESTS_E2E_E2E_SCENE_H_

#include <string>
#include <vector>

#include "tessera/rt.h"

namespace tessera::e2e {

struct Scene {
  RTcontext ctx = nullptr;
  RTbuffer image = nullptr;
  RTbuffer accum = nullptr;
  RTbuffer noise = nullptr;
  RTvariable iterations = nullptr;
  unsigned width = 0, height = 0;
};

// Builds the scene on `ctx` with entry point 0 = render, 1 = render_slow. On failure returns
// the code and puts the context's message in `*error`.
RTresult BuildScene(RTcontext ctx, unsigned width, unsigned height, Scene* scene,
                    std::string* error);

// The program module the scene's programs come from.
const char* ModulePath();

// The bytes of a buffer (mapped and copied).
std::string ReadBytes(RTbuffer buffer);

// The context's message for `code`.
std::string ErrorText(RTcontext ctx, RTresult code);

}  // namespace tessera::e2e

#endif  // TESSERA_TESTS_E2E_E2E_SCENE_H_
