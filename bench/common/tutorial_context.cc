#include "common/tutorial_context.h"

#include <cstring>

#include "common/rt_util.h"
#include "tutorial/render.h"

namespace tessera::bench {

TutorialContext::TutorialContext(const TutorialOptions& options)
    : width_(options.width), height_(options.height) {
  if (width_ <= 0 || height_ <= 0) throw BenchError("image size must be positive");
  Check(nullptr, rtContextCreate(&context_), "rtContextCreate");
  try {
    Build(options);
  } catch (...) {
    // The destructor does not run for a constructor that throws.
    rtContextDestroy(context_);
    throw;
  }
}

void TutorialContext::Build(const TutorialOptions& options) {
  RTcontext c = context_;
  UseDevices(c, options.devices);
  if (options.num_threads > 0) {
    int threads = options.num_threads;  // OptiX 3 takes a non-const pointer
    Check(c,
          rtContextSetAttribute(c, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(threads), &threads),
          "rtContextSetAttribute(CPU_NUM_THREADS)");
  }
  tutorial::RenderOptions render;
  render.step = options.step;
  render.width = width_;
  render.height = height_;
  render.module_dir = tutorial::ResolveModuleDir(options.module_dir);
  const tutorial::StepBuffers buffers = tutorial::SetUpStep(c, render);
  output_ = buffers.output;
  lights_ = buffers.lights;
}

TutorialContext::~TutorialContext() {
  if (context_ != nullptr) rtContextDestroy(context_);
}

void TutorialContext::Launch() {
  Check(context_,
        rtContextLaunch2D(context_, 0, static_cast<RTsize>(width_), static_cast<RTsize>(height_)),
        "rtContextLaunch2D");
}

RTsize TutorialContext::OutputBytes() const {
  return static_cast<RTsize>(width_) * static_cast<RTsize>(height_) * 4 * sizeof(float);
}

std::vector<float> TutorialContext::ReadOutput() {
  std::vector<float> pixels(OutputBytes() / sizeof(float));
  void* mapped = nullptr;
  Check(context_, rtBufferMap(output_, &mapped), "rtBufferMap(output)");
  std::memcpy(pixels.data(), mapped, OutputBytes());
  Check(context_, rtBufferUnmap(output_), "rtBufferUnmap(output)");
  return pixels;
}

}  // namespace tessera::bench
