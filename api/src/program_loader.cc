#include "program_loader.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "hash.h"
#include "module_compiler.h"
#include "status.h"
#include "tessera/scheduler/module_file.h"

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

// Whether `text` is PTX (what nvcc emits for OptiX): after blank lines and // comments, a
// .version or .target directive. C++ cannot start that way, so nothing valid is refused.
bool LooksLikePtx(absl::string_view text) {
  while (!text.empty()) {
    text = absl::StripLeadingAsciiWhitespace(text);
    if (!absl::StartsWith(text, "//")) break;
    const size_t eol = text.find('\n');
    text = eol == absl::string_view::npos ? absl::string_view() : text.substr(eol + 1);
  }
  return absl::StartsWith(text, ".version") || absl::StartsWith(text, ".target");
}

constexpr char kNoPtx[] =
    "PTX is not accepted: Tessera runs programs compiled as C++ from their .cu source; pass the "
    ".cu file (or its text) or a module built from it (README \"Writing programs\")";

// Checks that `function` exists from the module's dynamic symbol table, without loading it: the
// host never runs program code (dlopen would run the module's global constructors here, and one
// that crashes or exits would take the application down instead of a worker). What the module
// needs at run time (its libraries, the module ABI) the device that loads it reports.
absl::Status CheckModule(const std::string& path, absl::string_view bytes, const std::string& name,
                         const std::string& function) {
  if (absl::Status whole = scheduler::CheckModuleFileComplete(path); !whole.ok()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot load program module ", name, ": ", whole.message()));
  }
  absl::Status symbols = scheduler::CheckModuleBytes(bytes, function, /*require_init=*/false);
  if (absl::IsNotFound(symbols)) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("program module ", name, " defines no function '", function,
                                "' (declare it with RT_PROGRAM)"));
  }
  if (!symbols.ok()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot load program module ", name, ": ", symbols.message()));
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

// `bytes`: the module's contents when already read (null: read from `path`), `hash` their
// ModuleHash when already known. `source`: the C++ file the module was compiled from, which names
// the program in messages.
absl::StatusOr<ModuleRef> FromModule(const std::string& path, std::string* bytes,
                                     const std::string& function, const std::string& source = "",
                                     std::string hash = "") {
  std::error_code ec;
  fs::path absolute = fs::absolute(path, ec);
  ModuleRef ref;
  ref.path = ec ? path : absolute.lexically_normal().string();
  std::string read;
  if (bytes == nullptr) {
    TS_ASSIGN_OR_RETURN(read, ReadFile(ref.path));
    bytes = &read;
  }
  std::string name = absl::StrCat("'", ref.path, "'");
  if (!source.empty()) {
    const fs::path absolute_source = fs::absolute(source, ec);
    const std::string shown = ec ? source : absolute_source.lexically_normal().string();
    name = absl::StrCat("'", shown, "' (compiled as '", ref.path, "')");
    ref.path = shown;  // device messages name the source the application gave
  }
  TS_RETURN_IF_ERROR(CheckModule(path, *bytes, name, function));
  ref.hash = hash.empty() ? ModuleHash(*bytes) : std::move(hash);
  ref.bytes = SharedBytes(ref.hash, std::move(*bytes));
  return ref;
}

}  // namespace

absl::StatusOr<ModuleRef> LoadProgramFile(const std::string& path, const std::string& function) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    if (fs::exists(path, ec)) {
      return RtError(RT_ERROR_FILE_NOT_FOUND,
                     absl::StrCat("program file '", path,
                                  "' is not a regular file (a directory?); name a program module "
                                  "(.so) or C++ source file"));
    }
    return RtError(RT_ERROR_FILE_NOT_FOUND, absl::StrCat("program file '", path, "' not found"));
  }
  TS_ASSIGN_OR_RETURN(std::string bytes, ReadFile(path));
  const bool elf = bytes.size() >= 4 && bytes.compare(0, 4,
                                                      "\x7f"
                                                      "ELF") == 0;
  if (absl::EndsWith(path, ".so") || elf) return FromModule(path, &bytes, function);
  if (!IsSourcePath(path)) {
    if (LooksLikePtx(bytes)) {
      return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("'", path, "' is PTX. ", kNoPtx));
    }
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("'", path,
                                "' is neither a program module (.so) nor C++ source "
                                "(.cu, .cpp, .cc, .cxx)"));
  }
  TS_ASSIGN_OR_RETURN(CompiledModule module, CompileProgramModule(bytes, path));
  return FromModule(module.path, &module.bytes, function, path, std::move(module.hash));
}

absl::StatusOr<ModuleRef> LoadProgramSource(absl::string_view source, const std::string& function) {
  if (LooksLikePtx(source)) {
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("the source string is PTX. ", kNoPtx));
  }
  TS_ASSIGN_OR_RETURN(CompiledModule module, CompileProgramModule(source, ""));
  return FromModule(module.path, &module.bytes, function, "", std::move(module.hash));
}

}  // namespace tessera::api
