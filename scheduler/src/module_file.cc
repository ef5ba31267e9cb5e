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

}  // namespace

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

}  // namespace tessera::scheduler
