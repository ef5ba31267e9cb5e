// Programs of the atomics test (main.cc): counting from every launch index, CUDA's documented
// results of every atomic function, an append buffer, and a benchmark loop.
#include <optix.h>

#include "params.h"

extern "C" {
__constant__ Params params;
}

static __device__ unsigned LaunchIndex() {
  const uint3 i = optixGetLaunchIndex();
  const uint3 d = optixGetLaunchDimensions();
  return i.x + i.y * d.x;
}

extern "C" __global__ void __raygen__count() { CountIndex(params.counters, LaunchIndex()); }

// Appends the launch index at the slot its atomicAdd returned. Slots are unique within a device;
// across devices they are not (docs/device_memory.md): the host checks only the count.
extern "C" __global__ void __raygen__append() {
  const unsigned slot = atomicAdd(params.append, 1u);
  if (slot < params.slot_count) params.slots[slot] = LaunchIndex() + 1;
}

extern "C" __global__ void __raygen__bench() {
  const unsigned i = LaunchIndex();
  for (unsigned k = 0; k < params.bench_adds; ++k) {
    atomicAdd(&params.bench[(i + k) % params.bench_bins], 1u);
  }
}

// One launch index: each check's value in order, for the host to compare with CUDA's documented
// results (main.cc, kSemantics). The operands are the program's own variables; on a device that
// notes atomics these are noted and then dropped (not device memory).
static __device__ void See(unsigned long long check, unsigned long long value) {
  const unsigned n = (*params.seen_count)++;
  if (n < kMaxSeen) params.seen[n] = Seen{check, value};
}

extern "C" __global__ void __raygen__semantics() {
  int i = 10;
  See(1, atomicAdd(&i, 5));  // returns the old value
  See(2, i);
  unsigned u = 0xFFFFFFFFu;
  See(3, atomicAdd(&u, 2u));
  See(4, u);  // wraps
  unsigned long long ull = 1ull << 40;
  See(5, atomicAdd(&ull, 1ull << 33));
  See(6, ull);
  float f = 2.5f;
  See(7, __float_as_uint(atomicAdd(&f, 0.5f)));
  See(8, __float_as_uint(f));
  double d = 1.0;
  See(9, atomicAdd(&d, 1.0) == 1.0);
  See(10, d == 2.0);
  i = 3;
  See(11, atomicSub(&i, 5));
  See(12, static_cast<unsigned long long>(static_cast<long long>(i)));
  u = 1;
  See(13, atomicSub(&u, 2u));
  See(14, u);
  i = 4;
  See(15, atomicExch(&i, -9));
  See(16, static_cast<unsigned long long>(static_cast<long long>(i)));
  u = 6;
  See(17, atomicExch(&u, 8u));
  See(18, u);
  ull = 1ull << 50;
  See(19, atomicExch(&ull, 3ull));
  See(20, ull);
  f = 1.25f;
  See(21, __float_as_uint(atomicExch(&f, -4.0f)));
  See(22, __float_as_uint(f));
  i = -3;
  See(23, atomicMin(&i, -7));
  See(24, atomicMin(&i, 4));  // larger: stays
  See(25, static_cast<unsigned long long>(static_cast<long long>(i)));
  i = -3;
  See(26, atomicMax(&i, 2));
  See(27, i);
  u = 5;
  See(28, atomicMax(&u, 0x80000000u));  // unsigned comparison
  See(29, u);
  See(30, atomicMin(&u, 7u));
  See(31, u);
  long long ll = -1;
  See(32, atomicMin(&ll, -(1ll << 50)));
  See(33, static_cast<unsigned long long>(ll));
  See(34, atomicMax(&ll, 1ll << 45));
  See(35, static_cast<unsigned long long>(ll));
  ull = 1ull << 63;
  See(36, atomicMin(&ull, 5ull));
  See(37, atomicMax(&ull, 1ull << 62));
  See(38, ull);
  u = 9;
  See(39, atomicInc(&u, 9u));  // old >= val: 0
  See(40, u);
  See(41, atomicInc(&u, 9u));
  See(42, u);
  u = 20;
  See(43, atomicInc(&u, 9u));  // above the limit: 0
  See(44, u);
  u = 0;
  See(45, atomicDec(&u, 6u));  // old == 0: val
  See(46, u);
  u = 3;
  See(47, atomicDec(&u, 6u));
  See(48, u);
  u = 20;
  See(49, atomicDec(&u, 6u));  // old > val: val
  See(50, u);
  i = 5;
  See(51, atomicCAS(&i, 4, 9));  // no match: unchanged
  See(52, i);
  See(53, atomicCAS(&i, 5, 9));  // match: swapped
  See(54, i);
  u = 1;
  See(55, atomicCAS(&u, 1u, 2u));
  See(56, u);
  ull = 1ull << 40;
  See(57, atomicCAS(&ull, 1ull << 40, 7ull));
  See(58, ull);
  unsigned short s = 7;
  See(59, atomicCAS(&s, static_cast<unsigned short>(7), static_cast<unsigned short>(300)));
  See(60, s);
  See(61, atomicCAS(&s, static_cast<unsigned short>(7), static_cast<unsigned short>(1)));
  See(62, s);
  u = 0xF0F0u;
  See(63, atomicAnd(&u, 0xFF00u));
  See(64, u);
  See(65, atomicOr(&u, 0x000Fu));
  See(66, u);
  See(67, atomicXor(&u, 0xFFFFu));
  See(68, u);
  i = -1;
  See(69, static_cast<unsigned long long>(static_cast<long long>(atomicAnd(&i, 0x70))));
  See(70, i);
  See(71, atomicOr(&i, -256));
  See(72, static_cast<unsigned long long>(static_cast<long long>(i)));
  See(73, atomicXor(&i, -1));
  See(74, i);
  ull = 0xFFFF000000000000ull;
  See(75, atomicAnd(&ull, 0x0FF0000000000000ull));
  See(76, atomicOr(&ull, 1ull));
  See(77, atomicXor(&ull, 0x0FF0000000000001ull));
  See(78, ull);
  u = 3;
  See(79, atomicAdd_block(&u, 2u));
  See(80, atomicAdd_system(&u, 3u));
  See(81, atomicCAS_block(&u, 8u, 1u));
  See(82, atomicExch_system(&u, 4u));
  See(83, atomicMax_block(&u, 6u));
  See(84, atomicInc_system(&u, 6u));
  See(85, u);
}
