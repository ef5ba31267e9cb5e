// What every launch index of the counting program (atomics.cu, __raygen__count) does to the
// counters, with CUDA's atomic functions: the program runs it on its devices, and the host
// (main.cc) runs the same code on one thread, with the same functions (tessera/detail/
// cuda_atomics.h), to know the totals one GPU would reach. Only the combinable kinds are here:
// their totals do not depend on order or device count.
#ifndef TESSERA_TESTS_OPTIX7_ATOMICS_COUNTERS_H_
#define TESSERA_TESTS_OPTIX7_ATOMICS_COUNTERS_H_

constexpr unsigned kBins = 37;

struct Counters {
  unsigned count;  // +1 per index
  unsigned histogram[kBins];
  int signed_sum;  // (index % 7) - 3 per index
  unsigned down;   // atomicSub 3 per index, from near 0: wraps
  int down_signed;
  unsigned long long wide_sum;  // 2^33 + index per index: past 32 bits
  float float_sum;              // 0.5f per index: exact below 2^24
  double double_sum;            // 0.25 per index
  int min_s, max_s;
  unsigned min_u, max_u;
  long long min_ll, max_ll;
  unsigned long long min_ull, max_ull;
  unsigned or_bits[4];
  unsigned and_bits;
  unsigned xor_bits;
  int xor_signed;
  unsigned long long or_wide, and_wide, xor_wide;
  unsigned ring;       // atomicInc(…, 9): wraps at 10
  unsigned ring_down;  // atomicDec(…, 6)
  unsigned scoped;     // atomicAdd_block and atomicAdd_system, 1 each
};

// A value per index that reaches both signs and spans the range.
inline unsigned Mix(unsigned i) {
  unsigned h = i * 2654435761u;
  h ^= h >> 15;
  h *= 2246822519u;
  return h ^ (h >> 13);
}

inline void CountIndex(Counters* c, unsigned i) {
  atomicAdd(&c->count, 1u);
  atomicAdd(&c->histogram[i % kBins], 1u);
  atomicAdd(&c->signed_sum, static_cast<int>(i % 7) - 3);
  atomicSub(&c->down, 3u);
  atomicSub(&c->down_signed, static_cast<int>(i % 5));
  atomicAdd(&c->wide_sum, (1ull << 33) + i);
  atomicAdd(&c->float_sum, 0.5f);
  atomicAdd(&c->double_sum, 0.25);
  const unsigned m = Mix(i);
  atomicMin(&c->min_s, static_cast<int>(m));
  atomicMax(&c->max_s, static_cast<int>(m));
  atomicMin(&c->min_u, m | 1u);
  atomicMax(&c->max_u, m >> 1);
  // The shift on the unsigned bits (a negative value's left shift is undefined in C++17).
  const long long wide = static_cast<long long>(
      (static_cast<unsigned long long>(static_cast<long long>(static_cast<int>(m))) << 20) ^ i);
  atomicMin(&c->min_ll, wide);
  atomicMax(&c->max_ll, wide);
  atomicMin(&c->min_ull, static_cast<unsigned long long>(m) << 30 | 7u);
  atomicMax(&c->max_ull, static_cast<unsigned long long>(m) << 31);
  atomicOr(&c->or_bits[(i / 32) % 4], 1u << (i % 32));
  atomicAnd(&c->and_bits, ~(1u << (m % 29)));
  atomicXor(&c->xor_bits, m);
  atomicXor(&c->xor_signed, static_cast<int>(i));
  atomicOr(&c->or_wide, 1ull << (m % 61));
  atomicAnd(&c->and_wide, ~(1ull << (i % 64)) | (1ull << 63));
  atomicXor(&c->xor_wide, static_cast<unsigned long long>(m) << 17);
  atomicInc(&c->ring, 9u);
  atomicDec(&c->ring_down, 6u);
  atomicAdd_block(&c->scoped, 1u);
  atomicAdd_system(&c->scoped, 1u);
}

// Where a launch starts: none of the counters at its identity, so that a device's operation that
// left out the host's value would show.
inline Counters InitialCounters() {
  Counters c = {};
  c.count = 1000;
  for (unsigned b = 0; b < kBins; ++b) c.histogram[b] = b;
  c.signed_sum = -5;
  c.down = 7;
  c.down_signed = 11;
  c.wide_sum = 3;
  c.float_sum = 1.5f;
  c.double_sum = -2.0;
  c.min_s = 1 << 30;
  c.max_s = -(1 << 30);
  c.min_u = 0xF0000000u;
  c.max_u = 5;
  c.min_ll = 1ll << 40;
  c.max_ll = -(1ll << 40);
  c.min_ull = ~0ull >> 1;
  c.max_ull = 12;
  c.or_bits[0] = 0x80000000u;
  c.and_bits = 0xFFFFFFFFu;
  c.xor_bits = 0x12345678u;
  c.xor_signed = -1;
  c.or_wide = 1ull << 62;
  c.and_wide = ~0ull;
  c.xor_wide = 0xABCDEF;
  c.ring = 20;  // above the limit: the first atomicInc goes to 0
  c.ring_down = 3;
  return c;
}

#endif  // TESSERA_TESTS_OPTIX7_ATOMICS_COUNTERS_H_
