#include "packets.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "eyelight/camera.h"
#include "eyelight/mesh.h"

namespace tessera::bench {
namespace {

struct Hit {
  unsigned prim = RTC_INVALID_GEOMETRY_ID;
  float t = 0.f;
  bool operator!=(const Hit& o) const { return prim != o.prim || t != o.t; }
};

// One frame's primary rays, as the eyelight programs make them (bench/eyelight/eyelight.cu).
class Frame {
 public:
  Frame(unsigned width, unsigned height)
      : width_(width), height_(height), p_(MakePinhole(Camera(), width, height)) {}

  void Ray(unsigned x, unsigned y, float org[3], float dir[3]) const {
    const float dx = (static_cast<float>(x) + 0.5f) / static_cast<float>(width_) * 2.f - 1.f;
    const float dy = (static_cast<float>(y) + 0.5f) / static_cast<float>(height_) * 2.f - 1.f;
    float d[3], len = 0.f;
    for (int i = 0; i < 3; ++i) {
      d[i] = dx * p_.u[i] + dy * p_.v[i] + p_.w[i];
      len += d[i] * d[i];
    }
    const float inv = 1.f / std::sqrt(len);
    for (int i = 0; i < 3; ++i) {
      org[i] = p_.eye[i];
      dir[i] = d[i] * inv;
    }
  }
  unsigned width() const { return width_; }
  unsigned height() const { return height_; }

 private:
  unsigned width_, height_;
  Pinhole p_;
};

RTCScene BuildScene(RTCDevice device, const Mesh& mesh) {
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.VertexCount()));
  std::copy(mesh.positions.begin(), mesh.positions.end(), v);
  auto* i = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.TriangleCount()));
  std::copy(mesh.indices.begin(), mesh.indices.end(), i);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  return scene;
}

// Every pixel through rtcIntersect1.
void Singles(RTCScene scene, const Frame& f, std::vector<Hit>& hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (unsigned y = 0; y < f.height(); ++y) {
    for (unsigned x = 0; x < f.width(); ++x) {
      RTCRayHit rh;
      float o[3], d[3];
      f.Ray(x, y, o, d);
      rh.ray.org_x = o[0], rh.ray.org_y = o[1], rh.ray.org_z = o[2];
      rh.ray.dir_x = d[0], rh.ray.dir_y = d[1], rh.ray.dir_z = d[2];
      rh.ray.tnear = 0.f;
      rh.ray.tfar = INFINITY;
      rh.ray.time = 0.f;
      rh.ray.mask = ~0u;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      Hit& h = hits[size_t{y} * f.width() + x];
      h.prim = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID : rh.hit.primID;
      h.t = rh.ray.tfar;
    }
  }
}

template <int N, typename RayHitN>
void Intersect(const int* valid, RTCScene scene, RTCIntersectContext* c, RayHitN* rh);
template <>
void Intersect<4>(const int* valid, RTCScene scene, RTCIntersectContext* c, RTCRayHit4* rh) {
  rtcIntersect4(valid, scene, c, rh);
}
template <>
void Intersect<8>(const int* valid, RTCScene scene, RTCIntersectContext* c, RTCRayHit8* rh) {
  rtcIntersect8(valid, scene, c, rh);
}
template <>
void Intersect<16>(const int* valid, RTCScene scene, RTCIntersectContext* c, RTCRayHit16* rh) {
  rtcIntersect16(valid, scene, c, rh);
}

// Every block of BW x BH pixels (BW * BH = N) through one packet; lanes past the image's edge
// are inactive.
template <int N, int BW, typename RayHitN>
void Packets(RTCScene scene, const Frame& f, std::vector<Hit>& hits) {
  constexpr int BH = N / BW;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  for (unsigned by = 0; by < f.height(); by += BH) {
    for (unsigned bx = 0; bx < f.width(); bx += BW) {
      alignas(64) RayHitN rh;
      alignas(64) int valid[N];
      for (int k = 0; k < N; ++k) {
        const unsigned x = bx + k % BW, y = by + k / BW;
        valid[k] = x < f.width() && y < f.height() ? -1 : 0;
        float o[3] = {0, 0, 0}, d[3] = {0, 0, 1};
        if (valid[k]) f.Ray(x, y, o, d);
        rh.ray.org_x[k] = o[0], rh.ray.org_y[k] = o[1], rh.ray.org_z[k] = o[2];
        rh.ray.dir_x[k] = d[0], rh.ray.dir_y[k] = d[1], rh.ray.dir_z[k] = d[2];
        rh.ray.tnear[k] = 0.f;
        rh.ray.tfar[k] = INFINITY;
        rh.ray.time[k] = 0.f;
        rh.ray.mask[k] = ~0u;
        rh.ray.id[k] = 0;
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      Intersect<N>(valid, scene, &context, &rh);
      for (int k = 0; k < N; ++k) {
        if (!valid[k]) continue;
        const unsigned x = bx + k % BW, y = by + k / BW;
        Hit& h = hits[size_t{y} * f.width() + x];
        h.prim = rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID
                                                             : rh.hit.primID[k];
        h.t = rh.ray.tfar[k];
      }
    }
  }
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<KernelTime> TimePackets(const std::string& model, unsigned width, unsigned height,
                                    int rounds) {
  const Mesh mesh = LoadObjMesh(model);
  RTCDevice device = rtcNewDevice("threads=1");
  if (device == nullptr) throw std::runtime_error("rtcNewDevice failed");
  RTCScene scene = BuildScene(device, mesh);
  const Frame frame(width, height);
  using Kernel = void (*)(RTCScene, const Frame&, std::vector<Hit>&);
  const std::pair<const char*, Kernel> kernels[] = {
      {"rtcIntersect1", &Singles},
      {"rtcIntersect4 (2x2)", &Packets<4, 2, RTCRayHit4>},
      {"rtcIntersect8 (4x2)", &Packets<8, 4, RTCRayHit8>},
      {"rtcIntersect16 (4x4)", &Packets<16, 4, RTCRayHit16>},
  };
  const size_t pixels = size_t{width} * height;
  std::vector<Hit> reference(pixels), hits(pixels);
  Singles(scene, frame, reference);
  std::vector<std::vector<double>> times(std::size(kernels));
  std::vector<KernelTime> out(std::size(kernels));
  // Rounds alternate the kernels, so that each sees the same machine.
  for (int r = 0; r < rounds; ++r) {
    for (size_t k = 0; k < std::size(kernels); ++k) {
      const auto start = std::chrono::steady_clock::now();
      kernels[k].second(scene, frame, hits);
      const std::chrono::duration<double, std::nano> ns = std::chrono::steady_clock::now() - start;
      times[k].push_back(ns.count() / static_cast<double>(pixels));
      if (r == 0) {
        out[k].name = kernels[k].first;
        for (size_t i = 0; i < pixels; ++i) out[k].mismatches += hits[i] != reference[i];
      }
    }
  }
  for (size_t k = 0; k < std::size(kernels); ++k) out[k].ns_per_ray = Median(times[k]);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return out;
}

}  // namespace tessera::bench
