#include "program_loader.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

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
  // In blocks through the stream buffer: a character at a time took half a second per thousand
  // programs created from a 100 KB module.
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return std::move(bytes).str();
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

// What was read of each module file lately, so that creating many programs from one module
// (a closest hit program per material, as OptiX applications do) reads and hashes it once. A file
// counts as the same while its inode, size and modification time are.
struct ReadModule {
  dev_t device = 0;
  ino_t inode = 0;
  off_t size = 0;
  timespec modified{};
  std::string hash;
  std::weak_ptr<const std::string> bytes;
};

bool SameFile(const struct stat& st, const ReadModule& r) {
  return st.st_dev == r.device && st.st_ino == r.inode && st.st_size == r.size &&
         st.st_mtim.tv_sec == r.modified.tv_sec && st.st_mtim.tv_nsec == r.modified.tv_nsec;
}

std::mutex read_modules_mu;
absl::flat_hash_map<std::string, ReadModule>& ReadModules() {
  static auto* modules = new absl::flat_hash_map<std::string, ReadModule>;
  return *modules;
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

absl::StatusOr<ModuleRef> LoadProgramFile(const std::string& path, const std::string& function,
                                          bool fast_math) {
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
  struct stat st {};
  const bool stated = stat(path.c_str(), &st) == 0;
  std::error_code abs_ec;
  const std::string key = fs::absolute(path, abs_ec).lexically_normal().string();
  if (stated) {
    std::shared_ptr<const std::string> seen;
    std::string hash;
    {
      std::lock_guard<std::mutex> lock(read_modules_mu);
      auto it = ReadModules().find(key);
      if (it != ReadModules().end() && SameFile(st, it->second)) {
        seen = it->second.bytes.lock();
        hash = it->second.hash;
      }
    }
    if (seen != nullptr) {
      TS_RETURN_IF_ERROR(CheckModule(path, *seen, absl::StrCat("'", key, "'"), function));
      return ModuleRef{key, std::move(hash), std::move(seen)};
    }
  }
  TS_ASSIGN_OR_RETURN(std::string bytes, ReadFile(path));
  const bool elf = bytes.size() >= 4 && bytes.compare(0, 4,
                                                      "\x7f"
                                                      "ELF") == 0;
  if (absl::EndsWith(path, ".so") || elf) {
    absl::StatusOr<ModuleRef> ref = FromModule(path, &bytes, function);
    if (ref.ok() && stated) {
      std::lock_guard<std::mutex> lock(read_modules_mu);
      ReadModules()[key] =
          ReadModule{st.st_dev, st.st_ino, st.st_size, st.st_mtim, ref->hash, ref->bytes};
    }
    return ref;
  }
  if (!IsSourcePath(path)) {
    if (LooksLikePtx(bytes)) {
      return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("'", path, "' is PTX. ", kNoPtx));
    }
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("'", path,
                                "' is neither a program module (.so) nor C++ source "
                                "(.cu, .cpp, .cc, .cxx)"));
  }
  ProgramCompileOptions options;
  options.fast_math = fast_math;
  TS_ASSIGN_OR_RETURN(CompiledModule module, CompileProgramModule(bytes, path, options));
  return FromModule(module.path, &module.bytes, function, path, std::move(module.hash));
}

absl::StatusOr<ModuleRef> LoadProgramSource(absl::string_view source, const std::string& function,
                                            bool fast_math) {
  if (LooksLikePtx(source)) {
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("the source string is PTX. ", kNoPtx));
  }
  ProgramCompileOptions options;
  options.fast_math = fast_math;
  TS_ASSIGN_OR_RETURN(CompiledModule module, CompileProgramModule(source, "", options));
  return FromModule(module.path, &module.bytes, function, "", std::move(module.hash));
}

}  // namespace tessera::api
