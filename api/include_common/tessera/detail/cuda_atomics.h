// CUDA's atomic functions (atomicAdd, atomicCAS, ... and their _block and _system forms) for
// programs compiled as plain C++, shared by both include roots: the OptiX 3 root's
// tessera/cuda_compat.h and the OptiX 7 root's device_atomic_functions.h include it.
//
// Launch indices run on many CPU threads at once, so these are real atomics. They are
// sequentially consistent: on x86-64 that costs nothing over relaxed for read-modify-writes, and
// it keeps lock-style code correct even where a CUDA program forgot its __threadfence(). Each
// returns the value stored at `address` before the operation, as in CUDA.
//
// TESSERA_CUDA_ATOMIC_NOTE(address, op, operand, limit), when the including root defines it
// first, is told of every operation before it happens, by its kind (tessera/detail/atomic_ops.h):
// the OptiX 7 root has a device that holds a copy of device memory combine them, so that the
// host can apply them to its own copy (docs/device_memory.md, "Atomics across devices"). By
// default it is nothing, which the compiler removes.
#ifndef TESSERA_DETAIL_CUDA_ATOMICS_H_
#define TESSERA_DETAIL_CUDA_ATOMICS_H_

#include <stdint.h>
#include <string.h>

#include "tessera/detail/atomic_ops.h"

#ifndef TESSERA_CUDA_ATOMIC_NOTE
#define TESSERA_CUDA_ATOMIC_NOTE(address, op, operand, limit) ((void)0)
#endif

namespace tessera::cuda_atomics {

// CAS loop for read-modify-write operations the __atomic builtins lack (float add, min/max,
// wrapping increment). Returns the value seen before the update, as every CUDA atomic does.
template <typename T, typename Update>
inline T AtomicUpdate(T* address, Update update) {
  T old;
  __atomic_load(address, &old, __ATOMIC_RELAXED);
  T desired;
  do {
    desired = update(old);
  } while (!__atomic_compare_exchange(address, &old, &desired, /*weak=*/true, __ATOMIC_SEQ_CST,
                                      __ATOMIC_RELAXED));
  return old;
}

template <typename T>
inline uint64_t Bits(T value) {
  return atomic_ops::detail::ToBits(value);
}

}  // namespace tessera::cuda_atomics

// ---- Sums -----------------------------------------------------------------------------------
inline int atomicAdd(int* address, int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAdd32, tessera::cuda_atomics::Bits(val),
                           0);
  return __atomic_fetch_add(address, val, __ATOMIC_SEQ_CST);
}
inline unsigned int atomicAdd(unsigned int* address, unsigned int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAdd32, val, 0);
  return __atomic_fetch_add(address, val, __ATOMIC_SEQ_CST);
}
inline unsigned long long atomicAdd(unsigned long long* address, unsigned long long val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAdd64, val, 0);
  return __atomic_fetch_add(address, val, __ATOMIC_SEQ_CST);
}
inline float atomicAdd(float* address, float val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAddFloat,
                           tessera::cuda_atomics::Bits(val), 0);
  return tessera::cuda_atomics::AtomicUpdate(address, [val](float old) { return old + val; });
}
inline double atomicAdd(double* address, double val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAddDouble,
                           tessera::cuda_atomics::Bits(val), 0);
  return tessera::cuda_atomics::AtomicUpdate(address, [val](double old) { return old + val; });
}
// A subtraction is the addition of the negated operand, wrapping alike in two's complement.
inline int atomicSub(int* address, int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAdd32,
                           uint32_t{0} - static_cast<uint32_t>(val), 0);
  return __atomic_fetch_sub(address, val, __ATOMIC_SEQ_CST);
}
inline unsigned int atomicSub(unsigned int* address, unsigned int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kAdd32, 0u - val, 0);
  return __atomic_fetch_sub(address, val, __ATOMIC_SEQ_CST);
}

// ---- Exchanges: no combination across devices (kNone) -----------------------------------------
inline int atomicExch(int* address, int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kNone, 0, 0);
  return __atomic_exchange_n(address, val, __ATOMIC_SEQ_CST);
}
inline unsigned int atomicExch(unsigned int* address, unsigned int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kNone, 0, 0);
  return __atomic_exchange_n(address, val, __ATOMIC_SEQ_CST);
}
inline unsigned long long atomicExch(unsigned long long* address, unsigned long long val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kNone, 0, 0);
  return __atomic_exchange_n(address, val, __ATOMIC_SEQ_CST);
}
inline float atomicExch(float* address, float val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kNone, 0, 0);
  float old;
  __atomic_exchange(address, &val, &old, __ATOMIC_SEQ_CST);
  return old;
}

// ---- Minimum and maximum --------------------------------------------------------------------
#define TESSERA_CUDA_ATOMIC_MIN_MAX_(T, min_op, max_op)                                         \
  inline T atomicMin(T* address, T val) {                                                       \
    TESSERA_CUDA_ATOMIC_NOTE(address, min_op, tessera::cuda_atomics::Bits(val), 0);             \
    return tessera::cuda_atomics::AtomicUpdate(address,                                         \
                                               [val](T old) { return old < val ? old : val; }); \
  }                                                                                             \
  inline T atomicMax(T* address, T val) {                                                       \
    TESSERA_CUDA_ATOMIC_NOTE(address, max_op, tessera::cuda_atomics::Bits(val), 0);             \
    return tessera::cuda_atomics::AtomicUpdate(address,                                         \
                                               [val](T old) { return old > val ? old : val; }); \
  }
