#include "tools/tessera/render/renderer.h"

#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "tessera/image.h"
#include "tessera/rt_ext.h"
#include "tools/tessera/render/programs/path_tracer.h"

#ifndef TESSERA_RENDER_BUILD_MODULE_DIR
#error "TESSERA_RENDER_BUILD_MODULE_DIR must name the build's module directory"
#endif
#ifndef TESSERA_RENDER_INSTALLED_MODULE_DIR
#error "TESSERA_RENDER_INSTALLED_MODULE_DIR must name the installed modules, relative to bindir"
#endif

namespace tessera::render {
namespace {

using path_tracer::kAovEntry;
using path_tracer::kPathTraceEntry;

constexpr char kProbeModule[] = "tessera_render_camera.so";

// The timeout callback takes no argument: the renderer whose launch is running.
Renderer* g_launching = nullptr;

bool IsFile(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// An optix::Exception as a Status, its message prefixed with what was being done.
absl::Status FromException(const std::string& doing, const optix::Exception& e) {
  return absl::InternalError(absl::StrCat(doing, ": ", e.getErrorString()));
}

// A sampler of the environment image: around in u, clamped at the poles in v.
int MakeEnvironment(optix::Context& context, const std::string& path) {
  RTbuffer raw = nullptr;
  if (tesseraBufferCreateFromImage(context->get(), path.c_str(),
                                   TESSERA_IMAGE_TOP_ROW_FIRST | TESSERA_IMAGE_FLOAT,
                                   &raw) != RT_SUCCESS) {
    throw optix::Exception(std::string("environment map: ") + tesseraImageGetErrorString(),
                           RT_ERROR_FILE_NOT_FOUND);
  }
  optix::TextureSampler sampler = context->createTextureSampler();
  sampler->setWrapMode(0, RT_WRAP_REPEAT);
  sampler->setWrapMode(1, RT_WRAP_CLAMP_TO_EDGE);
  sampler->setFilteringModes(RT_FILTER_LINEAR, RT_FILTER_LINEAR, RT_FILTER_NONE);
  sampler->setIndexingMode(RT_TEXTURE_INDEX_NORMALIZED_COORDINATES);
  sampler->setReadMode(RT_TEXTURE_READ_ELEMENT_TYPE);
  sampler->setMaxAnisotropy(1.0f);
  sampler->setBuffer(optix::Buffer::take(raw));
  return sampler->getId();
}

}  // namespace

std::string DefaultModuleDir() {
  if (const char* env = std::getenv("TESSERA_RENDER_MODULE_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  if (n > 0) {
    const std::string self(exe, static_cast<size_t>(n));
    const std::string installed =
        self.substr(0, self.rfind('/')) + "/" + TESSERA_RENDER_INSTALLED_MODULE_DIR;
    char resolved[PATH_MAX];
    if (IsFile(installed + "/" + kProbeModule) &&
        realpath(installed.c_str(), resolved) != nullptr) {
      return resolved;
    }
  }
  return TESSERA_RENDER_BUILD_MODULE_DIR;
}

absl::StatusOr<std::unique_ptr<Renderer>> Renderer::Create(const SceneFile& scene,
                                                           const RendererSettings& settings) {
  std::unique_ptr<Renderer> renderer(new Renderer());
  if (absl::Status s = renderer->Init(scene, settings); !s.ok()) return s;
  return renderer;
}

Renderer::~Renderer() {
  if (g_launching == this) g_launching = nullptr;
  graph_.reset();
  if (context_) context_->destroy();
}

absl::Status Renderer::Init(const SceneFile& scene, const RendererSettings& settings) {
  settings_ = settings;
  const std::string probe = settings.module_dir + "/" + kProbeModule;
  if (!IsFile(probe)) {
    return absl::NotFoundError("the path tracer's program modules are not in '" +
                               settings.module_dir + "' (no " + kProbeModule +
                               "; set TESSERA_RENDER_MODULE_DIR)");
  }
  try {
    context_ = optix::Context::create();
    if (!settings.devices.empty()) {
      if (RTresult r = tesseraContextSetDeviceSpec(context_->get(), settings.devices.c_str());
          r != RT_SUCCESS) {
        return absl::UnavailableError("--devices " + settings.devices + ": " +
                                      context_->getErrorString(r));
      }
    }
    if (settings.threads > 0) context_->setCPUNumThreads(settings.threads);
    if (!settings.tile_size.empty()) {
      if (RTresult r = tesseraContextSetTileSize(context_->get(),
                                                 static_cast<unsigned>(settings.tile_size.size()),
                                                 settings.tile_size.data());
          r != RT_SUCCESS) {
        return absl::InvalidArgumentError("--tile-size: " + context_->getErrorString(r));
      }
    }
    context_->setRayTypeCount(path_tracer::kRayTypeCount);
    context_->setEntryPointCount(path_tracer::kEntryPointCount);
    auto program = [&](const char* module, const char* function) {
      return context_->createProgramFromPTXFile(
          settings.module_dir + "/tessera_render_" + module + ".so", function);
    };
    context_->setRayGenerationProgram(kPathTraceEntry, program("camera", "path_trace"));
    context_->setRayGenerationProgram(kAovEntry, program("camera", "aovs"));
    context_->setMissProgram(path_tracer::kRadianceRay, program("miss", "miss_radiance"));
    context_->setMissProgram(path_tracer::kShadowRay, program("miss", "miss_shadow"));

    context_["max_depth"]->setInt(settings.max_depth);
    context_["clamp_indirect"]->setFloat(settings.clamp_indirect);
    context_["seed"]->setUint(settings.seed);
    context_["aov_samples"]->setUint(settings.aov_samples);
    context_["sample_begin"]->setUint(0u);
    context_["sample_count"]->setUint(0u);
    context_["background_color"]->setFloat(settings.background[0], settings.background[1],
                                           settings.background[2]);
    context_["environment_intensity"]->setFloat(settings.environment_intensity);
    context_["environment_texture"]->setInt(settings.environment.empty()
                                                ? path_tracer::kNoTexture
                                                : MakeEnvironment(context_, settings.environment));

    SceneGraph::Programs programs;
    programs.closest_hit = program("material", "closest_hit");
    programs.attributes = program("mesh", "mesh_attributes");
    absl::StatusOr<SceneGraph> graph = SceneGraph::Build(context_, programs, scene.assets());
    if (!graph.ok()) return graph.status();
    graph_ = std::make_unique<SceneGraph>(*std::move(graph));

    accum_ = context_->createBuffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_FLOAT4,
                                    1, 1);
    output_ = context_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 1, 1);
    ray_counts_ = context_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, 1, 1);
    albedo_ = context_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 1, 1);
    normal_depth_ = context_->createBuffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 1, 1);
    context_["accum_buffer"]->set(accum_);
    context_["output_buffer"]->set(output_);
    context_["ray_count_buffer"]->set(ray_counts_);
    context_["albedo_buffer"]->set(albedo_);
    context_["normal_depth_buffer"]->set(normal_depth_);
    context_->setTimeoutCallback(&Renderer::TimeoutCallback, 0.2);
  } catch (const optix::Exception& e) {
    return FromException("setting up the renderer", e);
  }
  return absl::OkStatus();
}

