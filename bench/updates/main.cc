// tessera-bench-updates: how long a launch takes after a small change to a scene of many geometry
// instances, measured in one run against a launch after no change and one after a change that
// makes devices bind every program again (docs/devices.md: deltas of values and of the graph keep
// the launch plan). Changes, in alternating rounds:
//   unchanged       nothing
//   context value   the context variable `frame`
//   instance value  one instance's `tint`
//   transform       the Transform above all instances, moved
//   rebuild         a variable declared on one instance (every program is bound again)
// The last line is update_vs_rebuild=<median launch after a value or transform change / median
// launch after a rebuild>. --check runs 64 instances and exits 1 when a launch index holds
// anything but its instance's tint plus the frame.
#include <tessera/rt.h>
#include <tessera/rt_ext.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "common/rt_util.h"
#include "tessera/cli_checks.h"

namespace tessera::bench {
namespace {

struct Options {
  unsigned instances = 16384;
  unsigned width = 64;  // launch indices, one ray each, along the row of instances
  int rounds = 9;
  std::string devices = "inproc";
  std::string module = TESSERA_BENCH_MODULE_DIR "/bench_updates.so";
  bool check = false;
};

enum Change { kUnchanged, kContextValue, kInstanceValue, kTransform, kRebuild, kChanges };
constexpr const char* kChangeNames[kChanges] = {"unchanged", "context value", "instance value",
                                                "transform", "rebuild"};

class RowScene {
 public:
  explicit RowScene(const Options& o) : o_(o), tints_(o.instances) {
    Check(nullptr, rtContextCreate(&c_), "rtContextCreate");
    UseDevices(c_, o.devices);
    Check(c_, rtContextSetEntryPointCount(c_, 1), "rtContextSetEntryPointCount");
    Check(c_, rtContextSetRayTypeCount(c_, 1), "rtContextSetRayTypeCount");
    Check(c_, rtContextSetRayGenerationProgram(c_, 0, Program("row_raygen")), "ray generation");
    Check(c_, rtContextSetMissProgram(c_, 0, Program("row_miss")), "miss");
    frame_ = ContextVar("frame");
    Check(c_, rtVariableSet1f(frame_, 0.f), "frame");
    RTgeometry geometry = nullptr;
    Check(c_, rtGeometryCreate(c_, &geometry), "rtGeometryCreate");
    Check(c_, rtGeometrySetPrimitiveCount(geometry, 1), "primitive count");
    Check(c_, rtGeometrySetIntersectionProgram(geometry, Program("square_intersect")), "intersect");
    Check(c_, rtGeometrySetBoundingBoxProgram(geometry, Program("square_bounds")), "bounds");
    RTmaterial material = nullptr;
    Check(c_, rtMaterialCreate(c_, &material), "rtMaterialCreate");
    Check(c_, rtMaterialSetClosestHitProgram(material, 0, Program("row_closest_hit")), "hit");
    RTgeometrygroup group = nullptr;
    Check(c_, rtGeometryGroupCreate(c_, &group), "rtGeometryGroupCreate");
    Check(c_, rtGeometryGroupSetAcceleration(group, Accel()), "acceleration");
    Check(c_, rtGeometryGroupSetChildCount(group, o.instances), "child count");
    instances_.resize(o.instances);
    tint_vars_.resize(o.instances);
    for (unsigned i = 0; i < o.instances; ++i) {
      RTgeometryinstance& gi = instances_[i];
      Check(c_, rtGeometryInstanceCreate(c_, &gi), "rtGeometryInstanceCreate");
      Check(c_, rtGeometryInstanceSetGeometry(gi, geometry), "geometry");
      Check(c_, rtGeometryInstanceSetMaterialCount(gi, 1), "material count");
      Check(c_, rtGeometryInstanceSetMaterial(gi, 0, material), "material");
      RTvariable center = nullptr;
      Check(c_, rtGeometryInstanceDeclareVariable(gi, "center", &center), "center");
      Check(c_, rtVariableSet1f(center, 2.f * i), "center");
      Check(c_, rtGeometryInstanceDeclareVariable(gi, "tint", &tint_vars_[i]), "tint");
      tints_[i] = 1.f + static_cast<float>(i % 7);
      Check(c_, rtVariableSet1f(tint_vars_[i], tints_[i]), "tint");
      Check(c_, rtGeometryGroupSetChild(group, i, gi), "child");
    }
    Check(c_, rtTransformCreate(c_, &transform_), "rtTransformCreate");
    Check(c_, rtTransformSetChild(transform_, group), "transform child");
    RTgroup top = nullptr;
    Check(c_, rtGroupCreate(c_, &top), "rtGroupCreate");
    Check(c_, rtGroupSetAcceleration(top, Accel()), "acceleration");
    Check(c_, rtGroupSetChildCount(top, 1), "child count");
    Check(c_, rtGroupSetChild(top, 0, transform_), "child");
    Check(c_, rtVariableSetObject(ContextVar("top_object"), top), "top_object");
    Check(c_, rtBufferCreate(c_, RT_BUFFER_OUTPUT, &result_), "rtBufferCreate");
    Check(c_, rtBufferSetFormat(result_, RT_FORMAT_FLOAT), "format");
    Check(c_, rtBufferSetSize2D(result_, o.width, 1), "size");
    Check(c_, rtVariableSetObject(ContextVar("result"), result_), "result");
  }
  ~RowScene() { rtContextDestroy(c_); }
  RowScene(const RowScene&) = delete;
  RowScene& operator=(const RowScene&) = delete;

