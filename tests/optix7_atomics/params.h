// Launch parameters of the atomics test (atomics.cu, main.cc).
#ifndef TESSERA_TESTS_OPTIX7_ATOMICS_PARAMS_H_
#define TESSERA_TESTS_OPTIX7_ATOMICS_PARAMS_H_

#include "counters.h"

// A semantics result: which check, and the value the program saw.
struct Seen {
  unsigned long long check;
  unsigned long long value;
};

constexpr unsigned kMaxSeen = 128;

struct Params {
  Counters* counters;    // __raygen__count
  Seen* seen;            // __raygen__semantics: the checks in order
  unsigned* seen_count;  // how many
  unsigned* append;      // __raygen__append: a counter whose old values are slots
  unsigned* slots;       // slot -> 1 + index (0: empty)
  unsigned slot_count;
  unsigned* bench;  // __raygen__bench: bench_bins counters
  unsigned bench_bins;
  unsigned bench_adds;  // atomicAdds per index
};

#endif  // TESSERA_TESTS_OPTIX7_ATOMICS_PARAMS_H_
