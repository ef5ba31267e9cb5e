// Embree's kernels on the eyelight view's primary rays (bench/eyelight's camera), one thread:
// rtcIntersect1 per pixel against rtcIntersect4/8/16 per block of pixels (2x2, 4x2, 4x4), and
// whether the packet kernels find the same hits as the single-ray one.
#ifndef TESSERA_BENCH_BATCHING_PACKETS_H_
#define TESSERA_BENCH_BATCHING_PACKETS_H_

#include <string>
#include <vector>

namespace tessera::bench {

struct KernelTime {
  std::string name;       // "rtcIntersect1", "rtcIntersect8 (4x2)", ...
  double ns_per_ray = 0;  // median over the rounds
  size_t mismatches = 0;  // rays whose primitive or t differ from rtcIntersect1's
};

// Times each kernel over `rounds` frames of width x height on `model`.
std::vector<KernelTime> TimePackets(const std::string& model, unsigned width, unsigned height,
                                    int rounds);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_BATCHING_PACKETS_H_
