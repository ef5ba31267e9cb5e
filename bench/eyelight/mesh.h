// A triangle mesh as the OptiX buffers want it: float3 positions and int3 vertex indices.
#ifndef TESSERA_BENCH_EYELIGHT_MESH_H_
#define TESSERA_BENCH_EYELIGHT_MESH_H_

#include <string>
#include <vector>

namespace tessera::bench {

struct Mesh {
  std::vector<float> positions;  // x, y, z per vertex
  std::vector<int> indices;      // three vertex indices per triangle

  size_t VertexCount() const { return positions.size() / 3; }
  size_t TriangleCount() const { return indices.size() / 3; }
};

// Loads every shape of a Wavefront OBJ file into one mesh, triangulated (tinyobjloader).
// Throws std::runtime_error when the file cannot be read or holds no triangles.
Mesh LoadObjMesh(const std::string& path);

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_EYELIGHT_MESH_H_
