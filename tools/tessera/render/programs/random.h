// The random numbers of one sample: a PCG32 generator (O'Neill 2014) whose state and stream come
// from hashing (pixel, sample index, seed). What a sample draws depends on nothing else: not the
// thread, tile or device that runs it, nor how many samples one launch takes. So an image is the
// same bits on any set of devices, and a render resumed from its accumulation goes on exactly as
// an uninterrupted one would have.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_RANDOM_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_RANDOM_H_

#include <optix.h>

struct Rng {
  unsigned long long state;
  unsigned long long stream;  // odd: the generator's increment
};

// SplitMix64's finalizer (Steele, Lea and Flood 2014): a bijective 64-bit hash.
static __device__ __inline__ unsigned long long Mix64(unsigned long long z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

static __device__ __inline__ unsigned int NextU32(Rng& rng) {
  const unsigned long long old = rng.state;
  rng.state = old * 6364136223846793005ull + rng.stream;
  const unsigned int xorshifted = static_cast<unsigned int>(((old >> 18u) ^ old) >> 27u);
  const unsigned int rot = static_cast<unsigned int>(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

static __device__ __inline__ Rng MakeRng(unsigned int pixel, unsigned int sample,
                                         unsigned int seed) {
  const unsigned long long key =
      (static_cast<unsigned long long>(pixel) << 32 | sample) ^ Mix64(seed + 0x9e3779b97f4a7c15ull);
  Rng rng;
  rng.state = Mix64(key);
  rng.stream = Mix64(key ^ 0xd1b54a32d192ed03ull) | 1ull;
  NextU32(rng);
  return rng;
}

// A float in [0, 1): the top 24 bits, so that 1 is never reached.
static __device__ __inline__ float Rnd(Rng& rng) {
  return static_cast<float>(NextU32(rng) >> 8) * (1.0f / 16777216.0f);
}

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_RANDOM_H_