int Renderer::TimeoutCallback() {
  Renderer* r = g_launching;
  if (r == nullptr || !r->observer_) return 0;
  RTsize done = 0, total = 0;
  tesseraContextGetLaunchProgress(r->context_->get(), &done, &total);
  return r->observer_(total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 0.0) ? 1
                                                                                                : 0;
}

absl::Status Renderer::SetView(const Frame& frame, const Camera& camera, int width, int height) {
  try {
    graph_->SetFrame(frame);
    const CameraBasis basis = ComputeCameraBasis(camera, width, height);
    context_["eye"]->set3fv(basis.eye);
    context_["U"]->set3fv(basis.u);
    context_["V"]->set3fv(basis.v);
    context_["W"]->set3fv(basis.w);
    context_["orthographic"]->setInt(basis.orthographic ? 1 : 0);
    context_["near_distance"]->setFloat(basis.near_distance);
    if (width != width_ || height != height_) {
      for (optix::Buffer* b : {&accum_, &output_, &ray_counts_, &albedo_, &normal_depth_}) {
        (*b)->setSize(static_cast<RTsize>(width), static_cast<RTsize>(height));
      }
      width_ = width;
      height_ = height;
    }
    accumulation_.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * 4, 0.f);
    UploadAccumulation();
  } catch (const optix::Exception& e) {
    return FromException("setting up the frame", e);
  }
  samples_done_ = 0;
  rays_traced_ = 0.0;
  return absl::OkStatus();
}

absl::Status Renderer::ResumeFrom(const std::vector<float>& sums, uint32_t samples) {
  if (sums.size() != accumulation_.size()) {
    return absl::InvalidArgumentError("the accumulation does not fit the image size");
  }
  for (size_t i = 3; i < sums.size(); i += 4) {
    if (sums[i] != static_cast<float>(samples)) {
      return absl::InvalidArgumentError("the accumulation's pixels do not all hold its samples");
    }
  }
  accumulation_ = sums;
  try {
    UploadAccumulation();
  } catch (const optix::Exception& e) {
    return FromException("loading the accumulation", e);
  }
  samples_done_ = samples;
  return absl::OkStatus();
}

