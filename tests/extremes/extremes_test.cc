// Closed meshes shot through every vertex and edge midpoint, from inside and from outside, at
// offsets up to 1e7 of their size and scales 1e-6 to 1e6, baked into the vertices and by
// Transforms: leaks (rays that pass through the mesh) with default, robust and watertight
// traversal; and secondary rays leaving hits: self-intersections with a scene_epsilon, with
// tesseraSpawnPoint and with the automatic offset (TESSERA_ACCURACY_OFFSET_RAYS). Counts are
// printed; watertight and the error-bound offsets must give 0 (docs/accuracy.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "extremes_scene.h"
#include "tessera/accuracy.h"

namespace tessera::testing {
namespace {

using meshgen::Mesh;
using Vec = std::array<double, 3>;

Vec At(const std::vector<float>& v, uint32_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

std::array<float, 3> ToFloat(const Vec& v) {
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

// World space of a stored (object space under a Transform) point.
Vec World(const Placement& p, const Vec& v) {
  if (!p.by_transform) return v;
  return {p.offset[0] + p.scale * v[0], p.offset[1] + p.scale * v[1], p.offset[2] + p.scale * v[2]};
}

// Rays through every vertex and every edge midpoint of the mesh as stored: from its centre, and
// from outside towards the centre's opposite side (aimed through the point from three radii out).
std::vector<Ray> LeakRays(const Mesh& mesh, const std::vector<float>& stored, const Placement& p) {
  std::vector<Vec> targets;
  for (uint32_t i = 0; i < mesh.vertices.size(); ++i) targets.push_back(At(stored, i));
  for (const auto& [a, b] : meshgen::Edges(mesh)) {
    const Vec pa = At(stored, a), pb = At(stored, b);
    targets.push_back({(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2});
  }
  const Vec centre = World(p, p.by_transform ? Vec{0, 0, 0} : p.offset);
  const Vec centre_f = {static_cast<float>(centre[0]), static_cast<float>(centre[1]),
                        static_cast<float>(centre[2])};
  std::vector<Ray> rays;
  for (const Vec& object_target : targets) {
    const Vec t = World(p, object_target);
    Ray inside;
    inside.origin = ToFloat(centre_f);
    inside.direction = ToFloat({t[0] - centre_f[0], t[1] - centre_f[1], t[2] - centre_f[2]});
    rays.push_back(inside);
    Ray outside;
    const Vec out = {t[0] + 3 * (t[0] - centre_f[0]), t[1] + 3 * (t[1] - centre_f[1]),
                     t[2] + 3 * (t[2] - centre_f[2])};
    outside.origin = ToFloat(out);
    outside.direction =
        ToFloat({t[0] - outside.origin[0], t[1] - outside.origin[1], t[2] - outside.origin[2]});
    rays.push_back(outside);
  }
  return rays;
}

struct Target {
  uint32_t triangle;
};

// Rays from outside at random points inside supporting triangles (meshgen::Supporting), each with
// a secondary direction into the triangle's outer half-space, half of them grazing; `targets`
// receives the triangle each aims at.
std::vector<Ray> SpawnRays(const Mesh& mesh, const std::vector<float>& stored, const Placement& p,
                           size_t count, std::vector<Target>* targets) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(mesh.triangles.size() - 1));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Ray> rays;
  for (size_t attempts = 0; rays.size() < count && attempts < 20 * count; ++attempts) {
    const uint32_t k = pick(rng);
    if (!meshgen::Supporting(mesh, stored, k)) continue;
    const auto& tri = mesh.triangles[k];
    const Vec a = World(p, At(stored, tri[0])), b = World(p, At(stored, tri[1])),
              c = World(p, At(stored, tri[2]));
    double u = 0.1 + 0.8 * unit(rng), v = 0.1 + 0.8 * unit(rng);
    if (u + v > 0.9) u = 0.9 - u * 0.5, v = 0.9 - u - 0.05;
    const double w = 1 - u - v;
    Vec point, n, e1, e2;
    for (int i = 0; i < 3; ++i) {
      point[i] = w * a[i] + u * b[i] + v * c[i];
      e1[i] = b[i] - a[i];
      e2[i] = c[i] - a[i];
    }
    n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
         e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double elen = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    Vec out, tangent;
    for (int i = 0; i < 3; ++i) {
      n[i] /= len;
      tangent[i] = e1[i] / elen;
      out[i] = point[i] + 2 * p.scale * (n[i] + 0.3 * tangent[i]);
    }
    Ray r;
    r.origin = ToFloat(out);
    r.direction = ToFloat({point[0] - r.origin[0], point[1] - r.origin[1], point[2] - r.origin[2]});
    const double up = rays.size() % 2 == 0 ? 1.0 : 0.01;  // half of them grazing
    r.secondary = ToFloat({up * n[0] + tangent[0], up * n[1] + tangent[1], up * n[2] + tangent[2]});
    rays.push_back(r);
    targets->push_back(Target{k});
  }
  return rays;
}

struct Config {
  const char* mesh;
  double scale;
  double offset;  // in mesh radii
  bool by_transform;
};

std::string Name(const Config& c) {
  char text[96];
  std::snprintf(text, sizeof(text), "%s scale %g offset %g%s", c.mesh, c.scale, c.offset,
                c.by_transform ? " (transform)" : "");
  return text;
}

std::vector<Config> Configs() {
  std::vector<Config> out;
  for (const char* mesh : {"icosphere", "cube"}) {
    for (double scale : {1e-6, 1.0, 1e6}) {
      for (double offset : {0.0, 1e3, 1e5, 1e7}) {
        for (bool by_transform : {false, true}) out.push_back({mesh, scale, offset, by_transform});
      }
    }
  }
  return out;
}

const Mesh& MeshNamed(const std::string& name) {
  static const Mesh sphere = meshgen::Icosphere(3);  // 1280 triangles, 642 vertices
  static const Mesh cube = meshgen::SubdividedCube(8);
  return name == "cube" ? cube : sphere;
}

Placement PlacementOf(const Config& c) {
  Placement p;
  p.scale = c.scale;
  // Off every axis, so that no coordinate stays near 0.
  p.offset = {c.offset * c.scale, -0.7 * c.offset * c.scale, 0.4 * c.offset * c.scale};
  p.by_transform = c.by_transform;
  return p;
}

class LeakTest : public ExtremesScene, public ::testing::WithParamInterface<MeshKind> {};

size_t Leaks(const std::vector<RayResult>& results) {
  size_t leaks = 0;
  for (const RayResult& r : results) leaks += r.hit ? 0 : 1;
  return leaks;
}

TEST_P(LeakTest, WatertightLetsNoRayThroughAClosedMesh) {
  const MeshKind kind = GetParam();
  std::printf("%-44s %7s %9s %9s %11s\n", "scene", "rays", "default", "robust", "watertight");
  size_t total_default = 0, total_watertight = 0, rays_total = 0;
  for (const Config& c : Configs()) {
    const Placement p = PlacementOf(c);
    const Mesh& mesh = MeshNamed(c.mesh);
    size_t leaks[3] = {0, 0, 0};
    size_t count = 0;
    const uint32_t modes[3] = {0, TESSERA_ACCURACY_ROBUST, TESSERA_ACCURACY_WATERTIGHT};
    for (int m = 0; m < 3; ++m) {
      Build(mesh, kind, p, modes[m]);
      const std::vector<Ray> rays = LeakRays(mesh, stored(), p);
      const std::vector<RayResult> results = Trace(rays);
      count = rays.size();
      leaks[m] = Leaks(results);
      for (const RayResult& r : results) {
        if (r.hit) {
          EXPECT_TRUE(std::isfinite(r.t) && r.t >= 0.f) << Name(c) << ": t " << r.t;
        }
      }
    }
    std::printf("%-44s %7zu %9zu %9zu %11zu\n", Name(c).c_str(), count, leaks[0], leaks[1],
                leaks[2]);
    total_default += leaks[0];
    total_watertight += leaks[2];
    rays_total += count;
    // An application's mesh too: where its intersection program's own test rejects the
    // watertight hit, the program reports the hit's attributes from a hair inside the triangle.
    EXPECT_EQ(leaks[2], 0u) << Name(c);
  }
  std::printf("all: %zu rays, %zu leaks by default (%.3f%%), %zu watertight\n", rays_total,
              total_default, 100.0 * total_default / rays_total, total_watertight);
}

INSTANTIATE_TEST_SUITE_P(Meshes, LeakTest,
                         ::testing::Values(MeshKind::kGeometryTriangles,
                                           MeshKind::kApplicationMesh),
                         [](const auto& info) {
                           return info.param == MeshKind::kGeometryTriangles ? "GeometryTriangles"
                                                                             : "ApplicationMesh";
                         });

class SelfIntersectionTest : public ExtremesScene {};

// Secondary rays leave hits on supporting faces into their outer half-space, where nothing of the
// mesh is: any hit is the surface hitting itself again.
TEST_F(SelfIntersectionTest, ErrorBoundOffsetsNeverHitTheSurfaceAgain) {
  std::printf("%-44s %6s %12s %12s %12s %12s\n", "scene", "rays", "eps 1e-4", "spawn point",
              "auto offset", "spawn twice");
  size_t total[4] = {0, 0, 0, 0}, rays_total = 0;
  for (const Config& c : Configs()) {
    const Placement p = PlacementOf(c);
    const Mesh& mesh = MeshNamed(c.mesh);
    size_t self_hits[4] = {0, 0, 0, 0}, counted = 0;
    for (int mode = 1; mode <= 4; ++mode) {
      Build(mesh, MeshKind::kGeometryTriangles, p, mode == 3 ? TESSERA_ACCURACY_OFFSET_RAYS : 0);
      std::vector<Target> targets;
      const std::vector<Ray> rays = SpawnRays(mesh, stored(), p, 2000, &targets);
      const std::vector<RayResult> results = Trace(rays, static_cast<unsigned>(mode));
      counted = 0;
      for (size_t i = 0; i < results.size(); ++i) {
        if (!results[i].hit || results[i].primitive != targets[i].triangle) continue;
        ++counted;
        self_hits[mode - 1] += results[i].secondary_hit ? 1 : 0;
      }
    }
    std::printf("%-44s %6zu %12zu %12zu %12zu %12zu\n", Name(c).c_str(), counted, self_hits[0],
                self_hits[1], self_hits[2], self_hits[3]);
    EXPECT_GT(counted, 0u) << Name(c);
    EXPECT_EQ(self_hits[1], 0u) << Name(c) << ": tesseraSpawnPoint";
    EXPECT_EQ(self_hits[2], 0u) << Name(c) << ": TESSERA_ACCURACY_OFFSET_RAYS";
    EXPECT_EQ(self_hits[3], 0u) << Name(c) << ": tesseraSpawnPoint after one toward the other side";
    for (int m = 0; m < 4; ++m) total[m] += self_hits[m];
    rays_total += counted;
  }
  std::printf(
      "all: %zu rays; self-intersections: scene_epsilon 1e-4 %zu (%.2f%%), spawn point "
      "%zu, automatic offset %zu, spawn point after one toward the other side %zu\n",
      rays_total, total[0], 100.0 * total[0] / rays_total, total[1], total[2], total[3]);
}

}  // namespace
}  // namespace tessera::testing
