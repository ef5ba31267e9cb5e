// tessera-bench-tradeoff: the speed/accuracy knobs of docs/accuracy.md measured against each other
// in one run. For each scene and knob: the acceleration build time, the median trace time of the
// probes or the render (and rays/s), leaks and self-intersections per million probe rays, and the
// interior's RMSE against the reference (every accuracy knob on). Prints a table, writes
// tradeoff.csv and, through pareto.py (python3-matplotlib), tradeoff.png.
#include <tessera/rt.h>
#include <tessera/rt_ext.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/rt_util.h"
#include "scenes.h"
#include "tessera/accuracy.h"

namespace tessera::bench {
namespace {

struct Knob {
  const char* name;
  uint32_t flags;
  const char* builder;
  bool fast_math_modules;
};

constexpr uint32_t kReferenceFlags = TESSERA_ACCURACY_WATERTIGHT | TESSERA_ACCURACY_OFFSET_RAYS;

const Knob kKnobs[] = {
    {"reference", kReferenceFlags, "Trbvh", false},  // first: the others' RMSE needs its image
    {"default", 0, "Trbvh", false},
    {"Lbvh", 0, "Lbvh", false},
    {"Bvh", 0, "Bvh", false},
    {"compact", TESSERA_ACCURACY_COMPACT, "Trbvh", false},
    {"robust", TESSERA_ACCURACY_ROBUST, "Trbvh", false},
    {"watertight", TESSERA_ACCURACY_WATERTIGHT, "Trbvh", false},
    {"offset", TESSERA_ACCURACY_OFFSET_RAYS, "Trbvh", false},
    {"fast_math", TESSERA_ACCURACY_FAST_MATH, "Trbvh", true},
};

struct Options {
  std::string devices = "inproc";
  std::string out = "tradeoff";
  int runs = 3;
  int width = 160, height = 120, samples = 8, depth = 4;
  bool check = false;
  bool update_only = false;  // only the refit-against-rebuild timing
};

struct Row {
  std::string scene, knob;
  double build_s = 0, trace_s = 0;
  uint64_t rays = 0;
  double leaks_per_m = -1, self_per_m = -1, rmse = -1;
};

void Set(RTcontext ctx, const char* name, const void* data, size_t bytes, RTformat format,
         size_t count) {
  RTbuffer b = nullptr;
  Check(ctx, rtBufferCreate(ctx, RT_BUFFER_INPUT, &b), "rtBufferCreate");
  Check(ctx, rtBufferSetFormat(b, format), "rtBufferSetFormat");
  Check(ctx, rtBufferSetSize1D(b, count), "rtBufferSetSize1D");
  void* p = nullptr;
  Check(ctx, rtBufferMap(b, &p), "rtBufferMap");
  std::memcpy(p, data, bytes);
  Check(ctx, rtBufferUnmap(b), "rtBufferUnmap");
  RTvariable v = nullptr;
  Check(ctx, rtContextDeclareVariable(ctx, name, &v), name);
  Check(ctx, rtVariableSetObject(v, b), name);
}

RTbuffer Output(RTcontext ctx, const char* name, RTformat format, size_t w, size_t h) {
  RTbuffer b = nullptr;
  Check(ctx, rtBufferCreate(ctx, RT_BUFFER_OUTPUT, &b), "rtBufferCreate");
  Check(ctx, rtBufferSetFormat(b, format), "rtBufferSetFormat");
  if (h == 0) {
    Check(ctx, rtBufferSetSize1D(b, w), "rtBufferSetSize1D");
  } else {
    Check(ctx, rtBufferSetSize2D(b, w, h), "rtBufferSetSize2D");
  }
  RTvariable v = nullptr;
  Check(ctx, rtContextDeclareVariable(ctx, name, &v), name);
  Check(ctx, rtVariableSetObject(v, b), name);
  return b;
}

RTprogram Program(RTcontext ctx, const std::string& module, const char* function) {
  const std::string path = std::string(TESSERA_BENCH_MODULE_DIR) + "/" + module + ".so";
  RTprogram p = nullptr;
  Check(ctx, rtProgramCreateFromPTXFile(ctx, path.c_str(), function, &p), function);
  return p;
}

// A context holding `scene` under `knob`, its programs' entry point 0 ready to launch; `refit`
// sets the acceleration's "refit" property, `accel_out` and `vertices_out` receive them.
RTcontext Build(const TradeoffScene& scene, const Knob& knob, const Options& o, bool refit = false,
                RTacceleration* accel_out = nullptr, RTbuffer* vertices_out = nullptr) {
  RTcontext ctx = nullptr;
  Check(nullptr, rtContextCreate(&ctx), "rtContextCreate");
  UseDevices(ctx, o.devices);
  Check(ctx, tesseraContextSetAccuracy(ctx, knob.flags), "tesseraContextSetAccuracy");
  Check(ctx, rtContextSetEntryPointCount(ctx, 1), "entry points");
  Check(ctx, rtContextSetRayTypeCount(ctx, 2), "ray types");
  const std::string module =
      std::string(scene.interior ? "bench_tradeoff_path" : "bench_tradeoff_probe") +
      (knob.fast_math_modules ? "_fast" : "");
  const auto ntris = scene.indices.size() / 3, nverts = scene.vertices.size() / 3;
  RTbuffer vb = nullptr, ib = nullptr;
  Check(ctx, rtBufferCreate(ctx, RT_BUFFER_INPUT, &vb), "vertices");
  Check(ctx, rtBufferSetFormat(vb, RT_FORMAT_FLOAT3), "vertices");
  Check(ctx, rtBufferSetSize1D(vb, nverts), "vertices");
  void* p = nullptr;
  Check(ctx, rtBufferMap(vb, &p), "vertices");
  std::memcpy(p, scene.vertices.data(), scene.vertices.size() * 4);
  Check(ctx, rtBufferUnmap(vb), "vertices");
  Check(ctx, rtBufferCreate(ctx, RT_BUFFER_INPUT, &ib), "indices");
  Check(ctx, rtBufferSetFormat(ib, RT_FORMAT_UNSIGNED_INT3), "indices");
  Check(ctx, rtBufferSetSize1D(ib, ntris), "indices");
  Check(ctx, rtBufferMap(ib, &p), "indices");
  std::memcpy(p, scene.indices.data(), scene.indices.size() * 4);
  Check(ctx, rtBufferUnmap(ib), "indices");
  RTvariable v = nullptr;
  for (const auto& [name, buffer] :
       {std::pair{"vertex_buffer", vb}, std::pair{"index_buffer", ib}}) {
    if (!scene.interior) break;
    Check(ctx, rtContextDeclareVariable(ctx, name, &v), name);
    Check(ctx, rtVariableSetObject(v, buffer), name);
  }
  RTgeometrytriangles tris = nullptr;
  Check(ctx, rtGeometryTrianglesCreate(ctx, &tris), "rtGeometryTrianglesCreate");
  Check(ctx, rtGeometryTrianglesSetPrimitiveCount(tris, static_cast<unsigned>(ntris)), "count");
  Check(ctx,
        rtGeometryTrianglesSetVertices(tris, static_cast<unsigned>(nverts), vb, 0, 12,
                                       RT_FORMAT_FLOAT3),
        "vertices");
  Check(ctx, rtGeometryTrianglesSetTriangleIndices(tris, ib, 0, 12, RT_FORMAT_UNSIGNED_INT3),
        "indices");
  RTmaterial material = nullptr;
  Check(ctx, rtMaterialCreate(ctx, &material), "rtMaterialCreate");
  Check(ctx,
        rtMaterialSetClosestHitProgram(
            material, 0,
            Program(ctx, module, scene.interior ? "path_closest_hit" : "probe_closest_hit")),
        "closest hit");
  if (!scene.interior) {
    Check(ctx,
          rtMaterialSetClosestHitProgram(material, 1, Program(ctx, module, "shadow_closest_hit")),
          "shadow closest hit");
  }
  RTgeometryinstance instance = nullptr;
  Check(ctx, rtGeometryInstanceCreate(ctx, &instance), "instance");
  Check(ctx, rtGeometryInstanceSetGeometryTriangles(instance, tris), "instance");
  Check(ctx, rtGeometryInstanceSetMaterialCount(instance, 1), "instance");
  Check(ctx, rtGeometryInstanceSetMaterial(instance, 0, material), "instance");
  RTacceleration accel = nullptr;
  Check(ctx, rtAccelerationCreate(ctx, &accel), "acceleration");
  Check(ctx, rtAccelerationSetBuilder(accel, knob.builder), knob.builder);
  Check(ctx, rtAccelerationSetTraverser(accel, "Bvh"), "traverser");
  if (refit) Check(ctx, rtAccelerationSetProperty(accel, "refit", "1"), "refit");
  if (accel_out != nullptr) *accel_out = accel;
  if (vertices_out != nullptr) *vertices_out = vb;
  RTgeometrygroup group = nullptr;
  Check(ctx, rtGeometryGroupCreate(ctx, &group), "group");
  Check(ctx, rtGeometryGroupSetAcceleration(group, accel), "group");
  Check(ctx, rtGeometryGroupSetChildCount(group, 1), "group");
  Check(ctx, rtGeometryGroupSetChild(group, 0, instance), "group");
  Check(ctx, rtContextDeclareVariable(ctx, "top_object", &v), "top_object");
  Check(ctx, rtVariableSetObject(v, group), "top_object");
  Check(ctx, rtContextDeclareVariable(ctx, "scene_epsilon", &v), "scene_epsilon");
  Check(ctx, rtVariableSet1f(v, 1e-4f), "scene_epsilon");
  if (scene.interior) {
    Check(ctx, rtContextSetRayGenerationProgram(ctx, 0, Program(ctx, module, "render")), "rg");
    Check(ctx, rtContextSetMissProgram(ctx, 0, Program(ctx, module, "path_miss")), "miss");
    Set(ctx, "albedo", scene.albedo.data(), scene.albedo.size() * 4, RT_FORMAT_FLOAT3, ntris);
    Set(ctx, "emission", scene.emission.data(), scene.emission.size() * 4, RT_FORMAT_FLOAT3, ntris);
    Check(ctx, rtContextDeclareVariable(ctx, "samples", &v), "samples");
    Check(ctx, rtVariableSet1ui(v, static_cast<unsigned>(o.samples)), "samples");
    Check(ctx, rtContextDeclareVariable(ctx, "max_depth", &v), "max_depth");
    Check(ctx, rtVariableSet1ui(v, static_cast<unsigned>(o.depth)), "max_depth");
    Check(ctx, rtContextDeclareVariable(ctx, "eye", &v), "eye");
    Check(ctx, rtVariableSet3f(v, scene.eye[0], scene.eye[1], scene.eye[2]), "eye");
  } else {
    Check(ctx, rtContextSetRayGenerationProgram(ctx, 0, Program(ctx, module, "probe_shoot")), "rg");
    std::vector<float> rays, dirs;
    for (const Probe& pr : scene.probes) {
      rays.insert(rays.end(), {pr.origin[0], pr.origin[1], pr.origin[2], 0.f, pr.direction[0],
                               pr.direction[1], pr.direction[2], 1e30f});
      dirs.insert(dirs.end(), {pr.secondary[0], pr.secondary[1], pr.secondary[2], 0.f});
    }
    Set(ctx, "rays", rays.data(), rays.size() * 4, RT_FORMAT_FLOAT4, rays.size() / 4);
    Set(ctx, "secondary_dirs", dirs.data(), dirs.size() * 4, RT_FORMAT_FLOAT4, dirs.size() / 4);
  }
  return ctx;
}

template <typename T>
std::vector<T> Read(RTcontext ctx, RTbuffer b, size_t count) {
  std::vector<T> out(count);
  void* p = nullptr;
  Check(ctx, rtBufferMap(b, &p), "rtBufferMap");
  std::memcpy(out.data(), p, count * sizeof(T));
  Check(ctx, rtBufferUnmap(b), "rtBufferUnmap");
  return out;
}

Row Measure(const TradeoffScene& scene, const Knob& knob, const Options& o,
            std::vector<float>* image, const std::vector<float>* reference) {
  Row row{scene.name, knob.name};
  RTcontext ctx = Build(scene, knob, o);
  RTbuffer results = nullptr, pixels = nullptr, counts = nullptr;
  const size_t n = scene.probes.size();
  if (scene.interior) {
    pixels = Output(ctx, "image", RT_FORMAT_FLOAT4, o.width, o.height);
    counts = Output(ctx, "ray_counts", RT_FORMAT_UNSIGNED_INT, o.width, o.height);
  } else {
    results = Output(ctx, "probe_results", RT_FORMAT_UNSIGNED_INT4, n, 0);
  }
  // The first, empty launch builds the acceleration (and starts the devices: a second empty
  // launch would build nothing, so the build is what the first costs beyond it).
  double t0 = NowSeconds();
  Check(ctx, rtContextLaunch2D(ctx, 0, 0, 0), "build launch");
  const double first = NowSeconds() - t0;
  t0 = NowSeconds();
  Check(ctx, rtContextLaunch2D(ctx, 0, 0, 0), "empty launch");
  row.build_s = std::max(0.0, first - (NowSeconds() - t0));  // timer noise can go below 0
  std::vector<double> times;
  for (int r = 0; r < o.runs; ++r) {
    t0 = NowSeconds();
    if (scene.interior) {
      Check(ctx, rtContextLaunch2D(ctx, 0, o.width, o.height), "render");
    } else {
      Check(ctx, rtContextLaunch1D(ctx, 0, n), "probes");
    }
    times.push_back(NowSeconds() - t0);
  }
  row.trace_s = Median(times);
  if (scene.interior) {
    const size_t pix = size_t(o.width) * o.height;
    for (unsigned c : Read<unsigned>(ctx, counts, pix)) row.rays += c;
    *image = Read<float>(ctx, pixels, 4 * pix);
    if (reference != nullptr) {
      double sum = 0;
      for (size_t i = 0; i < image->size(); i += 4) {
        for (int k = 0; k < 3; ++k) {
          const double d = (*image)[i + k] - (*reference)[i + k];
          sum += d * d;
        }
      }
      row.rmse = std::sqrt(sum / (3.0 * pix));
    }
  } else {
    const std::vector<uint32_t> r = Read<uint32_t>(ctx, results, 4 * n);
    size_t leaks = 0, self = 0, secondary = 0;
    for (size_t i = 0; i < n; ++i) {
      if (i < scene.leak_probes) {
        leaks += r[4 * i] == 0 ? 1 : 0;
      } else if (r[4 * i] != 0) {
        ++secondary;
        // Only a secondary ray from the face aimed at is sure to have nothing to hit: rounding far
        // from the origin lets some probes land on a neighbour.
        if (r[4 * i + 2] == scene.probes[i].target) self += r[4 * i + 1];
      }
    }
    row.rays = n + secondary;
    row.leaks_per_m = 1e6 * static_cast<double>(leaks) / static_cast<double>(scene.leak_probes);
    row.self_per_m = secondary == 0 ? 0 : 1e6 * static_cast<double>(self) / secondary;
  }
  rtContextDestroy(ctx);
  return row;
}

// Seconds the launch after an update of every vertex (the mesh grown by 1%) takes, the median of
// `o.runs` updates: with the acceleration built anew or refitted (`refit`); or, for `rebuild`
// false, the launch after as many bytes of an unrelated buffer changed (what shipping them and the
// launch cost without a build).
double UpdateSeconds(const TradeoffScene& scene, bool rebuild, bool refit, const Options& o) {
  RTacceleration accel = nullptr;
  RTbuffer vertices = nullptr;
  RTcontext ctx = Build(scene, kKnobs[1], o, refit, &accel, &vertices);
  Output(ctx, "probe_results", RT_FORMAT_UNSIGNED_INT4, scene.probes.size(), 0);
  if (!rebuild) {
    Set(ctx, "unrelated", scene.vertices.data(), scene.vertices.size() * 4, RT_FORMAT_FLOAT3,
        scene.vertices.size() / 3);
    RTvariable v = nullptr;
    Check(ctx, rtContextQueryVariable(ctx, "unrelated", &v), "unrelated");
    RTobject object = nullptr;
    Check(ctx, rtVariableGetObject(v, &object), "unrelated");
    vertices = static_cast<RTbuffer>(object);
  }
  Check(ctx, rtContextLaunch2D(ctx, 0, 0, 0), "build launch");
  std::vector<double> times;
  std::vector<float> v = scene.vertices;
  for (int r = 0; r < o.runs; ++r) {
    for (float& x : v) x *= 1.01f;
    void* p = nullptr;
    Check(ctx, rtBufferMap(vertices, &p), "map vertices");
    std::memcpy(p, v.data(), v.size() * sizeof(float));
    Check(ctx, rtBufferUnmap(vertices), "unmap vertices");
    if (rebuild) Check(ctx, rtAccelerationMarkDirty(accel), "rtAccelerationMarkDirty");
    const double t0 = NowSeconds();
    Check(ctx, rtContextLaunch2D(ctx, 0, 0, 0), "update launch");
    times.push_back(NowSeconds() - t0);
  }
  rtContextDestroy(ctx);
  return Median(times);
}

std::string Number(double x, const char* format) {
  if (x < 0) return "-";
  char text[32];
  std::snprintf(text, sizeof(text), format, x);
  return text;
}

int Run(const Options& o) {
  std::vector<TradeoffScene> scenes;
  if (o.update_only) {
  } else if (o.check) {
    scenes.push_back(ClosedSphere("closed sphere (level 3)", 3, {0, 0, 0}, 2000, 2000));
    scenes.push_back(ClosedSphere("far sphere (1e5)", 3, {1e5, -7e4, 4e4}, 2000, 2000));
    scenes.push_back(Interior(4, {3e3, 1e3, -2e3}));
  } else {
    scenes.push_back(
        ClosedSphere("closed sphere (81,920 triangles)", 6, {0, 0, 0}, 200000, 100000));
    scenes.push_back(
        ClosedSphere("sphere 1e5 from the origin", 5, {1e5, -7e4, 4e4}, 200000, 100000));
    scenes.push_back(Interior(24, {3e3, 1e3, -2e3}));
  }
  std::printf("tessera-bench-tradeoff: devices %s, %d runs (median), load %.2f\n",
              o.devices.c_str(), o.runs, LoadAverage());
  std::printf("%-34s %-11s %9s %9s %8s %7s %10s %10s %8s\n", "scene", "knob", "build ms",
              "trace ms", "Mrays/s", "ratio", "leaks/M", "self/M", "RMSE");
  std::vector<Row> rows;
  int failures = 0;
  for (const TradeoffScene& scene : scenes) {
    std::vector<float> reference, image;
    double default_trace = 0;
    // Untimed: loads the program modules and starts the devices, which the first knob would pay.
    Measure(scene, kKnobs[1], o, &image, nullptr);
    for (const Knob& knob : kKnobs) {
      Row row = Measure(scene, knob, o, &image, reference.empty() ? nullptr : &reference);
      if (std::string(knob.name) == "reference") reference = image;
      if (std::string(knob.name) == "default") default_trace = row.trace_s;
      const double ratio = default_trace > 0 ? row.trace_s / default_trace : -1;
      std::printf("%-34s %-11s %9.1f %9.1f %8.2f %7s %10s %10s %8s\n", row.scene.c_str(),
                  row.knob.c_str(), 1e3 * row.build_s, 1e3 * row.trace_s,
                  row.rays / row.trace_s / 1e6, Number(ratio, "%.3f").c_str(),
                  Number(row.leaks_per_m, "%.0f").c_str(), Number(row.self_per_m, "%.0f").c_str(),
                  Number(row.rmse, "%.5f").c_str());
      const bool exact =
          std::string(knob.name) == "reference" || std::string(knob.name) == "watertight";
      if (exact && row.leaks_per_m > 0) {
        std::fprintf(stderr, "FAIL: %s leaks with %s\n", scene.name.c_str(), knob.name);
        ++failures;
      }
      if ((std::string(knob.name) == "reference" || std::string(knob.name) == "offset") &&
          row.self_per_m > 0) {
        std::fprintf(stderr, "FAIL: %s self-intersects with %s\n", scene.name.c_str(), knob.name);
        ++failures;
      }
      rows.push_back(row);
    }
  }
  if (o.update_only || !scenes.empty()) {
    const TradeoffScene sphere =
        o.check ? scenes.front() : ClosedSphere("sphere of 327,680 triangles", 7, {0, 0, 0}, 0, 0);
    const double ship = UpdateSeconds(sphere, false, false, o);
    const double rebuild = UpdateSeconds(sphere, true, false, o) - ship;
    const double refit = UpdateSeconds(sphere, true, true, o) - ship;
    std::printf(
        "update of every vertex of a %s (beyond the %.1f ms of shipping them): rebuild "
        "%.1f ms, refit (\"refit\" \"1\") %.1f ms, ratio %.3f\n",
        sphere.name.c_str(), 1e3 * ship, 1e3 * rebuild, 1e3 * refit,
        rebuild > 0 ? refit / rebuild : 0.0);
  }
  if (o.update_only) return 0;
  std::filesystem::create_directories(o.out);
  const std::string csv = o.out + "/tradeoff.csv";
  std::ofstream f(csv);
  f << "scene,knob,build_s,trace_s,rays,leaks_per_million,self_per_million,rmse\n";
  for (const Row& r : rows) {
    f << '"' << r.scene << "\"," << r.knob << ',' << r.build_s << ',' << r.trace_s << ',' << r.rays
      << ',' << r.leaks_per_m << ',' << r.self_per_m << ',' << r.rmse << '\n';
  }
  f.close();
  std::printf("table: %s\n", csv.c_str());
  if (!o.check) {
    const std::string png = o.out + "/tradeoff.png";
    const std::string command =
        std::string("python3 ") + TESSERA_BENCH_PARETO_SCRIPT + " " + csv + " " + png;
    if (std::system(command.c_str()) == 0) {
      std::printf("plot: %s\n", png.c_str());
    } else {
      std::printf(
          "plot: not drawn (needs python3-matplotlib: apt-get install python3-matplotlib)\n");
    }
  }
  // The headline: what watertight traversal costs on the first scene.
  double base = 0, watertight = 0;
  for (const Row& r : rows) {
    if (r.scene != rows.front().scene) continue;
    if (r.knob == "default") base = r.trace_s;
    if (r.knob == "watertight") watertight = r.trace_s;
  }
  std::printf("tradeoff_watertight_trace_ratio=%.3f\n", base > 0 ? watertight / base : 0.0);
  return failures == 0 ? 0 : 1;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  tessera::bench::Options o;
  CLI::App app{"Speed against accuracy: every knob of docs/accuracy.md on three scenes"};
  app.add_option("--devices", o.devices, "device spec (inproc, local:N, ...)");
  app.add_option("--out", o.out, "directory for tradeoff.csv and tradeoff.png");
  app.add_option("--runs", o.runs, "timed launches per knob (the median is reported)");
  app.add_option("--samples", o.samples, "samples per pixel of the interior");
  app.add_flag("--check", o.check, "small scenes; fail if watertight leaks or offsets self-hit");
  app.add_flag("--update-only", o.update_only, "only time an update: rebuild against refit");
  CLI11_PARSE(app, argc, argv);
  try {
    return tessera::bench::Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-tradeoff: %s\n", e.what());
    return 1;
  }
}
