#include "tutorial/programs.h"

#include <filesystem>

#include "tutorial/rt_check.h"

namespace tessera::tutorial {

ProgramLoader::ProgramLoader(RTcontext context, std::string module_dir)
    : context_(context), module_dir_(std::move(module_dir)) {}

std::string ProgramLoader::ModulePath(const char* module) const {
  return (std::filesystem::path(module_dir_) / (std::string(module) + ".so")).string();
}

RTprogram ProgramLoader::Get(const ProgramRef& ref) {
  auto key = std::make_pair(std::string(ref.module), std::string(ref.function));
  auto it = programs_.find(key);
  if (it != programs_.end()) return it->second;

  const std::string path = ModulePath(ref.module);
  // A missing module is the likeliest mistake (modules not built, wrong directory): say so.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw TutorialError("program module '" + path +
                        "' not found (build the tutorial_* targets, or point --modules or "
                        "TESSERA_MODULE_DIR at the directory that holds them)");
  }
  RTprogram program = nullptr;
  CheckRt(context_, rtProgramCreateFromPTXFile(context_, path.c_str(), ref.function, &program),
          "rtProgramCreateFromPTXFile(" + path + ", " + ref.function + ")");
  programs_.emplace(std::move(key), program);
  return program;
}

}  // namespace tessera::tutorial
