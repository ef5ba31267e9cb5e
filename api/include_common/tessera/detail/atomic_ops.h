// CUDA's atomic operations as Tessera carries them across devices (docs/device_memory.md,
// "Atomics across devices"). A device whose memory is a copy of the host's combines what its
// programs' atomics did to each address into one operation of the same kind (a sum for adds, the
// least operand for atomicMin, ...), and the host applies that operation to its own copy, so
// that every device's atomics reach the value one GPU would have made, whatever the device count.
//
// Shared by the programs' atomic functions (tessera/detail/cuda_atomics.h, which name the kind),
// the device that combines them (worker/core/optix7_atomics.cc) and the host that applies them
// (api/optix7/launch_target.cc): one definition of what each kind means on each side.
#ifndef TESSERA_DETAIL_ATOMIC_OPS_H_
#define TESSERA_DETAIL_ATOMIC_OPS_H_

#include <stdint.h>
#include <string.h>

namespace tessera::atomic_ops {

// Kinds of atomics, by how they combine. The values are module ABI and wire values
// (v1.DeviceMemoryAtomic.op): never renumbered.
enum Op : uint32_t {
  // No combination: atomicExch and atomicCAS (whose results depend on the order of operations),
  // or one address that atomics of different kinds (or atomicInc/Dec with different limits)
  // reached. The address's bytes travel as any write does: the last writer wins.
  kNone = 0,
  // Sums. int and unsigned int wrap alike in two's complement, so they share a kind; atomicSub
  // adds the negated operand.
  kAdd32 = 1,
  kAdd64 = 2,
  kAddFloat = 3,
  kAddDouble = 4,
  kMinS32 = 5,
  kMinU32 = 6,
  kMinS64 = 7,
  kMinU64 = 8,
  kMaxS32 = 9,
  kMaxU32 = 10,
  kMaxS64 = 11,
  kMaxU64 = 12,
  kAnd32 = 13,
  kAnd64 = 14,
  kOr32 = 15,
  kOr64 = 16,
  kXor32 = 17,
  kXor64 = 18,
  // atomicInc and atomicDec with one limit: the operand counts the calls. Each call applies the
  // same function of the old value, so k calls on one device and j on another compose to k + j
  // calls, in any order.
  kInc = 19,
  kDec = 20,
  kOpCount = 21
};

// Bytes an operation of kind `op` changes (0 for kNone, and for values that name no kind).
inline uint32_t SizeOf(uint32_t op) {
  switch (op) {
    case kAdd32:
    case kAddFloat:
    case kMinS32:
    case kMinU32:
    case kMaxS32:
    case kMaxU32:
    case kAnd32:
    case kOr32:
    case kXor32:
    case kInc:
    case kDec:
      return 4;
    case kAdd64:
    case kAddDouble:
    case kMinS64:
    case kMinU64:
    case kMaxS64:
    case kMaxU64:
    case kAnd64:
    case kOr64:
    case kXor64:
      return 8;
    default:
      return 0;
  }
}

namespace detail {

template <typename T>
inline T FromBits(uint64_t bits) {
  T value;
  if constexpr (sizeof(T) == 4) {
    const uint32_t low = static_cast<uint32_t>(bits);
    memcpy(&value, &low, sizeof value);
  } else {
    memcpy(&value, &bits, sizeof value);
  }
  return value;
}

template <typename T>
inline uint64_t ToBits(T value) {
  if constexpr (sizeof(T) == 4) {
    uint32_t bits;
    memcpy(&bits, &value, sizeof bits);
    return bits;
  } else {
    uint64_t bits;
    memcpy(&bits, &value, sizeof bits);
    return bits;
  }
}

template <typename T>
inline T Min(T a, T b) {
  return b < a ? b : a;
}
template <typename T>
inline T Max(T a, T b) {
  return a < b ? b : a;
}

// CUDA's atomicInc (old >= limit ? 0 : old + 1) `count` times: a value in [0, limit] cycles
// through limit + 1 values; one above the limit goes to 0 first.
inline uint32_t IncTimes(uint32_t old, uint64_t count, uint32_t limit) {
  if (count == 0) return old;
  if (old > limit) {
    old = 0;
    --count;
  }
  const uint64_t cycle = uint64_t{limit} + 1;
  return static_cast<uint32_t>((old + count % cycle) % cycle);
}

// CUDA's atomicDec ((old == 0 || old > limit) ? limit : old - 1) `count` times.
inline uint32_t DecTimes(uint32_t old, uint64_t count, uint32_t limit) {
  if (count == 0) return old;
  if (old > limit) {
    old = limit;
    --count;
  }
  const uint64_t cycle = uint64_t{limit} + 1;
  return static_cast<uint32_t>((old + cycle - count % cycle) % cycle);
}

}  // namespace detail

// The operand of one operation of kind `op` that does what `first` and then `second` did (or the
// other way round: every kind but kNone is commutative). Operands are the bits of the value,
// 32-bit ones in the low half.
inline uint64_t Combine(uint32_t op, uint64_t first, uint64_t second) {
  using detail::FromBits;
  using detail::ToBits;
  switch (op) {
    case kAdd32:
      return static_cast<uint32_t>(first + second);
    case kAdd64:
    case kInc:
    case kDec:
      return first + second;
    case kAddFloat:
      return ToBits(FromBits<float>(first) + FromBits<float>(second));
    case kAddDouble:
      return ToBits(FromBits<double>(first) + FromBits<double>(second));
    case kMinS32:
      return ToBits(detail::Min(FromBits<int32_t>(first), FromBits<int32_t>(second)));
    case kMinU32:
      return ToBits(detail::Min(FromBits<uint32_t>(first), FromBits<uint32_t>(second)));
    case kMinS64:
      return ToBits(detail::Min(FromBits<int64_t>(first), FromBits<int64_t>(second)));
    case kMinU64:
      return detail::Min(first, second);
    case kMaxS32:
      return ToBits(detail::Max(FromBits<int32_t>(first), FromBits<int32_t>(second)));
    case kMaxU32:
      return ToBits(detail::Max(FromBits<uint32_t>(first), FromBits<uint32_t>(second)));
    case kMaxS64:
      return ToBits(detail::Max(FromBits<int64_t>(first), FromBits<int64_t>(second)));
    case kMaxU64:
      return detail::Max(first, second);
    case kAnd32:
    case kAnd64:
      return first & second;
    case kOr32:
    case kOr64:
      return first | second;
    case kXor32:
    case kXor64:
      return first ^ second;
    default:
      return 0;
  }
}

namespace detail {

// A CAS loop: `update` of the value at `address`, atomically (other threads, e.g. an in-process
// device's programs, may update it at the same time).
template <typename T, typename Update>
inline void AtomicUpdate(void* address, Update update) {
  T* p = static_cast<T*>(address);
  T old;
  __atomic_load(p, &old, __ATOMIC_RELAXED);
  T desired;
  do {
    desired = update(old);
  } while (!__atomic_compare_exchange(p, &old, &desired, /*weak=*/true, __ATOMIC_SEQ_CST,
                                      __ATOMIC_RELAXED));
}

template <typename T>
inline void UpdateWith(void* address, uint32_t op, uint64_t operand) {
  AtomicUpdate<T>(address,
                  [op, operand](T old) { return FromBits<T>(Combine(op, ToBits(old), operand)); });
}

}  // namespace detail

// Applies an operation of kind `op` with `operand` (and `limit`, for kInc and kDec) to the value
// at `address`, atomically. Returns false for kNone and values that name no kind.
inline bool Apply(uint32_t op, void* address, uint64_t operand, uint32_t limit) {
  switch (op) {
    case kAdd32:
    case kMinS32:
    case kMinU32:
    case kMaxS32:
    case kMaxU32:
    case kAnd32:
    case kOr32:
    case kXor32:
      detail::UpdateWith<uint32_t>(address, op, operand);
      return true;
    case kAdd64:
    case kMinS64:
    case kMinU64:
    case kMaxS64:
    case kMaxU64:
    case kAnd64:
    case kOr64:
    case kXor64:
      detail::UpdateWith<uint64_t>(address, op, operand);
      return true;
    case kAddFloat:
      detail::UpdateWith<float>(address, op, operand);
      return true;
    case kAddDouble:
      detail::UpdateWith<double>(address, op, operand);
      return true;
    case kInc:
      detail::AtomicUpdate<uint32_t>(address, [operand, limit](uint32_t old) {
        return detail::IncTimes(old, operand, limit);
      });
      return true;
    case kDec:
      detail::AtomicUpdate<uint32_t>(address, [operand, limit](uint32_t old) {
        return detail::DecTimes(old, operand, limit);
      });
      return true;
    default:
      return false;
  }
}

}  // namespace tessera::atomic_ops

#endif  // TESSERA_DETAIL_ATOMIC_OPS_H_