TESSERA_CUDA_ATOMIC_MIN_MAX_(int, tessera::atomic_ops::kMinS32, tessera::atomic_ops::kMaxS32)
TESSERA_CUDA_ATOMIC_MIN_MAX_(unsigned int, tessera::atomic_ops::kMinU32,
                             tessera::atomic_ops::kMaxU32)
TESSERA_CUDA_ATOMIC_MIN_MAX_(long long, tessera::atomic_ops::kMinS64, tessera::atomic_ops::kMaxS64)
TESSERA_CUDA_ATOMIC_MIN_MAX_(unsigned long long, tessera::atomic_ops::kMinU64,
                             tessera::atomic_ops::kMaxU64)
#undef TESSERA_CUDA_ATOMIC_MIN_MAX_

// ---- Wrapping counters ----------------------------------------------------------------------
// atomicInc stores (old >= val) ? 0 : old + 1; atomicDec stores (old == 0 || old > val) ? val :
// old - 1. With one limit per address, k calls compose to one function of the count (kInc, kDec).
inline unsigned int atomicInc(unsigned int* address, unsigned int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kInc, 1, val);
  return tessera::cuda_atomics::AtomicUpdate(
      address, [val](unsigned int old) { return old >= val ? 0u : old + 1u; });
}
inline unsigned int atomicDec(unsigned int* address, unsigned int val) {
  TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kDec, 1, val);
  return tessera::cuda_atomics::AtomicUpdate(
      address, [val](unsigned int old) { return (old == 0u || old > val) ? val : old - 1u; });
}

// ---- Compare and swap: no combination across devices (kNone) ----------------------------------
// atomicCAS stores val only if the current value equals compare; either way it returns the
// value it found.
#define TESSERA_CUDA_ATOMIC_CAS_(T)                                                       \
  inline T atomicCAS(T* address, T compare, T val) {                                      \
    TESSERA_CUDA_ATOMIC_NOTE(address, tessera::atomic_ops::kNone, 0, 0);                  \
    __atomic_compare_exchange_n(address, &compare, val, /*weak=*/false, __ATOMIC_SEQ_CST, \
                                __ATOMIC_SEQ_CST);                                        \
    return compare;                                                                       \
  }
TESSERA_CUDA_ATOMIC_CAS_(int)
TESSERA_CUDA_ATOMIC_CAS_(unsigned int)
TESSERA_CUDA_ATOMIC_CAS_(unsigned long long)
TESSERA_CUDA_ATOMIC_CAS_(unsigned short)  // CUDA 10.0+, sm_70
#undef TESSERA_CUDA_ATOMIC_CAS_

// ---- Bitwise --------------------------------------------------------------------------------
#define TESSERA_CUDA_ATOMIC_BITWISE_(T, and_op, or_op, xor_op)                      \
  inline T atomicAnd(T* address, T val) {                                           \
    TESSERA_CUDA_ATOMIC_NOTE(address, and_op, tessera::cuda_atomics::Bits(val), 0); \
    return __atomic_fetch_and(address, val, __ATOMIC_SEQ_CST);                      \
  }                                                                                 \
  inline T atomicOr(T* address, T val) {                                            \
    TESSERA_CUDA_ATOMIC_NOTE(address, or_op, tessera::cuda_atomics::Bits(val), 0);  \
    return __atomic_fetch_or(address, val, __ATOMIC_SEQ_CST);                       \
  }                                                                                 \
  inline T atomicXor(T* address, T val) {                                           \
    TESSERA_CUDA_ATOMIC_NOTE(address, xor_op, tessera::cuda_atomics::Bits(val), 0); \
    return __atomic_fetch_xor(address, val, __ATOMIC_SEQ_CST);                      \
  }
TESSERA_CUDA_ATOMIC_BITWISE_(int, tessera::atomic_ops::kAnd32, tessera::atomic_ops::kOr32,
                             tessera::atomic_ops::kXor32)
TESSERA_CUDA_ATOMIC_BITWISE_(unsigned int, tessera::atomic_ops::kAnd32, tessera::atomic_ops::kOr32,
                             tessera::atomic_ops::kXor32)
TESSERA_CUDA_ATOMIC_BITWISE_(unsigned long long, tessera::atomic_ops::kAnd64,
                             tessera::atomic_ops::kOr64, tessera::atomic_ops::kXor64)
#undef TESSERA_CUDA_ATOMIC_BITWISE_

// The scoped forms (CUDA 8, sm_60): every scope is the whole process here, as for the fences.
#define TESSERA_CUDA_ATOMIC_SCOPES_(name)                   \
  template <typename... A>                                  \
  inline auto name##_block(A... a)->decltype(name(a...)) {  \
    return name(a...);                                      \
  }                                                         \
  template <typename... A>                                  \
  inline auto name##_system(A... a)->decltype(name(a...)) { \
    return name(a...);                                      \
  }
TESSERA_CUDA_ATOMIC_SCOPES_(atomicAdd)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicSub)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicExch)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicMin)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicMax)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicInc)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicDec)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicCAS)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicAnd)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicOr)
TESSERA_CUDA_ATOMIC_SCOPES_(atomicXor)
#undef TESSERA_CUDA_ATOMIC_SCOPES_

#endif  // TESSERA_DETAIL_CUDA_ATOMICS_H_
