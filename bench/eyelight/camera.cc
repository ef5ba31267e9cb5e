#include "camera.h"

#include <cmath>
#include <string>
#include <utility>

namespace tessera::bench {
namespace {

struct Vec3 {
  float x, y, z;
};
Vec3 Sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 Scale(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3 Cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 Normalize(Vec3 a) { return Scale(a, 1.f / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z)); }
Vec3 FromArray(const float* a) { return {a[0], a[1], a[2]}; }

std::string Num(float f) {
  std::string s = std::to_string(f);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::vector<std::string> Camera::ViewerFlags() const {
  std::vector<std::string> flags;
  const std::pair<const char*, const float*> points[] = {{"-vp", from}, {"-vi", to}, {"-vu", up}};
  for (const auto& [flag, p] : points) {
    flags.insert(flags.end(), {flag, Num(p[0]), Num(p[1]), Num(p[2])});
  }
  flags.insert(flags.end(), {"-fov", Num(fov_degrees)});
  return flags;
}

Pinhole MakePinhole(const Camera& camera, unsigned width, unsigned height) {
  Vec3 eye = FromArray(camera.from);
  Vec3 w = Sub(FromArray(camera.to), eye);
  float wlen = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
  Vec3 u = Normalize(Cross(w, FromArray(camera.up)));
  Vec3 v = Normalize(Cross(u, w));
  float vlen = wlen * std::tan(0.5f * camera.fov_degrees * static_cast<float>(M_PI) / 180.f);
  v = Scale(v, vlen);
  u = Scale(u, vlen * static_cast<float>(width) / static_cast<float>(height));
  return Pinhole{{eye.x, eye.y, eye.z}, {u.x, u.y, u.z}, {v.x, v.y, v.z}, {w.x, w.y, w.z}};
}

}  // namespace tessera::bench
