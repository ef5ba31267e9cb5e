// `tessera`: Tessera's command-line tool. Subcommands: render (docs/render.md).
#include <CLI/CLI.hpp>
#include <cstdio>

#include "tools/tessera/render/image_io.h"
#include "tools/tessera/render/render_command.h"

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
  if (render->parsed()) return tessera::render::RunRender(render_options);
  return 2;
}
