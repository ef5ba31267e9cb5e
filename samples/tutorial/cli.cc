#include "tutorial/cli.h"

#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <exception>
#include <string>

#include "tutorial/image_io.h"
#include "tutorial/render.h"
#include "tutorial/rt_check.h"
#include "tutorial/steps.h"

namespace tessera::tutorial {
namespace {

// Whether `path` can be written, checked before rendering: a long render should not end in
// "Could not open file". Names the directory or file and the system's reason.
void CheckOutputWritable(const std::string& out_path) {
  // Through symlinks, to where the image will land.
  const std::string path = OutputTarget(out_path);
  const std::string dir = DirectoryOf(path);
  struct stat st {};
  if (stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw TutorialError("cannot write '" + path + "': it is a directory");
    if (access(path.c_str(), W_OK) != 0) {
      throw TutorialError("cannot write '" + path + "': " + std::strerror(errno));
    }
    return;
  }
  if (stat(dir.c_str(), &st) != 0) {
    throw TutorialError("cannot write '" + path + "': directory '" + dir +
                        "': " + std::strerror(errno));
  }
  if (!S_ISDIR(st.st_mode)) {
    throw TutorialError("cannot write '" + path + "': '" + dir + "' is not a directory");
  }
  if (access(dir.c_str(), W_OK | X_OK) != 0) {
    throw TutorialError("cannot write '" + path + "': directory '" + dir +
                        "': " + std::strerror(errno));
  }
}

}  // namespace

int RunTutorialMain(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  CLI::App app{"Renders a step of the OptiX SDK tutorial (Whitted-style ray tracing) with Tessera.",
               "tessera-tutorial"};
  RenderOptions options;
  options.load_envmap = &LoadEnvmapFile;  // the file the build wrote, or --envmap
  std::string out_path;
  std::string modules;
  app.add_option("--step", options.step,
                 "tutorial step (0-10; 11: step 10 through an environment camera)")
      ->required();
  app.add_option("--envmap", options.envmap,
                 "environment map of steps 5 on: an image file (HDR, EXR, PNG ...) in "
                 "latitude-longitude layout (default: the sky the build made)");
  app.add_option("--width", options.width, "image width in pixels")->capture_default_str();
  app.add_option("--height", options.height, "image height in pixels")->capture_default_str();
  app.add_option("--out", out_path, "output image (.png: 8-bit RGBA, .exr: float RGBA)")
      ->required();
  app.add_option("--modules", modules,
                 "directory of the tutorial_*.so program modules (default: $TESSERA_MODULE_DIR, "
                 "else the build's modules directory)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e, out, err);
  }

  try {
    // Check what needs no rendering first, so mistakes fail fast.
    GetStep(options.step);  // an unknown step fails before anything else
    CheckImageSize(FormatForPath(out_path), options.width, options.height);
    CheckOutputWritable(out_path);
    options.module_dir = ResolveModuleDir(modules);
    const Image image = RenderStep(options);
    WriteImage(out_path, image);
  } catch (const std::exception& e) {
    err << "tessera-tutorial: error: " << e.what() << "\n";
    return 1;
  }
  out << out_path << "\n";
  return 0;
}

}  // namespace tessera::tutorial
