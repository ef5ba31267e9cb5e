#include "tutorial/render.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "tessera/rt.h"
#include "tessera/rt_ext.h"
#include "tutorial/camera.h"
#include "tutorial/programs.h"
#include "tutorial/programs/common_structs.h"
#include "tutorial/rt_check.h"
#include "tutorial/scene.h"
#include "tutorial/steps.h"
#include "tutorial/variables.h"

#ifndef TESSERA_TUTORIAL_MODULE_DIR
#error "TESSERA_TUTORIAL_MODULE_DIR must name the build's program module directory"
#endif

namespace tessera::tutorial {
namespace {

constexpr unsigned int kRadianceRayType = 0;
constexpr unsigned int kShadowRayType = 1;
constexpr int kMaxDepth = 10;
// Deep enough for kMaxDepth nested reflection/refraction rays.
constexpr RTsize kStackSize = 4096 + 512 * kMaxDepth;

// Long renders say how far they got: the timeout callback runs on the launching thread every
// kProgressSeconds (so short renders print nothing) and takes no argument, hence the static.
constexpr double kProgressSeconds = 2.0;
RTcontext g_rendering = nullptr;
int SayProgress() {
  RTsize done = 0, total = 0;
  if (tesseraContextGetLaunchProgress(g_rendering, &done, &total) == RT_SUCCESS && total > 0) {
    std::fprintf(stderr, "tessera-tutorial: %llu%% rendered (%llu of %llu tiles)\n",
                 static_cast<unsigned long long>(100 * done / total),
                 static_cast<unsigned long long>(done), static_cast<unsigned long long>(total));
  }
  return 0;  // never cancels
}

// Owns the context; destroying it destroys every object created in it.
class ContextHolder {
 public:
  ContextHolder() { RT_CHECK(nullptr, rtContextCreate(&context_)); }
  ~ContextHolder() { rtContextDestroy(context_); }
  ContextHolder(const ContextHolder&) = delete;
  ContextHolder& operator=(const ContextHolder&) = delete;
  RTcontext get() const { return context_; }

