#include "mesh.h"

#include <tiny_obj_loader.h>

#include <stdexcept>

namespace tessera::bench {

Mesh LoadObjMesh(const std::string& path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    throw std::runtime_error("cannot load " + path + ": " + reader.Error());
  }
  Mesh mesh;
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  mesh.positions.assign(attrib.vertices.begin(), attrib.vertices.end());
  const int vertex_count = static_cast<int>(mesh.VertexCount());
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t at = 0;
    for (unsigned char n : shape.mesh.num_face_vertices) {
      // Triangulation leaves only triangles; lines or points in the file have fewer corners.
      if (n == 3) {
        for (size_t k = 0; k < 3; ++k) {
          int v = shape.mesh.indices[at + k].vertex_index;
          if (v < 0 || v >= vertex_count) {
            throw std::runtime_error(path + ": shape '" + shape.name + "' uses vertex " +
                                     std::to_string(v) + " of " + std::to_string(vertex_count));
          }
          mesh.indices.push_back(v);
        }
      }
      at += n;
    }
  }
  if (mesh.TriangleCount() == 0) throw std::runtime_error(path + " holds no triangles");
  return mesh;
}

}  // namespace tessera::bench
