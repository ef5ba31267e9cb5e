// The exported symbols of a program module (an ELF shared object), read from its bytes: entry
// functions and the launch parameters' variable are found by name without loading the module,
// so that no code of an application's module runs on the host at optixModuleCreate.
#ifndef TESSERA_API_OPTIX7_ELF_SYMBOLS_H_
#define TESSERA_API_OPTIX7_ELF_SYMBOLS_H_

#include <string>

#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::optix7 {

enum class SymbolKind { kFunction, kObject, kOther };

// Defined global and weak symbols of the dynamic symbol table, by name.
using ElfSymbols = absl::flat_hash_map<std::string, SymbolKind>;

inline bool IsElf(absl::string_view bytes) {
  return bytes.size() >= 4 && bytes.substr(0, 4) == absl::string_view(
                                                        "\x7f"
                                                        "ELF",
                                                        4);
}

// INVALID_ARGUMENT saying why when `bytes` is not a 64-bit little-endian shared object for this
// machine, or its tables do not lie within it.
absl::StatusOr<ElfSymbols> ReadExportedSymbols(absl::string_view bytes);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_ELF_SYMBOLS_H_
