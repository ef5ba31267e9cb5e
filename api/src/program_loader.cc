#include "program_loader.h"

#include <dlfcn.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "hash.h"
#include "module_compiler.h"
#include "status.h"
#include "tessera/scheduler/module_file.h"
#include "tessera/scheduler/module_symbol.h"

namespace tessera::api {
namespace fs = std::filesystem;
namespace {

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return RtError(RT_ERROR_FILE_NOT_FOUND,
                   absl::StrCat("cannot open '", path, "': ", std::strerror(errno)));
  }
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool IsSourcePath(const std::string& path) {
  for (const char* ext : {".cu", ".cpp", ".cc", ".cxx", ".c++"}) {
    if (absl::EndsWith(path, ext)) return true;
  }
  return false;
}

// Loads the module only to see that `function` exists: the host never runs program code.
// RTLD_LAZY so that a module is not refused for symbols only a device resolves.
absl::Status CheckModule(const std::string& path, const std::string& function) {
  if (absl::Status whole = scheduler::CheckModuleFileComplete(path); !whole.ok()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot load program module '", path, "': ", whole.message()));
  }
  void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot load program module '", path,
                                "': ", why != nullptr ? why : "unknown error"));
  }
  dlerror();
  void* symbol = scheduler::FindModuleFunction(handle, function.c_str());
  dlclose(handle);
  if (symbol == nullptr) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("program module '", path, "' defines no function '", function,
                                "' (declare it with RT_PROGRAM)"));
  }
  return absl::OkStatus();
}

// One copy of each module's bytes while programs hold it, however many programs use it.
std::shared_ptr<const std::string> SharedBytes(const std::string& hash, std::string&& bytes) {
  static std::mutex mu;
  static auto* live = new absl::flat_hash_map<std::string, std::weak_ptr<const std::string>>;
  std::lock_guard<std::mutex> lock(mu);
  std::shared_ptr<const std::string> shared = (*live)[hash].lock();
  if (shared == nullptr) {
    shared = std::make_shared<const std::string>(std::move(bytes));
    (*live)[hash] = shared;
  }
  // Expired entries are dropped as they are met, so the table stays as large as what is alive.
  absl::erase_if(*live, [](const auto& entry) { return entry.second.expired(); });
  return shared;
}

absl::StatusOr<ModuleRef> FromModule(const std::string& path, std::string* bytes,
                                     const std::string& function) {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  ModuleRef ref;
  ref.path = ec ? path : absolute.lexically_normal().string();
  std::string read;
  if (bytes == nullptr) {
    TS_ASSIGN_OR_RETURN(read, ReadFile(ref.path));
    bytes = &read;
  }
  TS_RETURN_IF_ERROR(CheckModule(ref.path, function));
  ref.hash = ModuleHash(*bytes);
  ref.bytes = SharedBytes(ref.hash, std::move(*bytes));
  return ref;
}

}  // namespace

absl::StatusOr<ModuleRef> LoadProgramFile(const std::string& path, const std::string& function) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    return RtError(RT_ERROR_FILE_NOT_FOUND, absl::StrCat("program file '", path, "' not found"));
  }
  TS_ASSIGN_OR_RETURN(std::string bytes, ReadFile(path));
  const bool elf = bytes.size() >= 4 && bytes.compare(0, 4,
                                                      "\x7f"
                                                      "ELF") == 0;
  if (absl::EndsWith(path, ".so") || elf) return FromModule(path, &bytes, function);
  if (!IsSourcePath(path)) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("'", path,
                                "' is neither a program module (.so) nor C++ source "
                                "(.cu, .cpp, .cc, .cxx)"));
  }
  TS_ASSIGN_OR_RETURN(std::string module, CompileProgramModule(bytes, path));
  return FromModule(module, nullptr, function);
}

absl::StatusOr<ModuleRef> LoadProgramSource(absl::string_view source, const std::string& function) {
  TS_ASSIGN_OR_RETURN(std::string module, CompileProgramModule(source, ""));
  return FromModule(module, nullptr, function);
}

}  // namespace tessera::api
