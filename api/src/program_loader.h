// Turns what rtProgramCreateFromPTX{File,String} receive into a program module on disk: a
// module (.so) is checked for the function; C++ source is compiled first (module_compiler.h).
#ifndef TESSERA_API_SRC_PROGRAM_LOADER_H_
#define TESSERA_API_SRC_PROGRAM_LOADER_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::api {

struct ModuleRef {
  std::string path;  // absolute
  std::string hash;  // ModuleHash of the module file
  // The file's bytes as read now, shared by every program of the same module: devices receive
  // these, so a module rebuilt at the same path later does not change existing programs (as PTX
  // is compiled when the program is created, in OptiX).
  std::shared_ptr<const std::string> bytes;
};

// `path` is a module (.so, or any ELF shared object) or C++ source (.cu, .cpp, .cc, .cxx).
// Missing file: RT_ERROR_FILE_NOT_FOUND. Missing function or bad source: RT_ERROR_INVALID_SOURCE.
// `fast_math`: source compiles with fast math (the context's TESSERA_ACCURACY_FAST_MATH); a
// module is taken as it was built.
absl::StatusOr<ModuleRef> LoadProgramFile(const std::string& path, const std::string& function,
                                          bool fast_math = false);

// C++ source text of a program module.
absl::StatusOr<ModuleRef> LoadProgramSource(absl::string_view source, const std::string& function,
                                            bool fast_math = false);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_PROGRAM_LOADER_H_
