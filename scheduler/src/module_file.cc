#include "tessera/scheduler/module_file.h"

#include <elf.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace tessera::scheduler {
namespace {

bool ReadAt(int fd, void* out, size_t bytes, uint64_t offset) {
  return pread(fd, out, bytes, static_cast<off_t>(offset)) == static_cast<ssize_t>(bytes);
}

absl::Status CutShort(const std::string& path, uint64_t needed, uint64_t size) {
  return absl::InvalidArgumentError(absl::StrCat(path, " is cut short: it has ", size,
                                                 " bytes and its ELF headers describe ", needed));
}

template <typename T>
bool ReadStruct(absl::string_view bytes, uint64_t offset, T* out) {
  if (offset > bytes.size() || bytes.size() - offset < sizeof(T)) return false;
  std::memcpy(out, bytes.data() + offset, sizeof(T));
  return true;
}

// Whether [offset, offset + count * size) lies within `bytes`, without overflow.
bool InBounds(absl::string_view bytes, uint64_t offset, uint64_t count, uint64_t size) {
  if (offset > bytes.size()) return false;
  return size == 0 || count <= (bytes.size() - offset) / size;
}

#if defined(__x86_64__)
constexpr unsigned kMachine = EM_X86_64;
#elif defined(__aarch64__)
constexpr unsigned kMachine = EM_AARCH64;
#else
constexpr unsigned kMachine = EM_NONE;  // not checked
#endif

}  // namespace

absl::Status CheckModuleBytes(absl::string_view bytes, absl::string_view function,
                              bool require_init) {
  Elf64_Ehdr header{};
  if (!ReadStruct(bytes, 0, &header) || std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0) {
    return absl::InvalidArgumentError("it is not an ELF shared object");
  }
  if (header.e_ident[EI_CLASS] != ELFCLASS64 || header.e_type != ET_DYN ||
      (kMachine != EM_NONE && header.e_machine != kMachine)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "it is not a 64-bit shared object for this machine (ELF class ", header.e_ident[EI_CLASS],
        ", type ", header.e_type, ", machine ", header.e_machine, ")"));
  }
  if (header.e_shoff == 0 || header.e_shnum == 0) return absl::OkStatus();
  if (header.e_shentsize != sizeof(Elf64_Shdr) ||
      !InBounds(bytes, header.e_shoff, header.e_shnum, sizeof(Elf64_Shdr))) {
    return absl::InvalidArgumentError(absl::StrCat("its section headers reach past its end (",
                                                   bytes.size(), " bytes): is it cut short?"));
  }
  auto section = [&](unsigned i) {
    Elf64_Shdr s{};
    ReadStruct(bytes, header.e_shoff + uint64_t{i} * sizeof(Elf64_Shdr), &s);
    return s;
  };
  bool has_function = false;
  bool has_init = false;
  bool has_dynsym = false;
  for (unsigned i = 0; i < header.e_shnum; ++i) {
    const Elf64_Shdr symbols = section(i);
    if (symbols.sh_type != SHT_DYNSYM) continue;
    has_dynsym = true;
    if (symbols.sh_entsize != sizeof(Elf64_Sym) || symbols.sh_link >= header.e_shnum) {
      return absl::InvalidArgumentError("its dynamic symbol table is malformed");
    }
    const Elf64_Shdr strings = section(symbols.sh_link);
    if (!InBounds(bytes, symbols.sh_offset, 1, symbols.sh_size) ||
        !InBounds(bytes, strings.sh_offset, 1, strings.sh_size)) {
      return absl::InvalidArgumentError(
          absl::StrCat("its dynamic symbol table reaches past its end (", bytes.size(), " bytes)"));
    }
    const absl::string_view names = bytes.substr(strings.sh_offset, strings.sh_size);
    for (uint64_t j = 0; j < symbols.sh_size / sizeof(Elf64_Sym); ++j) {
      Elf64_Sym sym{};
      ReadStruct(bytes, symbols.sh_offset + j * sizeof(Elf64_Sym), &sym);
      if (sym.st_shndx == SHN_UNDEF || ELF64_ST_TYPE(sym.st_info) != STT_FUNC ||
          sym.st_name >= names.size()) {
        continue;
      }
      absl::string_view name = names.substr(sym.st_name);
      name = name.substr(0, name.find('\0'));
      if (name == function && ELF64_ST_BIND(sym.st_info) == STB_GLOBAL) has_function = true;
      if (name == "tessera_module_init") has_init = true;
    }
  }
  if (!has_dynsym) return absl::InvalidArgumentError("it has no dynamic symbol table");
  if (require_init && !has_init) {
    return absl::FailedPreconditionError(
        "it was not built against tessera/device.h (no tessera_module_init)");
  }
  if (!has_function) {
    return absl::NotFoundError(absl::StrCat("it defines no function '", function, "'"));
  }
  return absl::OkStatus();
}

