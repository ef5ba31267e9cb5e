#include "closed_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace tessera::meshgen {
namespace {

using Vec = std::array<double, 3>;

Vec Normalized(const Vec& v) {
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}

}  // namespace

Mesh Icosphere(int level) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  for (const Vec& v : std::initializer_list<Vec>{{-1, t, 0},
                                                 {1, t, 0},
                                                 {-1, -t, 0},
                                                 {1, -t, 0},
                                                 {0, -1, t},
                                                 {0, 1, t},
                                                 {0, -1, -t},
                                                 {0, 1, -t},
                                                 {t, 0, -1},
                                                 {t, 0, 1},
                                                 {-t, 0, -1},
                                                 {-t, 0, 1}}) {
    m.vertices.push_back(Normalized(v));
  }
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      const Vec& p = m.vertices[a];
      const Vec& q = m.vertices[b];
      m.vertices.push_back(Normalized({p[0] + q[0], p[1] + q[1], p[2] + q[2]}));
      const auto index = static_cast<uint32_t>(m.vertices.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& [a, b, c] : m.triangles) {
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  return m;
}

Mesh SubdividedCube(int cells) {
  Mesh m;
  std::map<std::array<int, 3>, uint32_t> index;  // integer grid coordinates → vertex
  auto vertex = [&](const std::array<int, 3>& g) {
    auto it = index.find(g);
    if (it != index.end()) return it->second;
    m.vertices.push_back(
        {2.0 * g[0] / cells - 1.0, 2.0 * g[1] / cells - 1.0, 2.0 * g[2] / cells - 1.0});
    const auto i = static_cast<uint32_t>(m.vertices.size() - 1);
    index.emplace(g, i);
    return i;
  };
  // Face (axis, side): the grid square (i, j) spans axes u, v; wound counter-clockwise seen from
  // outside.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int i = 0; i < cells; ++i) {
        for (int j = 0; j < cells; ++j) {
          auto at = [&](int di, int dj) {
            std::array<int, 3> g{};
            g[axis] = side * cells;
            g[u] = i + di;
            g[v] = j + dj;
            return vertex(g);
          };
          const uint32_t p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          if (side == 1) {
            m.triangles.push_back({p00, p10, p11});
            m.triangles.push_back({p00, p11, p01});
          } else {
            m.triangles.push_back({p00, p11, p10});
            m.triangles.push_back({p00, p01, p11});
          }
        }
      }
    }
  }
  return m;
}

std::vector<std::array<uint32_t, 2>> Edges(const Mesh& mesh) {
  std::vector<std::array<uint32_t, 2>> edges;
  for (const auto& tri : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[k], b = tri[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

std::vector<float> Placed(const Mesh& mesh, double scale, const std::array<double, 3>& offset) {
  std::vector<float> out;
  out.reserve(3 * mesh.vertices.size());
  for (const auto& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(offset[k] + scale * v[k]));
  }
  return out;
}

bool Supporting(const Mesh& mesh, const std::vector<float>& placed, uint32_t t) {
  using Wide = std::array<long double, 3>;
  auto p = [&](uint32_t i) -> Wide {
    return {placed[3 * i], placed[3 * i + 1], placed[3 * i + 2]};
  };
  const auto& tri = mesh.triangles[t];
  const Wide a = p(tri[0]), b = p(tri[1]), c = p(tri[2]);
  // In 64-bit significands the differences of the floats are exact and their products nearly
  // so: enough for the sign of a vertex's height over the plane.
  const Wide e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Wide e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const Wide n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
               e1[0] * e2[1] - e1[1] * e2[0]};
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) return false;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Wide q = p(static_cast<uint32_t>(i));
    const long double d = (q[0] - a[0]) * n[0] + (q[1] - a[1]) * n[1] + (q[2] - a[2]) * n[2];
    if (d > 0) return false;
  }
  return true;
}

}  // namespace tessera::meshgen
