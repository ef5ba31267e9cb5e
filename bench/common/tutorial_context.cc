#include "common/tutorial_context.h"

#include <cstring>

#include "common/rt_util.h"
#include "tutorial/camera.h"
#include "tutorial/programs.h"
#include "tutorial/programs/common_structs.h"
#include "tutorial/render.h"
#include "tutorial/scene.h"
#include "tutorial/variables.h"

namespace tessera::bench {
namespace {

// The values of samples/tutorial/render.cc, whose context setup is private to RenderStep: kept
// equal so that the benchmarks render what tessera-tutorial renders.
constexpr unsigned int kRadianceRayType = 0;
constexpr unsigned int kShadowRayType = 1;
constexpr int kMaxDepth = 10;
constexpr RTsize kStackSize = 4096 + 512 * kMaxDepth;

RTbuffer CreateLights(RTcontext context) {
  const BasicLight light = {tutorial::kLightPos, make_float3(1.0f, 1.0f, 1.0f), 1, 0};
  RTbuffer buffer = nullptr;
  Check(context, rtBufferCreate(context, RT_BUFFER_INPUT, &buffer), "rtBufferCreate(lights)");
  Check(context, rtBufferSetFormat(buffer, RT_FORMAT_USER), "rtBufferSetFormat(lights)");
  Check(context, rtBufferSetElementSize(buffer, sizeof(BasicLight)),
        "rtBufferSetElementSize(lights)");
  Check(context, rtBufferSetSize1D(buffer, 1), "rtBufferSetSize1D(lights)");
  void* mapped = nullptr;
  Check(context, rtBufferMap(buffer, &mapped), "rtBufferMap(lights)");
  std::memcpy(mapped, &light, sizeof(light));
  Check(context, rtBufferUnmap(buffer), "rtBufferUnmap(lights)");
  return buffer;
}

}  // namespace

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
  const tutorial::StepConfig& step = tutorial::GetStep(options.step);
  RTcontext c = context_;
  UseDevices(c, options.devices);
  if (options.num_threads > 0) {
    int threads = options.num_threads;  // OptiX 3 takes a non-const pointer
    Check(c,
          rtContextSetAttribute(c, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(threads), &threads),
          "rtContextSetAttribute(CPU_NUM_THREADS)");
  }
  tutorial::ProgramLoader programs(c, tutorial::ResolveModuleDir(options.module_dir));

  Check(c, rtBufferCreate(c, RT_BUFFER_OUTPUT, &output_), "rtBufferCreate(output)");
  Check(c, rtBufferSetFormat(output_, RT_FORMAT_FLOAT4), "rtBufferSetFormat(output)");
  Check(c, rtBufferSetSize2D(output_, static_cast<RTsize>(width_), static_cast<RTsize>(height_)),
        "rtBufferSetSize2D(output)");
  lights_ = CreateLights(c);

  Check(c, rtContextSetRayTypeCount(c, 2), "rtContextSetRayTypeCount");
  Check(c, rtContextSetEntryPointCount(c, 1), "rtContextSetEntryPointCount");
  Check(c, rtContextSetStackSize(c, kStackSize), "rtContextSetStackSize");
  Check(c, rtContextSetExceptionEnabled(c, RT_EXCEPTION_ALL, 1), "rtContextSetExceptionEnabled");
  Check(c, rtContextSetPrintEnabled(c, 1), "rtContextSetPrintEnabled");

  tutorial::Variables vars(c, c, rtContextDeclareVariable, "context");
  vars.Object("output_buffer", output_);
  vars.Object("lights", lights_);
  vars.Int("max_depth", kMaxDepth);
  vars.Uint("radiance_ray_type", kRadianceRayType);
  vars.Uint("shadow_ray_type", kShadowRayType);
  vars.Float("scene_epsilon", 1.e-3f);
  vars.Float("importance_cutoff", 0.01f);
  vars.Float3("ambient_light_color", 0.31f, 0.33f, 0.28f);
  vars.Float3("bg_color", tutorial::kBackgroundColor[0], tutorial::kBackgroundColor[1],
              tutorial::kBackgroundColor[2]);
  vars.Float3("horizon_color", 0.85f, 0.88f, 0.92f);
  vars.Float3("ground_color", 0.3f, 0.3f, 0.3f);
  vars.Float3("bad_color", tutorial::kBadColor[0], tutorial::kBadColor[1], tutorial::kBadColor[2]);
  const tutorial::CameraFrame frame = tutorial::ComputeFrame(
      tutorial::TutorialCamera(), static_cast<float>(width_) / static_cast<float>(height_));
  vars.Float3("eye", frame.eye);
  vars.Float3("U", frame.U);
  vars.Float3("V", frame.V);
  vars.Float3("W", frame.W);

  Check(c,
        rtContextSetRayGenerationProgram(c, 0, programs.Get({"tutorial_camera", "pinhole_camera"})),
        "rtContextSetRayGenerationProgram");
  Check(c, rtContextSetExceptionProgram(c, 0, programs.Get({"tutorial_camera", "exception"})),
        "rtContextSetExceptionProgram");
  Check(c, rtContextSetMissProgram(c, kRadianceRayType, programs.Get(step.miss)),
        "rtContextSetMissProgram");
  tutorial::BuildScene(c, step, programs);

  Check(c, rtContextValidate(c), "rtContextValidate");
  Check(c, rtContextCompile(c), "rtContextCompile");
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
