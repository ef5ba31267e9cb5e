#include "module_compiler.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <random>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "hash.h"
#include "status.h"
#include "subprocess.h"
#include "tessera/scheduler/install_paths.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/module_cache_files.h"
#include "tessera/scheduler/module_file.h"

#ifndef TESSERA_PROGRAM_INCLUDE_DIR
#define TESSERA_PROGRAM_INCLUDE_DIR ""
#endif
#ifndef TESSERA_OPTIX7_INCLUDE_DIR
#define TESSERA_OPTIX7_INCLUDE_DIR ""
#endif

namespace tessera::api {
namespace fs = std::filesystem;
namespace {

constexpr int kErrorLines = 20;

std::string CompilerName() {
  const char* cxx = std::getenv("TESSERA_CXX");
  return cxx != nullptr && *cxx != '\0' ? cxx : "c++";
}

// The compiler command without input and output paths (they do not change the result): the
// README's line. __CUDACC__ tells the headers (and the program's own, `#ifdef __CUDACC__`) that
// this is program code, as nvcc does; each include directory's optixu/ is searched too, as OptiX
// SDK projects put include/optixu on the path (`#include <optixu_math_namespace.h>`). OptiX 7
// programs have no optixu (docs/optix7.md gives their command). Fast math is nvcc's
// --use_fast_math analogue with isnan/isinf still answering (docs/fast_math.md).
std::vector<std::string> CompileFlags(const std::vector<std::string>& include_dirs, bool optix7,
                                      bool fast_math) {
  std::vector<std::string> flags = {CompilerName(), "-std=c++17", "-O2",
                                    "-shared",      "-fPIC",      "-D__CUDACC__"};
  if (fast_math) {
    flags.insert(flags.end(), {"-ffast-math", "-fno-finite-math-only", "-DTESSERA_FAST_MATH=1"});
  }
  for (const std::string& dir : include_dirs) {
    flags.push_back("-I" + dir);
    std::error_code ec;
    if (!optix7 && fs::is_directory(dir + "/optixu", ec)) flags.push_back("-I" + dir + "/optixu");
  }
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

// Headers a source includes from outside the include directories (a "common.h" beside it) are
// part of the module too. After each compile the compiler's dependency list is kept beside the
// modules as `<lookup key>.deps` (one path per line; the lookup key adds the source's directory,
// where `#include "..."` looks first); the module's name hashes the source key with those files'
// current contents (not their paths: the same text with the same headers elsewhere is the same
// module), so editing a header is a new module, as editing the source is. Returns 0 when a
// listed file cannot be read (compiled again).
uint64_t DependencyKey(uint64_t source_key, const std::vector<std::string>& files) {
  uint64_t key = source_key;
  for (const std::string& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return 0;
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    key = HashString(bytes, key);
  }
  return key == 0 ? 1 : key;
}

// Where the dependency list of `key`'s source at `source_path` is kept: the same text in two
// directories may include different headers.
uint64_t LookupKey(uint64_t key, const std::string& source_path) {
  if (source_path.empty()) return key;
  std::error_code ec;
  const fs::path absolute = fs::absolute(source_path, ec);
  return HashString(fs::weakly_canonical(absolute, ec).parent_path().string(), key);
}

constexpr char kModuleHashLine[] = "sha256 ";

// A file's bytes and their SHA-256 (hash "" when it cannot be read): a cache hit must be the
// bytes that were compiled, not whatever a disk error or another program left under the name.
CompiledModule ReadModule(const std::string& path) {
  CompiledModule m;
  m.path = path;
  std::ifstream in(path, std::ios::binary);
  if (!in) return m;
  m.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (!in.bad()) m.hash = ModuleHash(m.bytes);
  return m;
}

std::vector<std::string> ReadLines(const std::string& path, bool* found) {
  std::ifstream in(path);
  *found = static_cast<bool>(in);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

// The prerequisites of a make rule as `c++ -MMD -MF` writes it, less `source`.
std::vector<std::string> ParseDepFile(const std::string& path, const std::string& source) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  size_t colon = text.find(": ");
  std::vector<std::string> files;
  if (colon == std::string::npos) return files;
  std::string word;
  auto flush = [&] {
    if (!word.empty() && word != source) files.push_back(word);
    word.clear();
  };
  for (size_t i = colon + 2; i < text.size(); ++i) {
    const char ch = text[i];
    if (ch == '\\' && i + 1 < text.size() && text[i + 1] == '\n') {
      ++i;
      flush();
    } else if (ch == '\\' && i + 1 < text.size() && text[i + 1] == ' ') {
      word += ' ';
      ++i;
    } else if (ch == ' ' || ch == '\n' || ch == '\t') {
      flush();
    } else {
      word += ch;
    }
  }
  flush();
  return files;
}

// Of fixed width: the temporary source's name ends up in the module (its STT_FILE symbol), and a
// name of varying length made modules of the same source differ in size from compile to compile.
std::string TempSuffix() {
  std::random_device rd;
  return absl::StrFormat("%010d-%08x", static_cast<int>(getpid()), rd());
}

// ModuleCacheDir(), created; where it cannot be created or written and the application did not
// choose it ($TESSERA_CACHE_DIR), a private temporary directory, said once on stderr and removed
// at exit, as the devices' module cache does (docs/programs.md): a HOME that cannot be written
// (a service account's /nonexistent) must not stop programs from compiling.
// `chosen_dir`, when not empty, is the caller's choice (an OptiX 7 context's cache location), used
// as $TESSERA_CACHE_DIR is.
absl::StatusOr<std::string> UsableModuleCacheDir(const std::string& chosen_dir) {
  const std::string wanted = chosen_dir.empty() ? ModuleCacheDir() : chosen_dir;
  std::error_code ec;
  fs::create_directories(wanted, ec);
  if (!ec && access(wanted.c_str(), W_OK | X_OK) == 0) return wanted;
  const std::string why = ec ? ec.message() : std::strerror(errno);
  if (!chosen_dir.empty()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot use module cache directory '", wanted, "': ", why));
  }
  const char* chosen = std::getenv("TESSERA_CACHE_DIR");
  if (chosen != nullptr && *chosen != '\0') {
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("cannot use module cache directory '",
                                                         wanted, "' ($TESSERA_CACHE_DIR): ", why));
  }
  static std::mutex mu;
  static std::string* temp_dir = nullptr;
  std::lock_guard<std::mutex> lock(mu);
  if (temp_dir != nullptr) return *temp_dir;
  fs::path root = fs::temp_directory_path(ec);
  if (ec) root = "/tmp";
  std::string temp = (root / "tessera-compile-XXXXXX").string();
  if (mkdtemp(temp.data()) == nullptr) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot create module cache directory '", wanted, "': ", why,
                                "; nor a temporary one: ", std::strerror(errno)));
  }
  log::Warn(log::Component::kApi, "compile cache %s is not usable (%s); using %s instead", wanted,
            why, temp);
  temp_dir = new std::string(temp);
  std::atexit([] {
    std::error_code ignored;
    fs::remove_all(*temp_dir, ignored);
  });
  return *temp_dir;
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
  if (env != nullptr && *env != '\0') return absl::StrSplit(env, ':', absl::SkipEmpty());
  // An installed library's own headers first: a source tree that still exists may be another
  // version.
  const std::string installed = scheduler::InstalledIncludeDir();
  std::error_code ec;
  if (!installed.empty() && fs::is_regular_file(installed + "/tessera/device.h", ec)) {
    return {installed};
  }
  scheduler::NoteBuildTreeFallback(scheduler::InstalledPart::kHeaders,
                                   fs::path(installed).lexically_normal(),
                                   TESSERA_PROGRAM_INCLUDE_DIR);
  return absl::StrSplit(TESSERA_PROGRAM_INCLUDE_DIR, ':', absl::SkipEmpty());
}

