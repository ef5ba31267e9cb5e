#include "elf_symbols.h"

#include <elf.h>

#include <cstring>

#include "absl/strings/str_cat.h"

namespace tessera::optix7 {
namespace {

#if defined(__x86_64__)
constexpr uint16_t kMachine = EM_X86_64;
#elif defined(__aarch64__)
constexpr uint16_t kMachine = EM_AARCH64;
#else
#error "program modules: unknown machine"
#endif

// A copy of the T at `offset`, when it lies within `bytes` (module bytes are not aligned).
template <typename T>
bool ReadAt(absl::string_view bytes, uint64_t offset, T* out) {
  if (offset > bytes.size() || bytes.size() - offset < sizeof(T)) return false;
  std::memcpy(out, bytes.data() + offset, sizeof(T));
  return true;
}

absl::Status Bad(absl::string_view why) {
  return absl::InvalidArgumentError(absl::StrCat("not a program module: ", why));
}

}  // namespace

absl::StatusOr<ElfSymbols> ReadExportedSymbols(absl::string_view bytes) {
  Elf64_Ehdr eh;
  if (!IsElf(bytes) || !ReadAt(bytes, 0, &eh)) return Bad("no ELF header");
  if (eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_ident[EI_DATA] != ELFDATA2LSB) {
    return Bad("not a 64-bit little-endian ELF file");
  }
  if (eh.e_type != ET_DYN) return Bad("an ELF file that is not a shared object (-shared)");
  if (eh.e_machine != kMachine) {
    return Bad(absl::StrCat("a shared object for another machine (e_machine ", eh.e_machine,
                            ", this one is ", kMachine, ")"));
  }
  if (eh.e_shentsize != sizeof(Elf64_Shdr)) return Bad("unexpected section header size");
  ElfSymbols symbols;
  for (unsigned i = 0; i < eh.e_shnum; ++i) {
    Elf64_Shdr sh;
    if (!ReadAt(bytes, eh.e_shoff + uint64_t{i} * sizeof(Elf64_Shdr), &sh)) {
      return Bad("section headers past the end of the file");
    }
    if (sh.sh_type != SHT_DYNSYM) continue;
    Elf64_Shdr strtab;
    if (!ReadAt(bytes, eh.e_shoff + uint64_t{sh.sh_link} * sizeof(Elf64_Shdr), &strtab) ||
        strtab.sh_offset > bytes.size() || bytes.size() - strtab.sh_offset < strtab.sh_size) {
      return Bad("dynamic string table past the end of the file");
    }
    const absl::string_view names = bytes.substr(strtab.sh_offset, strtab.sh_size);
    if (sh.sh_entsize != sizeof(Elf64_Sym)) return Bad("unexpected symbol size");
    for (uint64_t k = 1; k < sh.sh_size / sizeof(Elf64_Sym); ++k) {
      Elf64_Sym sym;
      if (!ReadAt(bytes, sh.sh_offset + k * sizeof(Elf64_Sym), &sym)) {
        return Bad("dynamic symbols past the end of the file");
      }
      const unsigned bind = ELF64_ST_BIND(sym.st_info);
      const unsigned visibility = ELF64_ST_VISIBILITY(sym.st_other);
      if (sym.st_shndx == SHN_UNDEF || (bind != STB_GLOBAL && bind != STB_WEAK) ||
          (visibility != STV_DEFAULT && visibility != STV_PROTECTED) ||
          sym.st_name >= names.size()) {
        continue;
      }
      const absl::string_view rest = names.substr(sym.st_name);
      const std::string name(rest.substr(0, rest.find('\0')));
      const unsigned type = ELF64_ST_TYPE(sym.st_info);
      symbols[name] = type == STT_FUNC     ? SymbolKind::kFunction
                      : type == STT_OBJECT ? SymbolKind::kObject
                                           : SymbolKind::kOther;
    }
  }
  return symbols;
}

}  // namespace tessera::optix7
