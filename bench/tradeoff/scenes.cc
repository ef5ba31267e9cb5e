#include "scenes.h"

#include <cmath>
#include <random>

#include "closed_meshes.h"

namespace tessera::bench {
namespace {

using Vec = std::array<double, 3>;

Vec At(const std::vector<float>& v, uint32_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

std::array<float, 3> F(const Vec& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

Vec Sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

}  // namespace

TradeoffScene ClosedSphere(const std::string& name, int level, const std::array<double, 3>& offset,
                           size_t random_probes, size_t spawn) {
  const meshgen::Mesh mesh = meshgen::Icosphere(level);
  TradeoffScene s;
  s.name = name;
  s.vertices = meshgen::Placed(mesh, 1.0, offset);
  for (const auto& t : mesh.triangles) s.indices.insert(s.indices.end(), t.begin(), t.end());
  const std::array<float, 3> centre = F(offset);
  const Vec c{centre[0], centre[1], centre[2]};
  auto through = [&](const Vec& target) {
    Probe inside;
    inside.origin = centre;
    inside.direction = F(Sub(target, c));
    s.probes.push_back(inside);
    Probe outside;
    const Vec d = Sub(target, c);
    outside.origin = F({target[0] + 3 * d[0], target[1] + 3 * d[1], target[2] + 3 * d[2]});
    outside.direction = F(Sub(target, {outside.origin[0], outside.origin[1], outside.origin[2]}));
    s.probes.push_back(outside);
  };
  for (uint32_t i = 0; i < mesh.vertices.size(); ++i) through(At(s.vertices, i));
  for (const auto& [a, b] : meshgen::Edges(mesh)) {
    const Vec pa = At(s.vertices, a), pb = At(s.vertices, b);
    through({(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2});
  }
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (size_t i = 0; i < random_probes; ++i) {
    Probe p;
    p.origin = centre;
    p.direction = F({normal(rng), normal(rng), normal(rng)});
    s.probes.push_back(p);
  }
  s.leak_probes = s.probes.size();
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(mesh.triangles.size() - 1));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Every face of a sphere at the origin supports it; far away, rounding can dent a few.
  for (size_t tries = 0; s.probes.size() - s.leak_probes < spawn && tries < 4 * spawn; ++tries) {
    const uint32_t k = pick(rng);
    if (!meshgen::Supporting(mesh, s.vertices, k)) continue;
    const Vec a = At(s.vertices, mesh.triangles[k][0]), b = At(s.vertices, mesh.triangles[k][1]),
              cc = At(s.vertices, mesh.triangles[k][2]);
    const double u = 0.1 + 0.35 * unit(rng), v = 0.1 + 0.35 * unit(rng), w = 1 - u - v;
    const Vec e1 = Sub(b, a), e2 = Sub(cc, a);
    Vec n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
          e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double elen = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    Vec point, tangent;
    for (int i = 0; i < 3; ++i) {
      n[i] /= len;
      tangent[i] = e1[i] / elen;
      point[i] = w * a[i] + u * b[i] + v * cc[i];
    }
    Probe p;
    p.origin = F({point[0] + 2 * n[0] + 0.5 * tangent[0], point[1] + 2 * n[1] + 0.5 * tangent[1],
                  point[2] + 2 * n[2] + 0.5 * tangent[2]});
    p.direction = F(Sub(point, {p.origin[0], p.origin[1], p.origin[2]}));
    const double up = (s.probes.size() % 2 == 0) ? 1.0 : 0.05;  // half of them grazing
    p.secondary = F({up * n[0] + tangent[0], up * n[1] + tangent[1], up * n[2] + tangent[2]});
    p.target = k;
    s.probes.push_back(p);
  }
  return s;
}

TradeoffScene Interior(int cells, const std::array<double, 3>& at) {
  TradeoffScene s;
  s.name = "interior at 3e3 (path traced)";
  auto add = [&](const meshgen::Mesh& m, double scale, const Vec& offset, bool inward,
                 const std::array<float, 3>& rgb) {
    const auto base = static_cast<uint32_t>(s.vertices.size() / 3);
    const std::vector<float> v =
        meshgen::Placed(m, scale, {at[0] + offset[0], at[1] + offset[1], at[2] + offset[2]});
    s.vertices.insert(s.vertices.end(), v.begin(), v.end());
    for (const auto& t : m.triangles) {
      // The room is seen from inside: its triangles wind the other way.
      const std::array<uint32_t, 3> tri = inward ? std::array<uint32_t, 3>{t[0], t[2], t[1]} : t;
      for (uint32_t i : tri) s.indices.push_back(base + i);
      // The light: the ceiling's middle (y = +1 face, |x|, |z| < 0.3).
      const Vec ca = {v[3 * t[0]] - at[0], v[3 * t[0] + 1] - at[1], v[3 * t[0] + 2] - at[2]};
      const bool light = inward && ca[1] > 0.99 * scale && std::fabs(ca[0]) < 0.3 * scale &&
                         std::fabs(ca[2]) < 0.3 * scale;
      s.albedo.insert(s.albedo.end(), rgb.begin(), rgb.end());
      const float e = light ? 8.f : 0.f;
      s.emission.insert(s.emission.end(), {e, e, e});
    }
  };
  add(meshgen::SubdividedCube(cells), 1.0, {0, 0, 0}, true, {0.75f, 0.72f, 0.68f});
  add(meshgen::SubdividedCube(4), 0.3, {-0.4, -0.7, -0.3}, false, {0.7f, 0.25f, 0.2f});
  add(meshgen::Icosphere(4), 0.3, {0.45, -0.7, 0.2}, false, {0.25f, 0.6f, 0.3f});
  s.interior = true;
  s.eye = F({at[0], at[1], at[2] + 0.95});
  return s;
}

}  // namespace tessera::bench