void Renderer::UploadAccumulation() {
  std::memcpy(accum_->map(), accumulation_.data(), accumulation_.size() * sizeof(float));
  accum_->unmap();
}

absl::Status Renderer::RenderPass(uint32_t samples) {
  const auto w = static_cast<RTsize>(width_), h = static_cast<RTsize>(height_);
  const auto expected = static_cast<float>(samples_done_ + samples);
  // A device that lost its accumulation gives itself away in the sample counts; the pass then
  // runs again from the last good sums. Twice more at most: a device set that keeps losing
  // devices fails the launches themselves.
  for (int attempt = 0;; ++attempt) {
    try {
      context_["sample_begin"]->setUint(samples_done_);
      context_["sample_count"]->setUint(samples);
      g_launching = this;
      context_->launch(kPathTraceEntry, w, h);
      g_launching = nullptr;
      const auto* sums = static_cast<const float*>(output_->map(0, RT_BUFFER_MAP_READ));
      bool whole = true;
      for (size_t i = 3; i < accumulation_.size() && whole; i += 4) whole = sums[i] == expected;
      if (whole) std::memcpy(accumulation_.data(), sums, accumulation_.size() * sizeof(float));
      output_->unmap();
      if (!whole) {
        if (attempt == 2) {
          return absl::DataLossError("the devices lost their accumulation three times in a row");
        }
        ++passes_repeated_;
        UploadAccumulation();
        continue;
      }
      const auto* rays = static_cast<const unsigned*>(ray_counts_->map(0, RT_BUFFER_MAP_READ));
      double pass_rays = 0.0;
      for (size_t i = 0; i < accumulation_.size() / 4; ++i) pass_rays += rays[i];
      ray_counts_->unmap();
      rays_traced_ += pass_rays;
      samples_done_ += samples;
      return absl::OkStatus();
    } catch (const optix::Exception& e) {
      g_launching = nullptr;
      // The devices' sums may hold part of the pass: put back what the last whole pass left.
      try {
        UploadAccumulation();
      } catch (const optix::Exception&) {
        // The launch's own error says more.
      }
      if (e.getErrorCode() == RT_TIMEOUT_CALLBACK) {
        return absl::CancelledError("the sample pass was cancelled");
      }
      return FromException("rendering", e);
    }
  }
}

absl::StatusOr<RenderedImage> Renderer::Resolve(bool layers) {
  RenderedImage image;
  image.width = width_;
  image.height = height_;
  const size_t count = static_cast<size_t>(width_) * static_cast<size_t>(height_);
  image.rgba.resize(count * 4);
  if (layers) {
    image.albedo.resize(count * 3);
    image.normal.resize(count * 3);
    image.depth.resize(count);
  }
  const float scale = samples_done_ > 0 ? 1.f / static_cast<float>(samples_done_) : 0.f;
  for (int y = 0; y < height_; ++y) {
    // Launch row 0 is the bottom of the image; files start at the top.
    const size_t src_row = static_cast<size_t>(height_ - 1 - y) * static_cast<size_t>(width_);
    const size_t dst_row = static_cast<size_t>(y) * static_cast<size_t>(width_);
    for (size_t x = 0; x < static_cast<size_t>(width_); ++x) {
      for (size_t c = 0; c < 3; ++c) {
        image.rgba[(dst_row + x) * 4 + c] = accumulation_[(src_row + x) * 4 + c] * scale;
      }
      image.rgba[(dst_row + x) * 4 + 3] = 1.f;
    }
  }
  if (!layers) return image;
  try {
    context_->launch(kAovEntry, static_cast<RTsize>(width_), static_cast<RTsize>(height_));
    const auto* albedo = static_cast<const float*>(albedo_->map(0, RT_BUFFER_MAP_READ));
    const auto* normal_depth = static_cast<const float*>(normal_depth_->map(0, RT_BUFFER_MAP_READ));
    for (int y = 0; y < height_; ++y) {
      const size_t src_row = static_cast<size_t>(height_ - 1 - y) * static_cast<size_t>(width_);
      const size_t dst_row = static_cast<size_t>(y) * static_cast<size_t>(width_);
      for (size_t x = 0; x < static_cast<size_t>(width_); ++x) {
        const size_t s = src_row + x, d = dst_row + x;
        for (size_t c = 0; c < 3; ++c) {
          image.albedo[d * 3 + c] = albedo[s * 4 + c];
          image.normal[d * 3 + c] = normal_depth[s * 4 + c];
        }
        image.depth[d] = normal_depth[s * 4 + 3];
      }
    }
    albedo_->unmap();
    normal_depth_->unmap();
  } catch (const optix::Exception& e) {
    return FromException("rendering the albedo, normal and depth layers", e);
  }
  return image;
}

}  // namespace tessera::render
