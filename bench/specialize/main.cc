// tessera-bench-specialize: what the shape of a scene costs a ray, measured in one run against a
// baseline (issue 26, "only what a scene requires"). Primary rays (orthographic, one per launch
// index) hit a heightfield mesh of native triangles with an OptiX 3 intersection program; the
// closest-hit program shades with the world-space normal (rtTransformNormal). Variants:
//   levels     the mesh's GeometryGroup traced directly (flat), and below 1, 2 and 3 levels of
//              Group -> Transform, flattened into one Embree instance level (the default) and
//              not (acceleration property "flatten" "0" on every Group: a callback and a nested
//              Embree scene per level)
//   any-hit    no any-hit program; an empty one and one that ignores nothing on the traced ray
//              type; an empty one on another ray type only
//   geometry   native triangles against the same mesh as user geometry (builder Bvh)
// Each variant's median launch is divided by its baseline's (flat; no any-hit; native). --check
// renders 64x64 and exits 1 unless every variant gives the flat scene's image bit for bit.
#include <tessera/rt.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "common/rt_util.h"

namespace tessera::bench {
namespace {

struct Options {
  unsigned size = 512;  // launch, square
  unsigned grid = 97;   // mesh quads per side (two triangles each)
  std::string devices = "inproc";
  int rounds = 9;
  std::string module = TESSERA_BENCH_MODULE_DIR "/bench_specialize.so";
  bool check = false;
  std::string only;  // variants whose group is this (all when empty)
};

struct Variant {
  std::string group;  // which baseline it is divided by
  std::string name;
  RTobject top = nullptr;
  unsigned ray_type = 0;
  std::vector<double> seconds;
};

class Scene {
 public:
  explicit Scene(const Options& o) : o_(o) {
    Check(nullptr, rtContextCreate(&c_), "rtContextCreate");
    try {
      Build();
    } catch (...) {
      rtContextDestroy(c_);
      throw;
    }
  }
  ~Scene() { rtContextDestroy(c_); }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  std::vector<Variant>& variants() { return variants_; }

  double Launch(const Variant& v) {
    Check(c_, rtVariableSetObject(top_, v.top), "top_object");
    Check(c_, rtVariableSet1ui(ray_type_, v.ray_type), "traced_ray_type");
    const double start = NowSeconds();
    Check(c_, rtContextLaunch2D(c_, 0, o_.size, o_.size), "rtContextLaunch2D");
    return NowSeconds() - start;
  }

  std::vector<float> Image() {
    void* p = nullptr;
    Check(c_, rtBufferMap(output_, &p), "rtBufferMap");
    const float* f = static_cast<const float*>(p);
    std::vector<float> image(f, f + size_t{o_.size} * o_.size * 4);
    Check(c_, rtBufferUnmap(output_), "rtBufferUnmap");
    return image;
  }

 private:
  RTprogram Program(const char* name) {
    RTprogram p = nullptr;
    Check(c_, rtProgramCreateFromPTXFile(c_, o_.module.c_str(), name, &p), name);
    return p;
  }
  RTacceleration Accel(const char* builder, bool flatten = true) {
    RTacceleration a = nullptr;
    Check(c_, rtAccelerationCreate(c_, &a), "rtAccelerationCreate");
    Check(c_, rtAccelerationSetBuilder(a, builder), "rtAccelerationSetBuilder");
    Check(c_, rtAccelerationSetTraverser(a, "Bvh"), "rtAccelerationSetTraverser");
    if (!flatten) Check(c_, rtAccelerationSetProperty(a, "flatten", "0"), "flatten");
    return a;
  }
  RTbuffer Buffer(RTformat format, size_t n, const void* data, size_t bytes) {
    RTbuffer b = nullptr;
    Check(c_, rtBufferCreate(c_, RT_BUFFER_INPUT, &b), "rtBufferCreate");
    Check(c_, rtBufferSetFormat(b, format), "rtBufferSetFormat");
    Check(c_, rtBufferSetSize1D(b, n), "rtBufferSetSize1D");
    void* p = nullptr;
    Check(c_, rtBufferMap(b, &p), "rtBufferMap");
    std::memcpy(p, data, bytes);
    Check(c_, rtBufferUnmap(b), "rtBufferUnmap");
    return b;
  }
  // A material with `shade` for both ray types and `any_hit` (may be null) for ray type
  // `any_hit_type`.
  RTmaterial Material(RTprogram any_hit, unsigned any_hit_type) {
    RTmaterial m = nullptr;
    Check(c_, rtMaterialCreate(c_, &m), "rtMaterialCreate");
    for (unsigned t = 0; t < 2; ++t) {
      Check(c_, rtMaterialSetClosestHitProgram(m, t, shade_), "closest hit");
    }
    if (any_hit != nullptr) {
      Check(c_, rtMaterialSetAnyHitProgram(m, any_hit_type, any_hit), "any hit");
    }
    return m;
  }
  RTgeometrygroup Mesh(RTmaterial material, const char* builder) {
    RTgeometryinstance gi = nullptr;
    Check(c_, rtGeometryInstanceCreate(c_, &gi), "rtGeometryInstanceCreate");
    Check(c_, rtGeometryInstanceSetGeometry(gi, geometry_), "geometry");
    Check(c_, rtGeometryInstanceSetMaterialCount(gi, 1), "material count");
    Check(c_, rtGeometryInstanceSetMaterial(gi, 0, material), "material");
    RTgeometrygroup g = nullptr;
    Check(c_, rtGeometryGroupCreate(c_, &g), "rtGeometryGroupCreate");
    Check(c_, rtGeometryGroupSetAcceleration(g, Accel(builder)), "acceleration");
    Check(c_, rtGeometryGroupSetChildCount(g, 1), "child count");
    Check(c_, rtGeometryGroupSetChild(g, 0, gi), "child");
    return g;
  }
  // Group -> Transform (z moved by 1/4, and back at the innermost level) -> `child`, `levels`
  // times.
  RTobject Nest(RTobject child, int levels, bool flatten) {
    for (int i = 0; i < levels; ++i) {
      RTtransform t = nullptr;
      Check(c_, rtTransformCreate(c_, &t), "rtTransformCreate");
      const float dz = i == 0 ? -0.25f * static_cast<float>(levels - 1) : 0.25f;
      const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, dz, 0, 0, 0, 1};
      Check(c_, rtTransformSetMatrix(t, 0, m, nullptr), "rtTransformSetMatrix");
      Check(c_, rtTransformSetChild(t, child), "rtTransformSetChild");
      RTgroup g = nullptr;
      Check(c_, rtGroupCreate(c_, &g), "rtGroupCreate");
      Check(c_, rtGroupSetAcceleration(g, Accel("Bvh", flatten)), "acceleration");
      Check(c_, rtGroupSetChildCount(g, 1), "child count");
      Check(c_, rtGroupSetChild(g, 0, t), "child");
      child = g;
    }
    return child;
  }

