#include "module_compiler.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "hash.h"
#include "status.h"
#include "subprocess.h"
#include "tessera/scheduler/module_cache_files.h"
#include "tessera/scheduler/module_file.h"

#ifndef TESSERA_PROGRAM_INCLUDE_DIR
#define TESSERA_PROGRAM_INCLUDE_DIR ""
#endif

namespace tessera::api {
namespace fs = std::filesystem;
namespace {

constexpr int kErrorLines = 20;

std::string CompilerName() {
  const char* cxx = std::getenv("TESSERA_CXX");
  return cxx != nullptr && *cxx != '\0' ? cxx : "c++";
}

// The compiler command without input and output paths (they do not change the result).
std::vector<std::string> CompileFlags() {
  std::vector<std::string> flags = {CompilerName(), "-std=c++17", "-O2", "-shared", "-fPIC"};
  for (const std::string& dir : ProgramIncludeDirs()) flags.push_back("-I" + dir);
  flags.push_back("-x");
  flags.push_back("c++");
  return flags;
}

// Hash of every file under the include directories: a changed header is a new cache key.
uint64_t HeaderTreeHash(const std::vector<std::string>& dirs) {
  static std::mutex mu;
  static auto* cache = new absl::flat_hash_map<std::string, uint64_t>;
  std::string key = absl::StrJoin(dirs, ":");
  std::lock_guard<std::mutex> lock(mu);
  if (auto it = cache->find(key); it != cache->end()) return it->second;
  std::vector<std::string> files;
  for (const std::string& dir : dirs) {
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->is_regular_file(ec)) files.push_back(it->path().string());
    }
  }
  std::sort(files.begin(), files.end());
  uint64_t h = HashString(key);
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    h = HashString(bytes, HashString(file, h));
  }
  (*cache)[key] = h;
  return h;
}

std::string FirstLines(const std::string& text, int lines) {
  std::vector<absl::string_view> all = absl::StrSplit(text, '\n');
  if (static_cast<int>(all.size()) > lines) all.resize(lines);
  return absl::StrJoin(all, "\n");
}

std::string TempSuffix() {
  std::random_device rd;
  return absl::StrCat(getpid(), "-", rd());
}

}  // namespace

std::string ModuleCacheDir() {
  if (const char* dir = std::getenv("TESSERA_CACHE_DIR"); dir != nullptr && *dir != '\0') {
    return dir;
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return absl::StrCat(xdg, "/tessera/modules");
  }
  const char* home = std::getenv("HOME");
  return absl::StrCat(home != nullptr && *home != '\0' ? home : "/tmp", "/.cache/tessera/modules");
}

std::vector<std::string> ProgramIncludeDirs() {
  const char* env = std::getenv("TESSERA_INCLUDE_DIR");
  std::string dirs = env != nullptr && *env != '\0' ? env : TESSERA_PROGRAM_INCLUDE_DIR;
  return absl::StrSplit(dirs, ':', absl::SkipEmpty());
}

absl::StatusOr<std::string> CompileProgramModule(absl::string_view source,
                                                 const std::string& source_path) {
  std::vector<std::string> command = CompileFlags();
  uint64_t key = HashString(source);
  key = HashString(absl::StrJoin(command, "\x1f"), key);
  key ^= HeaderTreeHash(ProgramIncludeDirs());
  const std::string cache_dir = ModuleCacheDir();
  const std::string module_path = absl::StrCat(cache_dir, "/", HexHash(key), ".so");
  std::error_code ec;
  // Anything else under the module's name (cut short, or not a file) is compiled over.
  if (fs::is_regular_file(module_path, ec) &&
      scheduler::CheckModuleFileComplete(module_path).ok()) {
    scheduler::TouchCacheFile(module_path);  // recently used: trimmed last
    return module_path;
  }
  fs::create_directories(cache_dir, ec);
  if (ec) {
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("cannot create module cache directory '",
                                                         cache_dir, "': ", ec.message()));
  }

  const std::string suffix = TempSuffix();
  std::string input = source_path;
  std::string temp_source;
  if (input.empty()) {
    temp_source = absl::StrCat(cache_dir, "/", HexHash(key), ".", suffix, ".cpp");
    std::ofstream out(temp_source, std::ios::binary);
    out.write(source.data(), static_cast<std::streamsize>(source.size()));
    if (!out) {
      return RtError(RT_ERROR_INVALID_SOURCE,
                     absl::StrCat("cannot write temporary source '", temp_source, "'"));
    }
    input = temp_source;
  }
  // Compile to a temporary name and rename: concurrent compiles of the same key are harmless.
  const std::string temp_module = absl::StrCat(module_path, ".", suffix, ".tmp");
  command.push_back(input);
  command.push_back("-o");
  command.push_back(temp_module);
  auto result = RunCommand(command);
  if (!temp_source.empty()) fs::remove(temp_source, ec);
  if (!result.ok()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot run the C++ compiler: ", result.status().message(),
                                " (set TESSERA_CXX to choose one)"));
  }
  if (result->exit_code != 0) {
    fs::remove(temp_module, ec);
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("compiling '", source_path.empty() ? "<string>" : source_path,
                                "' failed (", command.front(), " exit code ", result->exit_code,
                                "):\n", FirstLines(result->output, kErrorLines)));
  }
  fs::rename(temp_module, module_path, ec);
  if (ec) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot store module '", module_path, "': ", ec.message()));
  }
  // Every edit of a source is a new module: keep the directory within its bound.
  scheduler::TrimModuleCache(cache_dir, scheduler::ModuleCacheLimitBytes(), HexHash(key));
  return module_path;
}

}  // namespace tessera::api
