// Closed triangle meshes for accuracy tests and benchmarks: exact (double) vertices of unit-size
// shapes about the origin, consistently wound (counter-clockwise seen from outside), and their
// vertices placed at an offset and scale in float, as an application stores them.
#ifndef TESSERA_TOOLS_MESHGEN_CLOSED_MESHES_H_
#define TESSERA_TOOLS_MESHGEN_CLOSED_MESHES_H_

#include <array>
#include <cstdint>
#include <vector>

namespace tessera::meshgen {

struct Mesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// An icosahedron subdivided `level` times, its vertices on the unit sphere: 20 * 4^level
// triangles (level 6: 81,920).
Mesh Icosphere(int level);

// The cube [-1, 1]^3 with `cells` x `cells` squares of two triangles on each face: every grid
// vertex inside a face is shared by six triangles (a fan), every edge by two.
Mesh SubdividedCube(int cells);

// Every edge once, as the pair of its vertices (lower index first).
std::vector<std::array<uint32_t, 2>> Edges(const Mesh& mesh);

// The vertices as floats at `offset` + `scale` * v (each component rounded once), packed xyz.
std::vector<float> Placed(const Mesh& mesh, double scale, const std::array<double, 3>& offset);

// Whether every vertex of `placed` (packed floats) lies on or below the plane of triangle `t`
// (its outward side up), computed exactly enough in double: a ray leaving `t` into its upper
// half-space can then hit nothing of the mesh, so any hit it reports is a self-intersection.
// False for a triangle without area.
bool Supporting(const Mesh& mesh, const std::vector<float>& placed, uint32_t t);

}  // namespace tessera::meshgen

#endif  // TESSERA_TOOLS_MESHGEN_CLOSED_MESHES_H_