  void Build() {
    UseDevices(c_, o_.devices);
    Check(c_, rtContextSetEntryPointCount(c_, 1), "rtContextSetEntryPointCount");
    Check(c_, rtContextSetRayTypeCount(c_, 2), "rtContextSetRayTypeCount");
    Check(c_, rtContextSetRayGenerationProgram(c_, 0, Program("camera")), "camera");
    for (unsigned t = 0; t < 2; ++t) {
      Check(c_, rtContextSetMissProgram(c_, t, Program("miss")), "miss");
    }
    shade_ = Program("shade");
    Check(c_, rtBufferCreate(c_, RT_BUFFER_OUTPUT, &output_), "rtBufferCreate");
    Check(c_, rtBufferSetFormat(output_, RT_FORMAT_FLOAT4), "rtBufferSetFormat");
    Check(c_, rtBufferSetSize2D(output_, o_.size, o_.size), "rtBufferSetSize2D");
    RTvariable v = nullptr;
    Check(c_, rtContextDeclareVariable(c_, "output", &v), "output");
    Check(c_, rtVariableSetObject(v, output_), "output");
    Check(c_, rtContextDeclareVariable(c_, "top_object", &top_), "top_object");
    Check(c_, rtContextDeclareVariable(c_, "traced_ray_type", &ray_type_), "traced_ray_type");

    // A heightfield whose vertices lie off the pixel centres' lines, so that no ray meets an
    // edge two triangles share (their order would pick the hit).
    const unsigned n = o_.grid;
    std::vector<float> vertices;
    for (unsigned j = 0; j <= n; ++j) {
      for (unsigned i = 0; i <= n; ++i) {
        const float x = -1.0123f + 2.0194f * static_cast<float>(i) / static_cast<float>(n);
        const float y = -1.0071f + 2.0139f * static_cast<float>(j) / static_cast<float>(n);
        vertices.insert(vertices.end(), {x, y, 0.2f * std::sin(5.f * x) * std::cos(4.f * y)});
      }
    }
    std::vector<int> indices;
    for (unsigned j = 0; j < n; ++j) {
      for (unsigned i = 0; i < n; ++i) {
        const int a = static_cast<int>(j * (n + 1) + i), b = a + 1;
        const int c = a + static_cast<int>(n + 1), d = c + 1;
        indices.insert(indices.end(), {a, b, d, a, d, c});
      }
    }
    Check(c_, rtGeometryCreate(c_, &geometry_), "rtGeometryCreate");
    Check(c_, rtGeometrySetPrimitiveCount(geometry_, 2 * n * n), "primitive count");
    Check(c_, rtGeometrySetIntersectionProgram(geometry_, Program("mesh_intersect")), "intersect");
    Check(c_, rtGeometrySetBoundingBoxProgram(geometry_, Program("mesh_bounds")), "bounds");
    RTvariable var = nullptr;
    Check(c_, rtGeometryDeclareVariable(geometry_, "vertex_buffer", &var), "vertex_buffer");
    Check(c_,
          rtVariableSetObject(var, Buffer(RT_FORMAT_FLOAT3, vertices.size() / 3, vertices.data(),
                                          vertices.size() * sizeof(float))),
          "vertex_buffer");
    Check(c_, rtGeometryDeclareVariable(geometry_, "index_buffer", &var), "index_buffer");
    Check(c_,
          rtVariableSetObject(var, Buffer(RT_FORMAT_INT3, indices.size() / 3, indices.data(),
                                          indices.size() * sizeof(int))),
          "index_buffer");

    RTgeometrygroup flat = Mesh(Material(nullptr, 0), "Trbvh");
    variants_.push_back({"levels", "flat", flat, 0, {}});
    for (int levels = 1; levels <= 3; ++levels) {
      for (bool flatten : {true, false}) {
        variants_.push_back({"levels",
                             std::to_string(levels) + (levels == 1 ? " level " : " levels ") +
                                 (flatten ? "flattened" : "nested"),
                             Nest(flat, levels, flatten),
                             0,
                             {}});
      }
    }
    RTprogram empty = Program("any_hit_empty");
    variants_.push_back({"any-hit", "none", flat, 0, {}});
    variants_.push_back(
        {"any-hit", "empty, traced type", Mesh(Material(empty, 0), "Trbvh"), 0, {}});
    variants_.push_back({"any-hit",
                         "accepting, traced type",
                         Mesh(Material(Program("any_hit_accepting"), 0), "Trbvh"),
                         0,
                         {}});
    variants_.push_back(
        {"any-hit", "empty, other type only", Mesh(Material(empty, 1), "Trbvh"), 0, {}});
    variants_.push_back({"geometry", "native triangles", flat, 0, {}});
    variants_.push_back({"geometry", "user geometry", Mesh(Material(nullptr, 0), "Bvh"), 0, {}});
  }