  // Makes change `what` (round `r` picks the values) and returns the seconds its launch took.
  double Launch(Change what, int r) {
    switch (what) {
      case kUnchanged:
        break;
      case kContextValue:
        frame_value_ = 0.25f * static_cast<float>(r % 4);
        Check(c_, rtVariableSet1f(frame_, frame_value_), "frame");
        break;
      case kInstanceValue: {
        const unsigned i = static_cast<unsigned>(r) % std::min(o_.instances, o_.width);
        tints_[i] += 1.f;
        Check(c_, rtVariableSet1f(tint_vars_[i], tints_[i]), "tint");
        break;
      }
      case kTransform: {
        // Up and down within the squares: every ray still hits its own.
        const float y = 0.01f * static_cast<float>(r % 5);
        const float m[16] = {1, 0, 0, 0, 0, 1, 0, y, 0, 0, 1, 0, 0, 0, 0, 1};
        Check(c_, rtTransformSetMatrix(transform_, 0, m, nullptr), "rtTransformSetMatrix");
        break;
      }
      case kRebuild: {
        RTvariable v = nullptr;
        const std::string name = "unused_" + std::to_string(declared_++);
        Check(c_, rtGeometryInstanceDeclareVariable(instances_[0], name.c_str(), &v), name);
        Check(c_, rtVariableSet1f(v, 0.f), name);
        break;
      }
      case kChanges:
        break;
    }
    const double start = NowSeconds();
    Check(c_, rtContextLaunch2D(c_, 0, o_.width, 1), "rtContextLaunch2D");
    return NowSeconds() - start;
  }

  // Every launch index holds its instance's tint plus the frame (a miss writes -1000 + frame).
  void Verify(const char* after) {
    void* p = nullptr;
    Check(c_, rtBufferMap(result_, &p), "rtBufferMap");
    std::vector<float> got(static_cast<const float*>(p), static_cast<const float*>(p) + o_.width);
    Check(c_, rtBufferUnmap(result_), "rtBufferUnmap");
    for (unsigned x = 0; x < o_.width; ++x) {
      const float want = (x < o_.instances ? tints_[x] : -1000.f) + frame_value_;
      if (got[x] != want) {
        throw BenchError("after a " + std::string(after) + " change, launch index " +
                         std::to_string(x) + " holds " + std::to_string(got[x]) + ", not " +
                         std::to_string(want));
      }
    }
  }

