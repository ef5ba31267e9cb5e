// The floating-point mode of the threads that run programs (docs/fast_math.md): denormals flushed
// to zero (FTZ) and read as zero (DAZ) for launches of fast-math modules or contexts, IEEE
// denormals otherwise. Tracing threads are shared (a TBB arena, the host's own thread for an
// in-process device), so a launch sets the mode for each batch of tiles and puts back what the
// thread had: default launches then compute the same bits on every machine and after any
// fast-math launch.
#ifndef TESSERA_WORKER_CORE_FLOAT_MODE_H_
#define TESSERA_WORKER_CORE_FLOAT_MODE_H_

#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

namespace tessera::worker {

#if defined(__x86_64__) || defined(__i386__)
// MXCSR bit 15 (flush results to zero) and bit 6 (denormal inputs are zero).
inline constexpr uint64_t kFlushDenormalBits = 0x8040u;
// MXCSR bits 0-5: sticky exception flags that arithmetic sets, not part of the mode.
inline constexpr uint64_t kFloatStatusBits = 0x3Fu;
// The calling thread's floating-point control word.
inline uint64_t FloatMode() { return _mm_getcsr(); }
inline void SetFloatMode(uint64_t mode) { _mm_setcsr(static_cast<unsigned>(mode)); }
#elif defined(__aarch64__)
// FPCR.FZ (bit 24) flushes denormal inputs and results alike.
inline constexpr uint64_t kFlushDenormalBits = uint64_t{1} << 24;
inline constexpr uint64_t kFloatStatusBits = 0;  // in FPSR, not FPCR
inline uint64_t FloatMode() {
  uint64_t mode;
  asm volatile("mrs %0, fpcr" : "=r"(mode));
  return mode;
}
inline void SetFloatMode(uint64_t mode) { asm volatile("msr fpcr, %0" : : "r"(mode)); }
#else
#error \
    "worker/core/float_mode.h: no FTZ/DAZ control for this architecture (x86 MXCSR, AArch64 FPCR)"
#endif

// Whether the calling thread flushes denormals.
inline bool FlushesDenormals() { return (FloatMode() & kFlushDenormalBits) == kFlushDenormalBits; }

// For its lifetime the calling thread flushes denormals or not, as `flush` says, whatever it did
// before; then it gets its old mode back. Rounding and exception masks are left alone.
class ScopedFloatMode {
 public:
  explicit ScopedFloatMode(bool flush) : saved_(FloatMode()) {
    const uint64_t wanted = (saved_ & ~kFlushDenormalBits) | (flush ? kFlushDenormalBits : 0u);
    if (wanted != saved_) SetFloatMode(wanted);
  }
  ~ScopedFloatMode() {
    if (FloatMode() != saved_) SetFloatMode(saved_);
  }
  ScopedFloatMode(const ScopedFloatMode&) = delete;
  ScopedFloatMode& operator=(const ScopedFloatMode&) = delete;

 private:
  const uint64_t saved_;
};

// Keeps the calling thread's whole control word across a scope that may change it: a module
// loaded with dlopen whose static constructors set FTZ/DAZ (GCC and Clang link crtfastmath.o into
// shared libraries built with -ffast-math, whose constructor does), which must not change the
// mode of the thread that happened to load it.
class PreservedFloatMode {
 public:
  PreservedFloatMode() : saved_(FloatMode()) {}
  ~PreservedFloatMode() {
    if (FloatMode() != saved_) SetFloatMode(saved_);
  }
  PreservedFloatMode(const PreservedFloatMode&) = delete;
  PreservedFloatMode& operator=(const PreservedFloatMode&) = delete;

 private:
  const uint64_t saved_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_FLOAT_MODE_H_