  const Options& o_;
  RTcontext c_ = nullptr;
  RTbuffer output_ = nullptr;
  RTvariable top_ = nullptr, ray_type_ = nullptr;
  RTprogram shade_ = nullptr;
  RTgeometry geometry_ = nullptr;
  std::vector<Variant> variants_;
};

int RunCheck(Options o) {
  o.size = 64;
  Scene scene(o);
  std::vector<float> reference;
  int wrong = 0;
  size_t hits = 0;
  for (Variant& v : scene.variants()) {
    scene.Launch(v);
    const std::vector<float> image = scene.Image();
    if (reference.empty()) {
      reference = image;
      for (size_t i = 0; i < image.size(); i += 4) hits += image[i] != 0.f;
    }
    const bool same = std::memcmp(image.data(), reference.data(), image.size() * 4) == 0;
    std::printf("%-9s %-26s %s\n", v.group.c_str(), v.name.c_str(),
                same ? "same image" : "DIFFERENT IMAGE");
    wrong += !same;
  }
  std::printf("check %ux%u: %zu launch indices hit the mesh, %d variants differ\n", o.size, o.size,
              hits, wrong);
  return wrong == 0 && hits > 0 ? 0 : 1;
}

int Run(const Options& o) {
  Scene scene(o);
  std::printf("heightfield of %u triangles, launch %ux%u on '%s', %d rounds (load average %.2f)\n",
              2 * o.grid * o.grid, o.size, o.size, o.devices.c_str(), o.rounds, LoadAverage());
  std::vector<Variant*> chosen;
  for (Variant& v : scene.variants()) {
    if (o.only.empty() || v.group == o.only) chosen.push_back(&v);
  }
  if (chosen.empty()) throw BenchError("--only " + o.only + ": no such group of variants");
  for (Variant* v : chosen) scene.Launch(*v);  // ship state, build accelerations
  for (int r = 0; r < o.rounds; ++r) {  // rounds alternate variants: drift in load hits all alike
    for (Variant* v : chosen) v->seconds.push_back(scene.Launch(*v));
  }
  double baseline = 0.0;
  std::string group;
  for (Variant* chosen_variant : chosen) {
    Variant& v = *chosen_variant;
    const double median = Median(v.seconds);
    if (v.group != group) {
      group = v.group;
      baseline = median;
    }
    std::printf("%-9s %-26s %8.2f ms  %5.2fx\n", v.group.c_str(), v.name.c_str(), median * 1e3,
                median / baseline);
  }
  std::printf("load average after: %.2f\n", LoadAverage());
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  tessera::bench::Options o;
  CLI::App app{"What nested groups, any-hit programs and user geometry cost a ray."};
  app.add_option("--size", o.size, "launch width and height")->check(CLI::Range(1u, 8192u));
  app.add_option("--grid", o.grid, "mesh quads per side")->check(CLI::Range(1u, 2048u));
  app.add_option("--devices", o.devices, "device spec (inproc, local:N, hosts)");
  app.add_option("--rounds", o.rounds, "timed launches of each variant")
      ->check(CLI::Range(1, 1000));
  app.add_option("--module", o.module, "the bench_specialize program module");
  app.add_flag("--check", o.check, "render 64x64 and compare every variant's image");
  app.add_option("--only", o.only, "one group of variants: levels, any-hit or geometry");
  CLI11_PARSE(app, argc, argv);
  try {
    return o.check ? tessera::bench::RunCheck(o) : tessera::bench::Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-specialize: %s\n", e.what());
    return 1;
  }
}