 private:
  RTprogram Program(const char* function) {
    RTprogram p = nullptr;
    Check(c_, rtProgramCreateFromPTXFile(c_, o_.module.c_str(), function, &p), function);
    return p;
  }
  RTvariable ContextVar(const char* name) {
    RTvariable v = nullptr;
    Check(c_, rtContextDeclareVariable(c_, name, &v), name);
    return v;
  }
  RTacceleration Accel() {
    RTacceleration a = nullptr;
    Check(c_, rtAccelerationCreate(c_, &a), "rtAccelerationCreate");
    Check(c_, rtAccelerationSetBuilder(a, "Bvh"), "builder");
    Check(c_, rtAccelerationSetTraverser(a, "Bvh"), "traverser");
    return a;
  }

  const Options& o_;
  RTcontext c_ = nullptr;
  RTvariable frame_ = nullptr;
  float frame_value_ = 0.f;
  RTtransform transform_ = nullptr;
  RTbuffer result_ = nullptr;
  std::vector<RTgeometryinstance> instances_;
  std::vector<RTvariable> tint_vars_;
  std::vector<float> tints_;
  int declared_ = 0;
};

int Run(const Options& o) {
  const double load = LoadAverage();
  RowScene scene(o);
  const double first = scene.Launch(kUnchanged, 0);
  scene.Verify("first launch");
  std::vector<double> seconds[kChanges];
  // Rounds alternate the changes, so that the machine's drift reaches each alike.
  for (int r = 0; r < o.rounds; ++r) {
    for (int k = 0; k < kChanges; ++k) {
      const Change what = static_cast<Change>(k);
      seconds[k].push_back(scene.Launch(what, r));
      scene.Verify(kChangeNames[k]);
    }
  }
  if (o.check) {
    std::printf("check passed: %u instances, %d rounds of every change\n", o.instances, o.rounds);
    return 0;
  }
  std::printf("%u geometry instances under a Transform, %u rays, devices %s, load average %.2f\n",
              o.instances, o.width, o.devices.c_str(), load);
  std::printf("first launch (builds everything): %.1f ms\n", first * 1e3);
  double median[kChanges];
  for (int k = 0; k < kChanges; ++k) median[k] = Median(seconds[k]);
  std::printf("%-16s %10s %14s %12s\n", "change", "median ms", "vs unchanged", "vs rebuild");
  for (int k = 0; k < kChanges; ++k) {
    std::printf("%-16s %10.2f %14.2f %12.3f\n", kChangeNames[k], median[k] * 1e3,
                median[k] / median[kUnchanged], median[k] / median[kRebuild]);
  }
  std::vector<double> updates;
  for (Change k : {kContextValue, kInstanceValue, kTransform}) {
    updates.insert(updates.end(), seconds[k].begin(), seconds[k].end());
  }
  std::printf("update_vs_rebuild=%.3f\n", Median(updates) / median[kRebuild]);
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  using namespace tessera::bench;
  Options o;
  CLI::App app{"Launches after small changes to a scene of many geometry instances"};
  app.add_option("--instances", o.instances, "geometry instances")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--width", o.width, "launch indices (one ray each)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--rounds", o.rounds, "timed launches of each change (median)")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--devices", o.devices, "device spec")->capture_default_str();
  app.add_option("--module", o.module, "program module built from updates.cu")
      ->capture_default_str();
  app.add_flag("--check", o.check,
               "64 instances, two rounds; exit 1 unless every launch index is right");
  CLI11_PARSE(app, argc, argv);
  if (o.check) {
    o.instances = 64;
    o.rounds = 2;
  }
  try {
    return Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-updates: %s\n", e.what());
    return 1;
  }
}
