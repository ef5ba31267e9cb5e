// What the port corpus's host tests share: a context on a named device set, buffers, samplers and
// scene nodes made with the OptiX 3 C API as SDK samples make them, a loop that renders on
// inproc, local:1 and local:3 and expects the same bits, and host versions of what the corpus's
// cameras and make_color compute.
#ifndef TESSERA_TESTS_PORT_CORPUS_PORT_CORPUS_FIXTURE_H_
#define TESSERA_TESTS_PORT_CORPUS_PORT_CORPUS_FIXTURE_H_

#include <optix.h>
#include <optixu/optixu_math_namespace.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "../semantics/rt_fixture.h"

namespace tessera::testing {

inline constexpr const char* kDeviceSets[] = {"inproc", "local:1", "local:3"};

// make_color of sample_common.h on the host: BGRA8 of a colour, as programs write it.
inline std::uint32_t Bgra8(const optix::float3& c) {
  auto byte = [](float v) { return static_cast<std::uint32_t>(__saturatef(v) * 255.99f); };
  return byte(c.z) | byte(c.y) << 8 | byte(c.x) << 16 | 255u << 24;
}
// Channel 0 (red), 1 (green) or 2 (blue) of a BGRA8 pixel.
inline int Channel(std::uint32_t bgra, int c) {
  return static_cast<int>((bgra >> (16 - 8 * c)) & 0xFF);
}

// The corpus's pinhole cameras (pinhole_camera.cu, motion_camera.cu): launch index (x, y) of a
// width x height launch looks along normalize(d.x U + d.y V + W), d in [-1, 1), y = 0 at the
// bottom.
struct PinholeCamera {
  optix::float3 eye, U, V, W;
  optix::float3 Direction(unsigned x, unsigned y, unsigned width, unsigned height) const {
    using namespace optix;
    const float2 d =
        make_float2(float(x), float(y)) / make_float2(float(width), float(height)) * 2.f - 1.f;
    return normalize(d.x * U + d.y * V + W);
  }
};

// The distance along a unit `dir` from `origin` to the sphere (centre, radius), or -1 on a miss.
inline float HitSphere(const optix::float3& origin, const optix::float3& dir,
                       const optix::float3& centre, float radius) {
  const optix::float3 o = origin - centre;
  const float b = optix::dot(o, dir), c = optix::dot(o, o) - radius * radius;
  const float disc = b * b - c;
  if (disc <= 0.f) return -1.f;
  const float t = -b - std::sqrt(disc);
  return t > 0.f ? t : -1.f;
}

class PortCorpusTest : public RtFixture {
 protected:
  // A fresh context on `spec` with one entry point and `ray_types` ray types.
  void UseDevices(const char* spec, unsigned ray_types) {
    if (ctx_ != nullptr) rtContextDestroy(ctx_);
    ctx_ = nullptr;
    Ok(rtContextCreate(&ctx_));
    Ok(tesseraContextSetDeviceSpec(ctx_, spec));
    Ok(rtContextSetEntryPointCount(ctx_, 1));
    Ok(rtContextSetRayTypeCount(ctx_, ray_types));
  }
  // A 1D buffer no variable names (its id goes in another buffer), and one bound to `name`.
  RTbuffer Unbound1D(unsigned type, RTformat format, size_t n, size_t element_size = 0) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, type, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, format), RT_SUCCESS);
    if (format == RT_FORMAT_USER) {
      EXPECT_EQ(rtBufferSetElementSize(b, element_size), RT_SUCCESS);
    }
    EXPECT_EQ(rtBufferSetSize1D(b, n), RT_SUCCESS);
    return b;
  }
  RTbuffer Buffer1D(const std::string& name, unsigned type, RTformat format, size_t n,
                    size_t element_size = 0) {
    RTbuffer b = Unbound1D(type, format, n, element_size);
    EXPECT_EQ(rtVariableSetObject(ContextVar(name), b), RT_SUCCESS);
    return b;
  }
  template <typename T>
  void Fill(RTbuffer b, const std::vector<T>& values) {
    void* p = nullptr;
    ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    std::memcpy(p, values.data(), values.size() * sizeof(T));
    ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  }
  template <typename T>
  std::vector<T> Get(RTbuffer b, size_t n) {
    std::vector<T> out(n);
    void* p = nullptr;
    EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    if (p != nullptr) std::memcpy(out.data(), p, n * sizeof(T));
    rtBufferUnmap(b);
    return out;
  }
  void SetFloat3(const char* name, float x, float y, float z) {
    Ok(rtVariableSet3f(ContextVar(name), x, y, z));
  }
  void SetFloat3(RTvariable v, const optix::float3& f) { Ok(rtVariableSet3f(v, f.x, f.y, f.z)); }
  void SetCamera(const PinholeCamera& c) {
    SetFloat3(ContextVar("eye"), c.eye);
    SetFloat3(ContextVar("U"), c.U);
    SetFloat3(ContextVar("V"), c.V);
    SetFloat3(ContextVar("W"), c.W);
  }
  // Spheres (center, radius) in the buffer sphere.cu reads.
  void Spheres(const std::vector<Float4>& spheres) {
    Fill(Buffer1D("spheres", RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, spheres.size()), spheres);
  }

  // Variables of scene nodes, declared on first use.
  RTvariable GeometryVar(RTgeometry g, const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtGeometryDeclareVariable(g, name, &v), RT_SUCCESS);
    return v;
  }
  RTvariable InstanceVar(RTgeometryinstance i, const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtGeometryInstanceDeclareVariable(i, name, &v), RT_SUCCESS);
    return v;
  }
  RTvariable MaterialVar(RTmaterial m, const char* name) {
    RTvariable v = nullptr;
    EXPECT_EQ(rtMaterialDeclareVariable(m, name, &v), RT_SUCCESS);
    return v;
  }

  // A geometry of `primitives` primitives, an instance of it with one material, and a group of
  // instances over one acceleration: the nodes SDK samples build by hand.
  RTgeometry NewGeometry(RTprogram intersect, RTprogram bounds, unsigned primitives) {
    RTgeometry g = nullptr;
    EXPECT_EQ(rtGeometryCreate(ctx_, &g), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetPrimitiveCount(g, primitives), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetIntersectionProgram(g, intersect), RT_SUCCESS);
    EXPECT_EQ(rtGeometrySetBoundingBoxProgram(g, bounds), RT_SUCCESS);
    return g;
  }
  RTgeometryinstance NewInstance(RTgeometry g, RTmaterial m) {
    RTgeometryinstance i = nullptr;
    EXPECT_EQ(rtGeometryInstanceCreate(ctx_, &i), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetGeometry(i, g), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterialCount(i, 1), RT_SUCCESS);
    EXPECT_EQ(rtGeometryInstanceSetMaterial(i, 0, m), RT_SUCCESS);
    return i;
  }
  RTgeometrygroup NewGroup(const std::vector<RTgeometryinstance>& instances) {
    RTgeometrygroup group = nullptr;
    EXPECT_EQ(rtGeometryGroupCreate(ctx_, &group), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetAcceleration(group, Accel()), RT_SUCCESS);
    EXPECT_EQ(rtGeometryGroupSetChildCount(group, static_cast<unsigned>(instances.size())),
              RT_SUCCESS);
    for (unsigned k = 0; k < instances.size(); ++k) {
      EXPECT_EQ(rtGeometryGroupSetChild(group, k, instances[k]), RT_SUCCESS);
    }
    return group;
  }

  // A 2D texture sampler as the SDK's loadTexture makes one: linear filtering without mipmaps,
  // normalized coordinates, normalized float reads, one wrap mode per dimension.
  RTtexturesampler Sampler2D(RTbuffer texels, RTwrapmode wrap_u, RTwrapmode wrap_v) {
    RTtexturesampler s = nullptr;
    EXPECT_EQ(rtTextureSamplerCreate(ctx_, &s), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetWrapMode(s, 0, wrap_u), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetWrapMode(s, 1, wrap_v), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetIndexingMode(s, RT_TEXTURE_INDEX_NORMALIZED_COORDINATES),
              RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetReadMode(s, RT_TEXTURE_READ_NORMALIZED_FLOAT), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetMaxAnisotropy(s, 1.0f), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetMipLevelCount(s, 1u), RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetArraySize(s, 1u), RT_SUCCESS);
    EXPECT_EQ(
        rtTextureSamplerSetFilteringModes(s, RT_FILTER_LINEAR, RT_FILTER_LINEAR, RT_FILTER_NONE),
        RT_SUCCESS);
    EXPECT_EQ(rtTextureSamplerSetBuffer(s, 0u, 0u, texels), RT_SUCCESS);
    return s;
  }

  // Runs `render(spec)` on each device set and expects each result to equal inproc's, bit for
  // bit; returns inproc's (empty after a fatal failure).
  template <typename Render>
  auto OnEveryDeviceSet(Render render) -> decltype(render("")) {
    decltype(render("")) reference{};
    bool first = true;
    for (const char* spec : kDeviceSets) {
      SCOPED_TRACE(spec);
      auto result = render(spec);
      if (::testing::Test::HasFatalFailure()) return {};
      if (first) {
        reference = result;
        first = false;
      } else {
        EXPECT_TRUE(result == reference) << "the result on " << spec << " differs from inproc's";
      }
    }
    return reference;
  }
};

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_PORT_CORPUS_PORT_CORPUS_FIXTURE_H_
