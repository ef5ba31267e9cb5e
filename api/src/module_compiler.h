// Compiles C++ program sources into program modules with the system compiler, cached by content:
// the key hashes the source, the compiler command and the program-side headers, so editing
// tessera/device.h recompiles. Headers the source includes from elsewhere (a "common.h" beside
// it) are part of the module's name through the compiler's dependency list, kept per source
// directory, so the same text in two directories with different headers never shares a module.
#ifndef TESSERA_API_SRC_MODULE_COMPILER_H_
#define TESSERA_API_SRC_MODULE_COMPILER_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::api {

// $TESSERA_CACHE_DIR, else $XDG_CACHE_HOME/tessera/modules, else ~/.cache/tessera/modules.
std::string ModuleCacheDir();

// $TESSERA_INCLUDE_DIR (colon-separated) if set, else the installed headers beside libtessera
// (<includedir>/tessera), else the api/include directory of this build.
std::vector<std::string> ProgramIncludeDirs();

// The OptiX 7 include root (api/include7, docs/optix7.md) that OptiX 7 programs compile against:
// $TESSERA_OPTIX7_INCLUDE_DIR (colon-separated) if set, else the installed one beside libtessera
// (<includedir>/tessera/optix7), else the api/include7 directory of this build.
std::vector<std::string> Optix7IncludeDirs();

// How CompileProgramModule compiles. The defaults are the OptiX 3 layer's.
struct ProgramCompileOptions {
  // An OptiX 7 program: compiled against Optix7IncludeDirs() instead of ProgramIncludeDirs().
  bool optix7 = false;
  // The cache directory, created if missing (an OptiX 7 context's cache location); an error if
  // it cannot be used. Empty: ModuleCacheDir(), or a temporary directory when that cannot be.
  std::string cache_dir;
  // Fast math (the context's TESSERA_ACCURACY_FAST_MATH, docs/fast_math.md): -ffast-math with
  // NaN and infinity checks kept (-fno-finite-math-only), and TESSERA_FAST_MATH defined so that
  // the module says so to the devices. Part of the compile command, so of the cache key.
  bool fast_math = false;
};

// A module in the compile cache: its path, its bytes and their SHA-256 (ModuleHash), read once
// to check a cached module is the one compiled and handed on so nobody reads them again.
struct CompiledModule {
  std::string path;
  std::string bytes;
  std::string hash;
};

// Compiles `source` (the contents of `source_path`, or text to be written to a temporary file
// when `source_path` is empty) into the cache, or finds it there. Compiler errors are
// RT_ERROR_INVALID_SOURCE with the compiler's first lines.
absl::StatusOr<CompiledModule> CompileProgramModule(absl::string_view source,
                                                    const std::string& source_path,
                                                    const ProgramCompileOptions& options = {});

// Keeps a module that was compiled elsewhere (an application's own .so, or its bytes) in the
// cache under its hash, so that it is a file of the cache like a compiled one.
absl::StatusOr<CompiledModule> StoreProgramModule(absl::string_view bytes,
                                                  const ProgramCompileOptions& options = {});

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_MODULE_COMPILER_H_