std::vector<std::string> Optix7IncludeDirs() {
  const char* env = std::getenv("TESSERA_OPTIX7_INCLUDE_DIR");
  if (env != nullptr && *env != '\0') return absl::StrSplit(env, ':', absl::SkipEmpty());
  const std::string installed = scheduler::InstalledIncludeDir() + "/optix7";
  std::error_code ec;
  if (fs::is_regular_file(installed + "/optix_device.h", ec)) return {installed};
  scheduler::NoteBuildTreeFallback(scheduler::InstalledPart::kHeaders,
                                   fs::path(installed).lexically_normal(),
                                   TESSERA_OPTIX7_INCLUDE_DIR);
  return absl::StrSplit(TESSERA_OPTIX7_INCLUDE_DIR, ':', absl::SkipEmpty());
}

// Builds the module of `command` (the compile command without its input and output) with
// initial-exec thread-local variables into `output`. Returns `output`, or "" when that build
// failed: the module then goes without it (its variables stay local-dynamic everywhere).
std::string InitialExecBuild(std::vector<std::string> command, const std::string& input,
                             const std::string& output) {
  command.insert(command.end(), {"-DTESSERA_TLS_INITIAL_EXEC=1", input, "-o", output});
  absl::StatusOr<CommandResult> result = RunCommand(command);
  std::error_code ec;
  if (result.ok() && result->exit_code == 0 && fs::is_regular_file(output, ec)) return output;
  fs::remove(output, ec);
  return "";
}

