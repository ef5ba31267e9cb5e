#include "lanes.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#endif

extern "C" void tessera_lane_start();

namespace tessera::worker {

LaneStack::LaneStack(size_t bytes, unsigned color) {
  // 5 lines apart (an odd count, so that 16 stacks cover 16 distinct sets of the 64 per way).
  color_bytes_ = (size_t{color} * 5 % 64) * 64;
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  size_ = (bytes + page - 1) / page * page;
  mapped_ = size_ + page;
  void* p = mmap(nullptr, mapped_, PROT_READ | PROT_WRITE,
                 MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  mapping_ = static_cast<char*>(p);
  mprotect(mapping_, page, PROT_NONE);  // the guard page; stacks grow down into it
  base_ = mapping_ + page;
  ForgetFrames(size_);
}

LaneStack::~LaneStack() {
  ForgetFrames(size_);  // for whatever is mapped here next
  munmap(mapping_, mapped_);
}

// AddressSanitizer keeps the redzones of frames a stack held when it was abandoned (a lane never
// returns from its loop, an interrupted tile's lanes are jumped out of) in its shadow memory, even
// past munmap; frames laid out there later would be reported as overflowing into them.
void LaneStack::ForgetFrames([[maybe_unused]] size_t top_bytes) {
#if defined(__SANITIZE_ADDRESS__)
  top_bytes = top_bytes < size_ ? top_bytes : size_;
  __asan_unpoison_memory_region(base_ + size_ - top_bytes, top_bytes);
#endif
}

void* LaneStack::Start(void (*entry)(void*), void* arg) {
  // The frames of a tile whose lanes were abandoned (the deep ones of a stack overflow are unwound
  // by its exception).
  ForgetFrames(kFramesOfATile);
  // tessera_lane_switch pops r15, r14, r13, r12, rbx and rbp, then jumps to the address above
  // them: tessera_lane_start, entered with the stack 16-byte aligned, calls r13(r12).
  const auto top = reinterpret_cast<uintptr_t>(base_ + size_ - color_bytes_) & ~uintptr_t{15};
  // The start address sits 8 bytes below a 16-byte boundary, so that the stack is aligned once
  // the switch has taken it.
  auto* slot = reinterpret_cast<uintptr_t*>(top - 24);
  slot[1] = 0;  // above the start address: no caller
  slot[0] = reinterpret_cast<uintptr_t>(&tessera_lane_start);
  uintptr_t* regs = slot - 6;
  regs[0] = 0;                                   // r15
  regs[1] = 0;                                   // r14
  regs[2] = reinterpret_cast<uintptr_t>(entry);  // r13
  regs[3] = reinterpret_cast<uintptr_t>(arg);    // r12
  regs[4] = 0;                                   // rbx
  regs[5] = 0;                                   // rbp
  return regs;
}

}  // namespace tessera::worker
