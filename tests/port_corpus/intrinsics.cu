// Every intrinsic and math helper of intrinsic_cases.h in a program, and the atomics CUDA has on
// every type, shared by all launch indices.
#include <optix.h>

#include "intrinsic_cases.h"

using namespace optix;

rtDeclareVariable(uint2, index, rtLaunchIndex, );
rtDeclareVariable(uint2, launch_dim, rtLaunchDim, );
rtBuffer<float> cases;
rtBuffer<int> atomic_int;                 // add, sub, min, max, exch, cas, and, or, xor
rtBuffer<unsigned int> atomic_uint;       // add, sub, min, max, inc, dec, and, or, xor
rtBuffer<unsigned long long> atomic_ull;  // add, min, max, exch, cas, and, or, xor
rtBuffer<float> atomic_float;             // add, exch
rtBuffer<double> atomic_double;           // add
rtBuffer<unsigned int> hashes;            // tea<4> of each launch index, as sample_common.h has it
rtBuffer<long long> clocks;               // clock() and clock64() as launch index 0 read them

#include "sample_common.h"

RT_PROGRAM void run_cases() {
  const unsigned i = index.y * launch_dim.x + index.x;
  if (i == 0) {
    float out[kIntrinsicCases];
    intrinsic_cases(out);
    for (unsigned k = 0; k < kIntrinsicCases; ++k) cases[k] = out[k];
  }
  hashes[i] = tea<4>(index.x, index.y);
  const int si = static_cast<int>(i);
  atomicAdd(&atomic_int[0], 2);
  atomicSub(&atomic_int[1], 1);
  atomicMin(&atomic_int[2], -si);
  atomicMax(&atomic_int[3], si);
  atomicExch(&atomic_int[4], 7);
  atomicCAS(&atomic_int[5], 0, si + 1);  // exactly one index wins
  atomicAnd(&atomic_int[6], ~(1 << (i % 31)));
  atomicOr(&atomic_int[7], 1 << (i % 31));
  atomicXor(&atomic_int[8], 1 << (i % 2));
  atomicAdd(&atomic_uint[0], 3u);
  atomicSub(&atomic_uint[1], 1u);
  atomicMin(&atomic_uint[2], i + 5u);
  atomicMax(&atomic_uint[3], i);
  atomicInc(&atomic_uint[4], 9u);  // wraps to 0 after 9
  atomicDec(&atomic_uint[5], 9u);
  atomicAnd(&atomic_uint[6], ~(1u << (i % 32)));
  atomicOr_block(&atomic_uint[7], 1u << (i % 32));
  atomicXor_system(&atomic_uint[8], 1u);
  atomicAdd(&atomic_ull[0], 1ull << 33);
  atomicMin(&atomic_ull[1], static_cast<unsigned long long>(i) + 100ull);
  atomicMax(&atomic_ull[2], static_cast<unsigned long long>(i) << 40);
  atomicExch(&atomic_ull[3], 5ull);
  atomicCAS(&atomic_ull[4], 0ull, 1ull + i);
  atomicAnd(&atomic_ull[5], ~(1ull << (i % 64)));
  atomicOr(&atomic_ull[6], 1ull << (i % 64));
  atomicXor(&atomic_ull[7], 1ull);
  atomicAdd(&atomic_float[0], 0.5f);
  atomicExch(&atomic_float[1], 2.5f);
  atomicAdd(&atomic_double[0], 0.25);
  // clock() and clock64() are one monotonic counter in programs.
  const clock_t c0 = clock();
  const long long c1 = clock64();
  if (!(c1 >= static_cast<long long>(c0))) atomicAdd(&atomic_int[9], 1);
  if (i == 0) {
    clocks[0] = static_cast<long long>(c0);
    clocks[1] = c1;
  }
}