// Puts the initial-exec build into `module` as a section that is not loaded with it
// (scheduler::kInitialExecSection); devices that can use it write it out (worker/core/module.cc).
// A module without it (no objcopy) still loads everywhere.
void EmbedInitialExecBuild(const std::string& module, const std::string& initial_exec) {
  const std::string section = scheduler::kInitialExecSection;
  absl::StatusOr<CommandResult> result =
      RunCommand({"objcopy", "--add-section", absl::StrCat(section, "=", initial_exec),
                  "--set-section-flags", absl::StrCat(section, "=readonly"), module});
  (void)result;  // the module is whole either way: objcopy writes a new file and renames it
}

absl::StatusOr<CompiledModule> StoreProgramModule(absl::string_view bytes,
                                                  const ProgramCompileOptions& options) {
  TS_ASSIGN_OR_RETURN(const std::string cache_dir, UsableModuleCacheDir(options.cache_dir));
  CompiledModule m;
  m.bytes = std::string(bytes);
  m.hash = ModuleHash(m.bytes);
  m.path = absl::StrCat(cache_dir, "/", m.hash, ".so");
  std::error_code ec;
  if (fs::is_regular_file(m.path, ec) && ReadModule(m.path).hash == m.hash) {
    scheduler::TouchCacheFile(m.path);
    return m;
  }
  // Written under a temporary name and renamed, as compiled modules are.
  const std::string temp = absl::StrCat(m.path, ".", TempSuffix(), ".tmp");
  std::ofstream out(temp, std::ios::binary);
  out.write(m.bytes.data(), static_cast<std::streamsize>(m.bytes.size()));
  out.close();
  if (!out) {
    fs::remove(temp, ec);
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("cannot write module '", temp, "'"));
  }
  fs::rename(temp, m.path, ec);
  if (ec) {
    fs::remove(temp, ec);
    return RtError(RT_ERROR_INVALID_SOURCE, absl::StrCat("cannot store module '", m.path, "'"));
  }
  return m;
}

