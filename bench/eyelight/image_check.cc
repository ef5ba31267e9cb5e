#include "image_check.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <set>
#include <stdexcept>

namespace tessera::bench {
namespace {

constexpr double kMinHitFraction = 0.5;
constexpr int kMinGreyLevels = 16;
constexpr int kGreyTolerance = 2;
constexpr double kMaxMismatchFraction = 0.01;

// Grey value and hit flag of the closest triangle along one ray, by testing every triangle.
struct Shade {
  bool hit = false;
  int grey = 0;
};

Shade TraceReference(const Mesh& mesh, const float o[3], const float d[3]) {
  const float* p = mesh.positions.data();
  float best_t = INFINITY;
  float best_n[3] = {0, 0, 0};
  for (size_t i = 0; i < mesh.TriangleCount(); ++i) {
    const float* a = p + 3 * mesh.indices[3 * i];
    const float* b = p + 3 * mesh.indices[3 * i + 1];
    const float* c = p + 3 * mesh.indices[3 * i + 2];
    double e1[3], e2[3], s[3], pv[3], qv[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = b[k] - a[k];
      e2[k] = c[k] - a[k];
      s[k] = o[k] - a[k];
    }
    pv[0] = d[1] * e2[2] - d[2] * e2[1];
    pv[1] = d[2] * e2[0] - d[0] * e2[2];
    pv[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (det == 0) continue;
    double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
    qv[0] = s[1] * e1[2] - s[2] * e1[1];
    qv[1] = s[2] * e1[0] - s[0] * e1[2];
    qv[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    double t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
    if (u < 0 || v < 0 || u + v > 1 || t <= 0 || t >= best_t) continue;
    best_t = static_cast<float>(t);
    best_n[0] = static_cast<float>(e1[1] * e2[2] - e1[2] * e2[1]);
    best_n[1] = static_cast<float>(e1[2] * e2[0] - e1[0] * e2[2]);
    best_n[2] = static_cast<float>(e1[0] * e2[1] - e1[1] * e2[0]);
  }
  Shade shade;
  if (!std::isfinite(best_t)) return shade;
  float nlen = std::sqrt(best_n[0] * best_n[0] + best_n[1] * best_n[1] + best_n[2] * best_n[2]);
  float dlen = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  float c = std::fabs(best_n[0] * d[0] + best_n[1] * d[1] + best_n[2] * d[2]) / (nlen * dlen);
  shade.hit = true;
  shade.grey = static_cast<int>(255.01f * std::fmin(std::fmax(c, 0.f), 1.f));
  return shade;
}

}  // namespace

CheckReport CheckImage(const Image& image, const Mesh& mesh, const Camera& camera) {
  const Pinhole pin = MakePinhole(camera, image.width, image.height);
  size_t hits = 0, mismatches = 0;
  std::set<int> levels;
  for (unsigned row = 0; row < image.height; ++row) {
    unsigned y = image.height - 1 - row;  // launch row; image rows run top to bottom
    for (unsigned x = 0; x < image.width; ++x) {
      const uint8_t* px = &image.rgba[(size_t{row} * image.width + x) * 4];
      bool hit = px[3] == 255;
      hits += hit;
      levels.insert(px[0]);
      float dx = (static_cast<float>(x) + 0.5f) / static_cast<float>(image.width) * 2.f - 1.f;
      float dy = (static_cast<float>(y) + 0.5f) / static_cast<float>(image.height) * 2.f - 1.f;
      float d[3];
      for (int k = 0; k < 3; ++k) d[k] = dx * pin.u[k] + dy * pin.v[k] + pin.w[k];
      Shade ref = TraceReference(mesh, pin.eye, d);
      if (ref.hit != hit || std::abs(ref.grey - static_cast<int>(px[0])) > kGreyTolerance) {
        ++mismatches;
      }
    }
  }
  CheckReport r;
  double n = static_cast<double>(size_t{image.width} * image.height);
  r.hit_fraction = n > 0 ? static_cast<double>(hits) / n : 0;
  r.grey_levels = static_cast<int>(levels.size());
  r.mismatch_fraction = n > 0 ? static_cast<double>(mismatches) / n : 1;
  r.ok = r.hit_fraction >= kMinHitFraction && r.grey_levels >= kMinGreyLevels &&
         r.mismatch_fraction <= kMaxMismatchFraction;
  char text[256];
  std::snprintf(text, sizeof(text),
                "hit %.1f%% of pixels (need >= %.0f%%), %d grey levels (need >= %d), "
                "%.2f%% pixels differ from the reference (allowed <= %.0f%%)",
                100 * r.hit_fraction, 100 * kMinHitFraction, r.grey_levels, kMinGreyLevels,
                100 * r.mismatch_fraction, 100 * kMaxMismatchFraction);
  r.summary = text;
  return r;
}

void WriteImage(const Image& image, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << image.width << " " << image.height << "\n255\n";
  for (size_t pixel = 0; pixel < size_t{image.width} * image.height; ++pixel) {
    out.write(reinterpret_cast<const char*>(&image.rgba[4 * pixel]), 3);  // RGB of RGBA
  }
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace tessera::bench
