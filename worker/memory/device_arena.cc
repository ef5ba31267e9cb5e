#include "device_arena.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace tessera::memory {
namespace {

std::string Range(uintptr_t address, size_t length) {
  return absl::StrFormat("[0x%x, 0x%x)", address, address + length);
}

}  // namespace

size_t DeviceArena::PageSize() {
  static const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  return page;
}

absl::StatusOr<std::unique_ptr<DeviceArena>> DeviceArena::Reserve(uintptr_t base, size_t size) {
  const size_t page = PageSize();
  if (size == 0 || base % page != 0 || size % page != 0 || base + size < base) {
    return absl::InvalidArgumentError(absl::StrCat("device memory range ", Range(base, size),
                                                   " is empty, wraps or is not page aligned"));
  }
  // MAP_FIXED_NOREPLACE fails rather than unmap what is there; kernels before 4.17 ignore the flag
  // and treat the address as a hint, which the check below catches.
  void* at = mmap(reinterpret_cast<void*>(base), size, PROT_NONE,
                  MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE | MAP_FIXED_NOREPLACE, -1, 0);
  if (at == MAP_FAILED) {
    const int error = errno;
    return absl::FailedPreconditionError(
        absl::StrCat("cannot reserve device memory at ", Range(base, size), ": ",
                     error == EEXIST ? "something of this process is already mapped there"
                                     : std::strerror(error),
                     " (set TESSERA_DEVICE_MEMORY_BASE to a free range on every machine)"));
  }
  if (reinterpret_cast<uintptr_t>(at) != base) {
    munmap(at, size);
    return absl::FailedPreconditionError(absl::StrCat(
        "cannot reserve device memory at ", Range(base, size),
        ": the kernel placed it elsewhere (set TESSERA_DEVICE_MEMORY_BASE to a free range)"));
  }
  return std::unique_ptr<DeviceArena>(new DeviceArena(base, size));
}

DeviceArena::~DeviceArena() { munmap(reinterpret_cast<void*>(base_), size_); }

bool DeviceArena::Contains(uintptr_t address, size_t length) const {
  if (address < base_ || address - base_ > size_) return false;
  return length <= size_ - (address - base_) && (length > 0 || address < base_ + size_);
}

absl::Status DeviceArena::Commit(uintptr_t address, size_t length) {
  if (!Contains(address, length)) {
    return absl::OutOfRangeError(absl::StrCat("device memory ", Range(address, length),
                                              " is outside the arena ", Range(base_, size_)));
  }
  if (length == 0) return absl::OkStatus();
  const size_t page = PageSize();
  const uintptr_t first = address / page * page;
  const uintptr_t end = (address + length + page - 1) / page * page;
  if (mprotect(reinterpret_cast<void*>(first), end - first, PROT_READ | PROT_WRITE) != 0) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "cannot commit device memory ", Range(first, end - first), ": ", std::strerror(errno)));
  }
  return absl::OkStatus();
}

absl::Status DeviceArena::Release(uintptr_t address, size_t length) {
  if (!Contains(address, length)) {
    return absl::OutOfRangeError(absl::StrCat("device memory ", Range(address, length),
                                              " is outside the arena ", Range(base_, size_)));
  }
  const size_t page = PageSize();
  const uintptr_t first = (address + page - 1) / page * page;
  const uintptr_t end = (address + length) / page * page;
  if (end <= first) return absl::OkStatus();
  // A fresh mapping over the pages: their memory goes back to the system and they read as zeros
  // when committed again, as cudaMalloc'ed memory of a new allocation may (CUDA promises nothing).
  void* at = mmap(reinterpret_cast<void*>(first), end - first, PROT_NONE,
                  MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE | MAP_FIXED, -1, 0);
  if (at == MAP_FAILED) {
    return absl::InternalError(absl::StrCat("cannot release device memory ",
                                            Range(first, end - first), ": ", std::strerror(errno)));
  }
  return absl::OkStatus();
}

namespace {

absl::StatusOr<uintptr_t> ArenaBase() {
  const char* text = std::getenv("TESSERA_DEVICE_MEMORY_BASE");
  if (text == nullptr || *text == '\0') return kDefaultArenaBase;
  char* end = nullptr;
  const unsigned long long base = std::strtoull(text, &end, 16);
  if (end == text || *end != '\0') {
    return absl::InvalidArgumentError(
        absl::StrCat("TESSERA_DEVICE_MEMORY_BASE='", text, "' is not a hexadecimal address"));
  }
  return static_cast<uintptr_t>(base);
}

}  // namespace

absl::StatusOr<DeviceArena*> ProcessArena() {
  static absl::StatusOr<DeviceArena*>* const arena = [] {
    auto* result = new absl::StatusOr<DeviceArena*>(nullptr);
    absl::StatusOr<uintptr_t> base = ArenaBase();
    if (!base.ok()) {
      *result = base.status();
      return result;
    }
    absl::StatusOr<std::unique_ptr<DeviceArena>> reserved =
        DeviceArena::Reserve(*base, kDefaultArenaSize);
    if (!reserved.ok()) {
      *result = reserved.status();
    } else {
      *result = reserved->release();  // lives as long as the process
    }
    return result;
  }();
  return *arena;
}

}  // namespace tessera::memory
