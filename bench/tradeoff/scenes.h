// The tradeoff bench's scenes: triangles in world space (floats, as the devices hold them), per
// triangle albedo and emission for the path-traced interior, and the probe rays of the closed
// meshes: through every vertex and edge midpoint and in random directions from inside (a miss is
// a leak), and from outside onto supporting faces with a secondary direction into their outer
// side (a secondary hit is a self-intersection).
#ifndef TESSERA_BENCH_TRADEOFF_SCENES_H_
#define TESSERA_BENCH_TRADEOFF_SCENES_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::bench {

struct Probe {
  std::array<float, 3> origin, direction;
  std::array<float, 3> secondary{0.f, 0.f, 0.f};  // zero: no secondary ray
  uint32_t target = 0;                            // self-intersection probes: the triangle aimed at
};

struct TradeoffScene {
  std::string name;
  std::vector<float> vertices;          // xyz
  std::vector<uint32_t> indices;        // 3 a triangle
  bool interior = false;                // path traced (albedo, emission) rather than probed
  std::vector<float> albedo, emission;  // rgb a triangle
  std::array<float, 3> eye{0.f, 0.f, 0.f};
  std::vector<Probe> probes;
  size_t leak_probes = 0;  // probes [0, leak_probes) count leaks, the rest self-intersections
};

// Closed sphere of `level` (icosphere) of radius 1 at `offset`, with `spawn` self-intersection
// probes.
TradeoffScene ClosedSphere(const std::string& name, int level, const std::array<double, 3>& offset,
                           size_t random_probes, size_t spawn);

// A room (the inside of a subdivided cube, 2 units wide) with a box, a ball and a light in its
// ceiling, centred at `at`: 3e3 from the origin, floats are 2.4e-4 apart, more than the usual
// scene_epsilon of 1e-4.
TradeoffScene Interior(int cells, const std::array<double, 3>& at);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_TRADEOFF_SCENES_H_