absl::Status CheckModuleFileComplete(const std::string& path) {
  // O_NONBLOCK: a FIFO under that name must not block; dlopen then reports it.
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return absl::OkStatus();
  struct stat st {};
  Elf64_Ehdr header{};
  absl::Status status;
  if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ReadAt(fd, &header, sizeof(header), 0) &&
      std::memcmp(header.e_ident, ELFMAG, SELFMAG) == 0 && header.e_ident[EI_CLASS] == ELFCLASS64 &&
      header.e_phentsize == sizeof(Elf64_Phdr)) {
    const uint64_t size = static_cast<uint64_t>(st.st_size);
    const uint64_t headers_end = header.e_phoff + uint64_t{header.e_phnum} * sizeof(Elf64_Phdr);
    if (header.e_phoff > size || headers_end > size) {
      status = CutShort(path, headers_end, size);
    }
    for (unsigned i = 0; status.ok() && i < header.e_phnum; ++i) {
      Elf64_Phdr segment{};
      if (!ReadAt(fd, &segment, sizeof(segment), header.e_phoff + i * sizeof(Elf64_Phdr))) break;
      if (segment.p_type != PT_LOAD) continue;
      const uint64_t end = segment.p_offset + segment.p_filesz;
      if (end < segment.p_offset || end > size) status = CutShort(path, end, size);
    }
  }
  close(fd);
  return status;
}

absl::string_view FindElfSection(absl::string_view bytes, absl::string_view name) {
  Elf64_Ehdr header{};
  if (!ReadStruct(bytes, 0, &header) || std::memcmp(header.e_ident, ELFMAG, SELFMAG) != 0 ||
      header.e_ident[EI_CLASS] != ELFCLASS64 || header.e_shentsize != sizeof(Elf64_Shdr) ||
      header.e_shstrndx >= header.e_shnum ||
      !InBounds(bytes, header.e_shoff, header.e_shnum, sizeof(Elf64_Shdr))) {
    return {};
  }
  auto section = [&](unsigned i) {
    Elf64_Shdr s{};
    ReadStruct(bytes, header.e_shoff + uint64_t{i} * sizeof(Elf64_Shdr), &s);
    return s;
  };
  const Elf64_Shdr names = section(header.e_shstrndx);
  if (!InBounds(bytes, names.sh_offset, names.sh_size, 1)) return {};
  const absl::string_view table = bytes.substr(names.sh_offset, names.sh_size);
  for (unsigned i = 0; i < header.e_shnum; ++i) {
    const Elf64_Shdr s = section(i);
    if (s.sh_name >= table.size() || s.sh_type == SHT_NOBITS) continue;
    const absl::string_view rest = table.substr(s.sh_name);
    if (rest.substr(0, rest.find('\0')) != name) continue;
    if (!InBounds(bytes, s.sh_offset, s.sh_size, 1)) return {};
    return bytes.substr(s.sh_offset, s.sh_size);
  }
  return {};
}

}  // namespace tessera::scheduler