 private:
  RTcontext context_ = nullptr;
};

RTbuffer CreateOutputBuffer(RTcontext context, int width, int height) {
  RTbuffer buffer = nullptr;
  RT_CHECK(context, rtBufferCreate(context, RT_BUFFER_OUTPUT, &buffer));
  RT_CHECK(context, rtBufferSetFormat(buffer, RT_FORMAT_FLOAT4));
  RT_CHECK(context,
           rtBufferSetSize2D(buffer, static_cast<RTsize>(width), static_cast<RTsize>(height)));
  return buffer;
}

RTbuffer CreateLights(RTcontext context) {
  const BasicLight lights[] = {
      {kLightPos, make_float3(1.0f, 1.0f, 1.0f), 1, 0},
  };
  RTbuffer buffer = nullptr;
  RT_CHECK(context, rtBufferCreate(context, RT_BUFFER_INPUT, &buffer));
  RT_CHECK(context, rtBufferSetFormat(buffer, RT_FORMAT_USER));
  RT_CHECK(context, rtBufferSetElementSize(buffer, sizeof(BasicLight)));
  RT_CHECK(context, rtBufferSetSize1D(buffer, sizeof(lights) / sizeof(lights[0])));
  void* mapped = nullptr;
  RT_CHECK(context, rtBufferMap(buffer, &mapped));
  std::memcpy(mapped, lights, sizeof(lights));
  RT_CHECK(context, rtBufferUnmap(buffer));
  return buffer;
}

// A sampler of `buffer` with linear filtering and normalized coordinates, repeating along the
// dimensions in `repeat` and clamping along the others.
RTtexturesampler CreateSampler(RTcontext context, RTbuffer buffer, unsigned dimensions,
                               const bool repeat[3]) {
  RTtexturesampler sampler = nullptr;
  RT_CHECK(context, rtTextureSamplerCreate(context, &sampler));
  for (unsigned d = 0; d < dimensions; ++d) {
    RT_CHECK(context, rtTextureSamplerSetWrapMode(
                          sampler, d, repeat[d] ? RT_WRAP_REPEAT : RT_WRAP_CLAMP_TO_EDGE));
  }
  RT_CHECK(context, rtTextureSamplerSetFilteringModes(sampler, RT_FILTER_LINEAR, RT_FILTER_LINEAR,
                                                      RT_FILTER_NONE));
  RT_CHECK(context,
           rtTextureSamplerSetIndexingMode(sampler, RT_TEXTURE_INDEX_NORMALIZED_COORDINATES));
  RT_CHECK(context, rtTextureSamplerSetReadMode(sampler, RT_TEXTURE_READ_NORMALIZED_FLOAT));
  RT_CHECK(context, rtTextureSamplerSetMaxAnisotropy(sampler, 1.0f));
  RT_CHECK(context, rtTextureSamplerSetBuffer(sampler, 0, 0, buffer));
  return sampler;
}

// The environment map, from `options.load_envmap`: around u, clamped at the poles.
RTtexturesampler CreateEnvmap(RTcontext context, const RenderOptions& options) {
  const bool repeat[3] = {true, false, false};
  return CreateSampler(context, options.load_envmap(context, options.envmap), 2, repeat);
}

// A value in [0, 1) for each texel of the noise texture: a fixed integer hash of its position,
// so that every run and every device set renders the same rust.
float NoiseValue(unsigned x, unsigned y, unsigned z) {
  unsigned h = x * 0x8da6b343u ^ y * 0xd8163841u ^ z * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

// The SDK tutorial's 64^3 noise texture, repeating in every dimension.
RTtexturesampler CreateNoise(RTcontext context) {
  constexpr unsigned kSize = 64;
  RTbuffer buffer = nullptr;
  RT_CHECK(context, rtBufferCreate(context, RT_BUFFER_INPUT, &buffer));
  RT_CHECK(context, rtBufferSetFormat(buffer, RT_FORMAT_FLOAT));
  RT_CHECK(context, rtBufferSetSize3D(buffer, kSize, kSize, kSize));
  void* mapped = nullptr;
  RT_CHECK(context, rtBufferMap(buffer, &mapped));
  float* values = static_cast<float*>(mapped);
  for (unsigned z = 0; z < kSize; ++z) {
    for (unsigned y = 0; y < kSize; ++y) {
      for (unsigned x = 0; x < kSize; ++x) *values++ = NoiseValue(x, y, z);
    }
  }
  RT_CHECK(context, rtBufferUnmap(buffer));
  const bool repeat[3] = {true, true, true};
  return CreateSampler(context, buffer, 3, repeat);
}

void SetUpContext(RTcontext context, const StepConfig& step, const RenderOptions& options,
                  ProgramLoader& programs, RTbuffer output, RTbuffer lights) {
  RT_CHECK(context, rtContextSetRayTypeCount(context, 2));
  RT_CHECK(context, rtContextSetEntryPointCount(context, 1));
  RT_CHECK(context, rtContextSetStackSize(context, kStackSize));
  // Exceptions go to the exception program (magenta pixels plus a printed report).
  RT_CHECK(context, rtContextSetExceptionEnabled(context, RT_EXCEPTION_ALL, 1));
  RT_CHECK(context, rtContextSetPrintEnabled(context, 1));

  Variables vars(context, context, rtContextDeclareVariable, "context");
  vars.Object("output_buffer", output);
  vars.Object("lights", lights);
  vars.Int("max_depth", kMaxDepth);
  vars.Uint("radiance_ray_type", kRadianceRayType);
  vars.Uint("shadow_ray_type", kShadowRayType);
  vars.Float("scene_epsilon", 1.e-3f);
  vars.Float("importance_cutoff", 0.01f);
  vars.Float3("ambient_light_color", 0.31f, 0.33f, 0.28f);
  vars.Float3("bg_color", kBackgroundColor[0], kBackgroundColor[1], kBackgroundColor[2]);
  vars.Float3("bad_color", kBadColor[0], kBadColor[1], kBadColor[2]);
  if (step.has_envmap()) {
    vars.Object("envmap", CreateEnvmap(context, options));
  }
  if (step.has_noise()) vars.Object("noise_texture", CreateNoise(context));

  const CameraFrame frame = ComputeFrame(
      TutorialCamera(), static_cast<float>(options.width) / static_cast<float>(options.height));
  vars.Float3("eye", frame.eye);
  vars.Float3("U", frame.U);
  vars.Float3("V", frame.V);
  vars.Float3("W", frame.W);

  RT_CHECK(context, rtContextSetRayGenerationProgram(context, 0, programs.Get(step.camera)));
  RT_CHECK(context, rtContextSetExceptionProgram(context, 0,
                                                 programs.Get({"tutorial_camera", "exception"})));
  RT_CHECK(context, rtContextSetMissProgram(context, kRadianceRayType, programs.Get(step.miss)));
}

// Copies the float4 output buffer into an Image, flipping rows: launch row 0 is the bottom.
Image ReadOutput(RTcontext context, RTbuffer output, int width, int height) {
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.resize(4 * static_cast<size_t>(width) * static_cast<size_t>(height));
  void* mapped = nullptr;
  RT_CHECK(context, rtBufferMap(output, &mapped));
  const size_t row_floats = 4 * static_cast<size_t>(width);
  const float* src = static_cast<const float*>(mapped);
  for (int y = 0; y < height; ++y) {
    std::memcpy(&image.rgba[static_cast<size_t>(height - 1 - y) * row_floats],
                src + static_cast<size_t>(y) * row_floats, row_floats * sizeof(float));
  }
  RT_CHECK(context, rtBufferUnmap(output));
  return image;
}

}  // namespace

std::string ResolveModuleDir(const std::string& flag) {
  if (!flag.empty()) return flag;
  const char* env = std::getenv("TESSERA_MODULE_DIR");
  if (env != nullptr && env[0] != '\0') return env;
  return TESSERA_TUTORIAL_MODULE_DIR;
}

StepBuffers SetUpStep(RTcontext context, const RenderOptions& options) {
  const StepConfig& step = GetStep(options.step);
  if (options.width <= 0 || options.height <= 0) {
    throw TutorialError("image size must be positive, got " + std::to_string(options.width) + "x" +
                        std::to_string(options.height));
  }
  ProgramLoader programs(context, options.module_dir);
  StepBuffers buffers;
  buffers.output = CreateOutputBuffer(context, options.width, options.height);
  buffers.lights = CreateLights(context);
  SetUpContext(context, step, options, programs, buffers.output, buffers.lights);
  BuildScene(context, step, programs);
  RT_CHECK(context, rtContextValidate(context));
  RT_CHECK(context, rtContextCompile(context));
  return buffers;
}

Image RenderStep(const RenderOptions& options) {
  ContextHolder holder;
  RTcontext context = holder.get();
  const StepBuffers buffers = SetUpStep(context, options);
  g_rendering = context;
  RT_CHECK(context, rtContextSetTimeoutCallback(context, &SayProgress, kProgressSeconds));
  RT_CHECK(context, rtContextLaunch2D(context, 0, static_cast<RTsize>(options.width),
                                      static_cast<RTsize>(options.height)));
  g_rendering = nullptr;
  return ReadOutput(context, buffers.output, options.width, options.height);
}

}  // namespace tessera::tutorial
