// Turns what rtProgramCreateFromPTX{File,String} receive into a program module on disk: a
// module (.so) is checked for the function; C++ source is compiled first (module_compiler.h).
#ifndef TESSERA_API_SRC_PROGRAM_LOADER_H_
#define TESSERA_API_SRC_PROGRAM_LOADER_H_

#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::api {

struct ModuleRef {
  std::string path;  // absolute
  std::string hash;  // hex content hash of the module file
};

// `path` is a module (.so, or any ELF shared object) or C++ source (.cu, .cpp, .cc, .cxx).
// Missing file: RT_ERROR_FILE_NOT_FOUND. Missing function or bad source: RT_ERROR_INVALID_SOURCE.
absl::StatusOr<ModuleRef> LoadProgramFile(const std::string& path, const std::string& function);

// C++ source text of a program module.
absl::StatusOr<ModuleRef> LoadProgramSource(absl::string_view source, const std::string& function);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_PROGRAM_LOADER_H_