absl::StatusOr<CompiledModule> CompileProgramModule(absl::string_view source,
                                                    const std::string& source_path,
                                                    const ProgramCompileOptions& options) {
  const std::vector<std::string> include_dirs =
      options.optix7 ? Optix7IncludeDirs() : ProgramIncludeDirs();
  std::vector<std::string> command = CompileFlags(include_dirs, options.optix7, options.fast_math);
  uint64_t key = HashString(source);
  key = HashString(absl::StrJoin(command, "\x1f"), key);
  key ^= HeaderTreeHash(include_dirs);
  TS_ASSIGN_OR_RETURN(const std::string cache_dir, UsableModuleCacheDir(options.cache_dir));
  const std::string deps_path =
      absl::StrCat(cache_dir, "/", HexHash(LookupKey(key, source_path)), ".deps");
  std::error_code ec;
  bool have_deps = false;
  std::vector<std::string> deps = ReadLines(deps_path, &have_deps);
  // The list's first line is the SHA-256 of the module compiled (a list without one, from an
  // older Tessera, is compiled again).
  std::string compiled_hash;
  if (!deps.empty() && absl::StartsWith(deps.front(), kModuleHashLine)) {
    compiled_hash = deps.front().substr(sizeof(kModuleHashLine) - 1);
    deps.erase(deps.begin());
  }
  const uint64_t cached_key = have_deps && !compiled_hash.empty() ? DependencyKey(key, deps) : 0;
  if (cached_key != 0) {
    const std::string cached = absl::StrCat(cache_dir, "/", HexHash(cached_key), ".so");
    // Anything else under the module's name (cut short, changed, or not a file) is compiled over.
    if (fs::is_regular_file(cached, ec)) {
      CompiledModule hit = ReadModule(cached);
      if (hit.hash == compiled_hash) {
        scheduler::TouchCacheFile(cached);  // recently used: trimmed last
        scheduler::TouchCacheFile(deps_path);
        return hit;
      }
    }
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
  const std::string temp_module = absl::StrCat(cache_dir, "/", HexHash(key), ".", suffix, ".tmp");
  const std::string temp_deps = absl::StrCat(temp_module, ".d");
  // An OptiX 3 module also carries itself built with initial-exec thread-local variables, compiled
  // alongside (InitialExecBuild).
  std::future<std::string> initial_exec;
  if (!options.optix7) {
    initial_exec = std::async(std::launch::async, InitialExecBuild, command, input,
                              absl::StrCat(temp_module, ".ie"));
  }
  command.push_back("-MMD");  // system headers change with the compiler (in the key)
  command.push_back("-MF");
  command.push_back(temp_deps);
  command.push_back(input);
  command.push_back("-o");
  command.push_back(temp_module);
  auto result = RunCommand(command);
  const std::string initial_exec_path = initial_exec.valid() ? initial_exec.get() : "";
  // Tessera's own headers are in the key already (HeaderTreeHash): list only the others.
  std::vector<std::string> compiled_deps = ParseDepFile(temp_deps, input);
  for (const std::string& dir : include_dirs) {
    const std::string prefix = dir.back() == '/' ? dir : dir + "/";
    compiled_deps.erase(
        std::remove_if(compiled_deps.begin(), compiled_deps.end(),
                       [&](const std::string& f) { return f.rfind(prefix, 0) == 0; }),
        compiled_deps.end());
  }
  fs::remove(temp_deps, ec);
  if (!temp_source.empty()) fs::remove(temp_source, ec);
  const char* chosen = std::getenv("TESSERA_CXX");
  const bool from_env = chosen != nullptr && *chosen != '\0';
  if (!initial_exec_path.empty() && (!result.ok() || result->exit_code != 0)) {
    fs::remove(initial_exec_path, ec);
  }
  if (!result.ok()) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot run the C++ compiler: ", result.status().message(),
                                from_env ? " (it is $TESSERA_CXX: name a C++ compiler there; "
                                           "it is run directly, without a shell)"
                                         : " (set TESSERA_CXX to choose one)"));
  }
  if (result->exit_code != 0) {
    fs::remove(temp_module, ec);
    // Without Tessera's headers every error is a consequence: say where they were looked for.
    std::string headers;
    if (absl::StrContains(result->output, "optix.h: No such file") ||
        absl::StrContains(result->output, "optix_world.h: No such file") ||
        absl::StrContains(result->output, "tessera/device.h: No such file")) {
      headers =
          absl::StrCat("Tessera's program headers are not in the include directories it passed (",
                       absl::StrJoin(include_dirs, ", "), "); set ",
                       options.optix7 ? "TESSERA_OPTIX7_INCLUDE_DIR" : "TESSERA_INCLUDE_DIR",
                       " to the directory holding optix.h (an installed <prefix>/include/tessera",
                       options.optix7 ? "/optix7" : "", ")\n");
    }
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("compiling '", source_path.empty() ? "<string>" : source_path,
                                "' failed (", command.front(), " exit code ", result->exit_code,
                                "):\n", headers, FirstLines(result->output, kErrorLines)));
  }
  if (!fs::is_regular_file(temp_module, ec)) {
    // Exit status 0 and no output: not a compiler (TESSERA_CXX=/bin/true), or one that ignored -o.
    return RtError(
        RT_ERROR_INVALID_SOURCE,
        absl::StrCat("compiling '", source_path.empty() ? "<string>" : source_path, "': '",
                     command.front(), "'", from_env ? " ($TESSERA_CXX)" : "",
                     " exited with status 0 but wrote no module; is it a C++ compiler?",
                     result->output.empty() ? "" : "\n", FirstLines(result->output, kErrorLines)));
  }
  if (!initial_exec_path.empty()) {
    EmbedInitialExecBuild(temp_module, initial_exec_path);
    fs::remove(initial_exec_path, ec);
  }
  // The module's name covers the headers as they were read; a header edited since is read
  // again at the next lookup, differs, and compiles again.
  const uint64_t module_key = DependencyKey(key, compiled_deps);
  const std::string module_path = absl::StrCat(cache_dir, "/", HexHash(module_key), ".so");
  CompiledModule compiled = ReadModule(temp_module);
  compiled.path = module_path;
  {
    const std::string temp_list = absl::StrCat(deps_path, ".", suffix, ".tmp");
    std::ofstream out(temp_list);
    out << kModuleHashLine << compiled.hash << "\n";
    for (const std::string& file : compiled_deps) out << file << "\n";
    out.close();
    if (out) fs::rename(temp_list, deps_path, ec);
    if (!out || ec) fs::remove(temp_list, ec);
  }
  fs::rename(temp_module, module_path, ec);
  if (ec) {
    return RtError(RT_ERROR_INVALID_SOURCE,
                   absl::StrCat("cannot store module '", module_path, "': ", ec.message()));
  }
  // Every edit of a source is a new module: keep the directory within its bound.
  scheduler::TrimModuleCache(cache_dir, scheduler::ModuleCacheLimitBytes(), HexHash(module_key));
  return compiled;
}

}  // namespace tessera::api
