// `tessera`: Tessera's command-line tool. Subcommands: render (docs/render.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_split.h"
#include "tessera/worker/static_tls.h"
#include "tools/tessera/render/image_io.h"
#include "tools/tessera/render/render_command.h"

namespace {

// Whether the render runs on an in-process device: an `inproc` entry of --devices, else of
// TESSERA_DEVICES (a host name containing "inproc" is not one).
bool UsesInprocDevice(const tessera::render::RenderOptions& o) {
  const char* env = std::getenv("TESSERA_DEVICES");
  const std::string spec = !o.devices.empty() ? o.devices : env != nullptr ? env : "";
  for (absl::string_view entry : absl::StrSplit(spec, ',')) {
    if (absl::StripAsciiWhitespace(entry) == "inproc") return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Tessera: OptiX-style ray tracing on CPUs.", "tessera"};
  app.set_version_flag("--version", tessera::render::SoftwareName());
  app.require_subcommand(1);
  tessera::render::RenderOptions render_options;
  CLI::App* render = tessera::render::AddRenderCommand(app, render_options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every usage error 2, its message naming the flag.
    return app.exit(e) == 0 ? 0 : 2;
  }
  // In-process devices load program modules' initial-exec builds only where the process has
  // static TLS for them, which only a new start gives (tessera/worker/static_tls.h); the tool
  // loads no graphics driver or plug-in that could need that room later. Only for them: a start
  // of this tool costs ~0.5 s (the image libraries' loading), and workers reserve their own room.
  if (render->parsed() && UsesInprocDevice(render_options)) {
    tessera::worker::RestartWithModuleStaticTls(argv, "TESSERA_TOOL_RESTARTED");
  }
  if (render->parsed()) return tessera::render::RunRender(render_options);
  return 2;
}
