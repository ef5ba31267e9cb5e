// `tessera render SCENE -o OUT [options]`: scene files into images (docs/render.md).
//
// Exit status: 0 when every frame was written (or skipped), 1 when rendering failed (a missing
// or bad scene, a device that cannot be used, an image that cannot be written), 2 for a usage
// error (an unknown flag or a bad value, named in the message), 130 after SIGINT and 143 after
// SIGTERM (the image so far was written, with its sample count).
#ifndef TESSERA_TOOLS_TESSERA_RENDER_RENDER_COMMAND_H_
#define TESSERA_TOOLS_TESSERA_RENDER_RENDER_COMMAND_H_

#include <CLI/CLI.hpp>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::render {

struct RenderOptions {
  std::string scene;   // a file, or builtin:NAME
  std::string output;  // an image path; '#' runs take the frame number
  uint32_t spp = 64;
  double time_limit = 0.0;  // seconds; 0: none
  int max_depth = 8;
  float clamp_indirect = 0.f;  // 0: off
  int width = 0, height = 0;   // 0: from the camera's aspect ratio (docs/render.md)
  std::string camera;
  std::vector<float> look_from, look_at;  // --look-from, --look-at: empty when not given
  float fov_degrees = 0.f;                // --fov: vertical field of view; 0: the camera's own
  std::vector<std::string> point_lights;  // --point-light X,Y,Z,R,G,B, added to every frame
  std::string frames;                     // "" : one image at time 0
  double fps = 24.0;
  bool skip_existing = false;
  std::string environment;
  float environment_intensity = 1.f;
  // Empty: black, or a white sky for a scene with no lights and no emissive surfaces (an OBJ
  // without Ke materials would otherwise render black).
  std::vector<float> background;
  uint32_t seed = 0;
  std::string devices;
  std::string tile_size;
  int threads = 0;  // --threads: per device; 0: the devices' default (every core between them)
  std::string log_level = "info";
  bool resume = false;
  bool keep_accumulation = false;
  uint32_t pass_samples = 0;  // 0: chosen for passes of about a second
  uint32_t aov_samples = 16;
  bool exr_float = false;
};

// Adds the `render` subcommand to `app`; parsing fills `options`, checking each value (a bad one
// is a CLI::ValidationError naming its flag).
CLI::App* AddRenderCommand(CLI::App& app, RenderOptions& options);

// Renders what `options` asks for; returns the exit status above.
int RunRender(const RenderOptions& options);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_RENDER_COMMAND_H_
