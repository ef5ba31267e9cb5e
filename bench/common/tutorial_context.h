// The OptiX SDK tutorial scene (samples/tutorial) as a context the benchmarks keep and launch
// repeatedly; tutorial::RenderStep builds one for a single image and destroys it.
#ifndef TESSERA_BENCH_COMMON_TUTORIAL_CONTEXT_H_
#define TESSERA_BENCH_COMMON_TUTORIAL_CONTEXT_H_

#include <tessera/rt.h>

#include <string>
#include <vector>

#include "tutorial/steps.h"

namespace tessera::bench {

struct TutorialOptions {
  std::string devices;  // a device spec: "inproc", "local:2", …
  int num_threads = 0;  // > 0 sets RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS
  int step = tutorial::kLastStep;
  int width = 512;
  int height = 384;
  std::string module_dir;  // empty: tutorial::ResolveModuleDir's choice
};

class TutorialContext {
 public:
  // Builds the scene as tessera-tutorial does. Throws BenchError or tutorial::TutorialError
  // (both carry rtContextGetErrorString's message).
  explicit TutorialContext(const TutorialOptions& options);
  ~TutorialContext();
  TutorialContext(const TutorialContext&) = delete;
  TutorialContext& operator=(const TutorialContext&) = delete;

  void Launch();
  // The float4 output buffer as the launch left it (row 0 at the bottom): for bit comparisons.
  std::vector<float> ReadOutput();
  RTsize OutputBytes() const;

  RTcontext context() const { return context_; }
  // The INPUT buffer of point lights (one BasicLight): the small buffer a host might edit.
  RTbuffer lights() const { return lights_; }

 private:
  void Build(const TutorialOptions& options);

  RTcontext context_ = nullptr;
  RTbuffer output_ = nullptr;
  RTbuffer lights_ = nullptr;
  int width_, height_;
};

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_COMMON_TUTORIAL_CONTEXT_H_
