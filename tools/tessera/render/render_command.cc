#include "tools/tessera/render/render_command.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "tessera/cli_checks.h"
#include "tessera/rt_ext.h"
#include "tools/tessera/render/accumulation_file.h"
#include "tools/tessera/render/camera_setup.h"
#include "tools/tessera/render/frames.h"
#include "tools/tessera/render/image_io.h"
#include "tools/tessera/render/progress.h"
#include "tools/tessera/render/renderer.h"
#include "tools/tessera/render/stop_signals.h"
#include "tools/tessera/scene/builtin_scene.h"

namespace tessera::render {
namespace {

// Whether anything in `scene` gives light: a punctual light at its first frame or an emissive
// material.
bool Lit(const SceneFile& scene) {
  if (!scene.FrameAt(scene.time_begin()).lights.empty()) return true;
  for (const Material& m : scene.assets().materials) {
    if (m.emissive[0] > 0.f || m.emissive[1] > 0.f || m.emissive[2] > 0.f) return true;
  }
  return false;
}

// "X,Y,Z,R,G,B" (`--point-light`) into a light at X,Y,Z with intensity R,G,B; false when it is not
// six finite numbers with a non-negative intensity.
bool ParsePointLight(const std::string& text, Light* light) {
  const std::vector<std::string> parts = absl::StrSplit(text, ',');
  float v[6];
  if (parts.size() != 6) return false;
  for (int i = 0; i < 6; ++i) {
    if (!absl::SimpleAtof(absl::StripAsciiWhitespace(parts[i]), &v[i]) || !std::isfinite(v[i])) {
      return false;
    }
    if (i >= 3 && v[i] < 0.f) return false;
  }
  light->name = absl::StrCat("--point-light ", text);
  light->type = Light::Type::kPoint;
  std::copy(v + 3, v + 6, light->color);
  light->intensity = 1.f;
  light->to_world = {1, 0, 0, v[0], 0, 1, 0, v[1], 0, 0, 1, v[2]};
  return true;
}

constexpr int kExitFailure = 1;
constexpr double kPassSeconds = 1.0;  // what automatic pass sizes aim for

enum class LogLevel { kOff, kError, kWarn, kInfo, kDebug };

LogLevel ParseLogLevel(const std::string& name) {
  if (name == "off") return LogLevel::kOff;
  if (name == "error") return LogLevel::kError;
  if (name == "warn") return LogLevel::kWarn;
  if (name == "debug") return LogLevel::kDebug;
  return LogLevel::kInfo;
}

// Messages on stderr, at or above the --log-level.
class Log {
 public:
  explicit Log(LogLevel level) : level_(level) {}
  bool enabled(LogLevel level) const { return level != LogLevel::kOff && level <= level_; }
  template <typename... Args>
  void operator()(LogLevel level, const absl::FormatSpec<Args...>& format,
                  const Args&... args) const {
    if (!enabled(level)) return;
    const char* prefix = level == LogLevel::kError  ? "error: "
                         : level == LogLevel::kWarn ? "warning: "
                                                    : "";
    std::fprintf(stderr, "tessera render: %s%s\n", prefix,
                 absl::StrFormat(format, args...).c_str());
    std::fflush(stderr);
  }

 private:
  LogLevel level_;
};

bool Exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

// "W", "WxH" or "WxHxD", each at least 1.
bool ParseTileSize(const std::string& text, std::vector<RTsize>* size) {
  size->clear();
  for (absl::string_view part : absl::StrSplit(text, 'x')) {
    unsigned long long n = 0;
    if (!absl::SimpleAtoi(part, &n) || n == 0) return false;
    size->push_back(static_cast<RTsize>(n));
  }
  return !size->empty() && size->size() <= 3;
}

absl::StatusOr<std::unique_ptr<SceneFile>> OpenScene(const std::string& scene) {
  const std::string prefix = kBuiltinPrefix;
  if (scene.compare(0, prefix.size(), prefix) == 0) {
    return OpenBuiltinScene(scene.substr(prefix.size()));
  }
  return SceneFile::Open(scene);
}

// What an accumulation's sums depend on besides its size and sample count: a resume refuses
// sums made with anything else.
std::string AccumulationKey(const RenderOptions& o, const std::string& camera, double time) {
  std::string key = absl::StrFormat(
      "tessera %s; scene %s; camera %s; time %.9g; seed %u; max-depth %d; clamp %.9g; "
      "env %s x %.9g; background %s; fov %.9g; point lights %s",
      SoftwareName(), o.scene, camera, time, o.seed, o.max_depth, o.clamp_indirect, o.environment,
      o.environment_intensity,
      o.background.empty()
          ? std::string("auto")
          : absl::StrFormat("%.9g %.9g %.9g", o.background[0], o.background[1], o.background[2]),
      o.fov_degrees, absl::StrJoin(o.point_lights, " "));
  std::replace(key.begin(), key.end(), '\n', ' ');
  return key;
}

// One frame to render: its number, its image and its time in the scene.
struct FrameJob {
  int frame = 0;
  std::string path;
  double time = 0.0;
};

class RenderRun {
 public:
  explicit RenderRun(const RenderOptions& options)
      : options_(options),
        log_(ParseLogLevel(options.log_level)),
        progress_(log_.enabled(LogLevel::kInfo)
                      ? (isatty(STDERR_FILENO) ? Progress::Mode::kBar : Progress::Mode::kLines)
                      : Progress::Mode::kOff) {}

  int Run();

 private:
  // 0 when the frame was written, else the exit status.
  int RenderFrame(const FrameJob& job);
  // The camera of `frame` the options ask for: --look-from/--look-at, else --camera (or one made
  // up to frame the scene), with --fov applied.
  absl::StatusOr<Camera> ChooseCamera(const Frame& frame) const;
  uint32_t NextPassSize(uint32_t target) const;

  const RenderOptions& options_;
  Log log_;
  Progress progress_;
  std::unique_ptr<SceneFile> scene_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<Light> extra_lights_;  // --point-light, added to every frame
  double seconds_per_sample_ = 0.0;  // measured on the last pass
  double rays_per_second_ = 0.0;
  int passes_repeated_ = 0;  // already reported
};

int RenderRun::Run() {
  InstallStopSignalHandlers();
  std::vector<FrameJob> jobs;
  if (options_.frames.empty()) {
    jobs.push_back({0, ExpandFramePattern(options_.output, 0), 0.0});
  } else {
    const absl::StatusOr<std::vector<int>> frames = ParseFrames(options_.frames);
    for (int frame : frames.value()) {  // checked when parsing
      jobs.push_back({frame, ExpandFramePattern(options_.output, frame), frame / options_.fps});
    }
  }
  if (options_.skip_existing) {
    // Before the scene is read or a device started: a farm that restarts a finished range does
    // no work.
    std::vector<FrameJob> left;
    for (const FrameJob& job : jobs) {
      if (Exists(job.path) && !Exists(AccumulationPath(job.path))) {
        log_(LogLevel::kInfo, "%s exists, skipped", job.path);
      } else {
        left.push_back(job);
      }
    }
    jobs.swap(left);
    if (jobs.empty()) return 0;
  }

  absl::StatusOr<std::unique_ptr<SceneFile>> scene = OpenScene(options_.scene);
  if (!scene.ok()) {
    log_(LogLevel::kError, "%s", scene.status().message());
    return kExitFailure;
  }
  scene_ = *std::move(scene);

  RendererSettings settings;
  settings.module_dir = DefaultModuleDir();
  settings.devices = options_.devices;
  if (!options_.tile_size.empty()) ParseTileSize(options_.tile_size, &settings.tile_size);
  settings.threads = options_.threads;
  settings.max_depth = options_.max_depth;
  settings.clamp_indirect = options_.clamp_indirect;
  settings.seed = options_.seed;
  settings.environment = options_.environment;
  settings.environment_intensity = options_.environment_intensity;
  if (!options_.background.empty()) {
    std::copy_n(options_.background.begin(), 3, settings.background.begin());
  } else if (options_.environment.empty() && options_.point_lights.empty() && !Lit(*scene_)) {
    settings.background = {1.f, 1.f, 1.f};
    log_(LogLevel::kWarn,
         "%s has no lights and no emissive surfaces: lit by a white sky (--background 0,0,0 "
         "keeps it black)",
         options_.scene);
  }
  settings.aov_samples = options_.aov_samples;
  for (const std::string& text : options_.point_lights) {
    Light light;
    if (ParsePointLight(text, &light)) extra_lights_.push_back(light);  // checked when parsed
  }
  absl::StatusOr<std::unique_ptr<Renderer>> renderer = Renderer::Create(*scene_, settings);
  if (!renderer.ok()) {
    log_(LogLevel::kError, "%s", renderer.status().message());
    return kExitFailure;
  }
  renderer_ = *std::move(renderer);
  log_(LogLevel::kDebug, "program modules in %s", settings.module_dir);

  for (const FrameJob& job : jobs) {
    if (StopSignal() != 0) return ExitStatusForSignal(StopSignal());
    if (const int status = RenderFrame(job); status != 0) return status;
  }
  return 0;
}

absl::StatusOr<Camera> RenderRun::ChooseCamera(const Frame& frame) const {
  absl::StatusOr<Camera> camera;
  if (!options_.look_from.empty()) {
    // At the middle of the scene's bounds unless --look-at says where.
    const float* b = frame.bounds;
    const float middle[3] = {0.5f * (b[0] + b[3]), 0.5f * (b[1] + b[4]), 0.5f * (b[2] + b[5])};
    camera = LookAtCamera(options_.look_from.data(),
                          options_.look_at.empty() ? middle : options_.look_at.data());
  } else {
    int width = 0, height = 0;  // the image a camera made up to frame the scene fills
    ResolveImageSize(Camera{}, options_.width, options_.height, &width, &height);
    camera = SelectCamera(frame, options_.camera,
                          static_cast<float>(width) / static_cast<float>(height));
  }
  if (camera.ok() && options_.fov_degrees > 0.f) {
    camera->yfov = options_.fov_degrees * 3.14159265f / 180.f;
  }
  return camera;
}

uint32_t RenderRun::NextPassSize(uint32_t target) const {
  const uint32_t left = target - renderer_->samples_done();
  uint32_t samples = options_.pass_samples;
  if (samples == 0) {
    // About a second per launch: progress, Ctrl-C and --time-limit act between launches, and
    // every launch costs the same few milliseconds of calls and copies however many samples it
    // takes.
    samples = seconds_per_sample_ > 0.0
                  ? static_cast<uint32_t>(std::clamp(kPassSeconds / seconds_per_sample_, 1.0, 1e6))
                  : 1;
  }
  if (options_.time_limit > 0.0 && seconds_per_sample_ > 0.0) {
    const double room = (options_.time_limit - progress_.Elapsed()) / seconds_per_sample_;
    samples = std::min<uint32_t>(samples, static_cast<uint32_t>(std::max(room, 0.0)));
  }
  return std::min(samples, left);
}

int RenderRun::RenderFrame(const FrameJob& job) {
  if (absl::Status s = CheckWritable(job.path); !s.ok()) {
    log_(LogLevel::kError, "%s", s.message());
    return kExitFailure;
  }
  Frame frame = scene_->FrameAt(job.time);
  frame.lights.insert(frame.lights.end(), extra_lights_.begin(), extra_lights_.end());
  absl::StatusOr<Camera> camera = ChooseCamera(frame);
  if (!camera.ok()) {
    log_(LogLevel::kError, "%s", camera.status().message());
    return kExitFailure;
  }
  int width = 0, height = 0;
  ResolveImageSize(*camera, options_.width, options_.height, &width, &height);
  if (absl::Status s = renderer_->SetView(frame, *camera, width, height); !s.ok()) {
    log_(LogLevel::kError, "%s", s.message());
    return kExitFailure;
  }
  const std::string key = AccumulationKey(options_, camera->name, job.time);
  const std::string accum_path = AccumulationPath(job.path);
  if (options_.resume) {
    absl::StatusOr<Accumulation> saved = ReadAccumulation(accum_path);
    if (absl::IsNotFound(saved.status())) {
      log_(LogLevel::kInfo, "no %s to resume: rendering %s from the start", accum_path, job.path);
    } else if (!saved.ok()) {
      log_(LogLevel::kError, "%s", saved.status().message());
      return kExitFailure;
    } else if (saved->width != width || saved->height != height || saved->key != key) {
      log_(LogLevel::kError,
           "cannot resume from %s: it was rendered as %dx%d with [%s], this render is %dx%d "
           "with [%s] (remove it to start afresh)",
           accum_path, saved->width, saved->height, saved->key, width, height, key);
      return kExitFailure;
    } else if (absl::Status s = renderer_->ResumeFrom(saved->sums, saved->samples); !s.ok()) {
      log_(LogLevel::kError, "%s", s.message());
      return kExitFailure;
    } else {
      log_(LogLevel::kInfo, "resuming %s at %u samples", job.path, saved->samples);
    }
  }

  const std::string label = options_.frames.empty() ? job.path : absl::StrCat("frame ", job.frame);
  const uint32_t target = options_.spp > 0 ? options_.spp : UINT32_MAX;
  const float* b = frame.bounds;
  log_(LogLevel::kDebug,
       "%s: %dx%d, camera \"%s\", time %g s, %zu emissive triangles, bounds (%g %g %g)-(%g %g %g)",
       job.path, width, height, camera->name, job.time, renderer_->emissive_triangle_count(), b[0],
       b[1], b[2], b[3], b[4], b[5]);
  progress_.StartFrame(label, options_.spp, options_.time_limit, renderer_->samples_done());
  bool stopped_early = false;
  while (renderer_->samples_done() < target) {
    if (StopSignal() != 0) {
      stopped_early = true;
      break;
    }
    const uint32_t samples = NextPassSize(target);
    if (samples == 0) {  // out of time
      stopped_early = options_.spp > 0;
      break;
    }
    const uint32_t before = renderer_->samples_done();
    const double rays_before = renderer_->rays_traced();
    renderer_->SetPassObserver([&](double fraction) {
      progress_.Update(before + fraction * samples, rays_per_second_);
      return AbandonPass();
    });
    const auto start = std::chrono::steady_clock::now();
    const absl::Status pass = renderer_->RenderPass(samples);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!pass.ok()) {
      // A pass abandoned on a second signal, or one whose workers a terminal's Ctrl-C stopped
      // with the rest of the process group: the passes before it are kept.
      if (StopSignal() != 0) {
        log_(LogLevel::kWarn, "the sample pass in flight was abandoned: %s", pass.message());
        stopped_early = true;
        break;
      }
      progress_.FinishFrame(before, rays_per_second_);
      log_(LogLevel::kError, "%s", pass.message());
      return kExitFailure;
    }
    seconds_per_sample_ = seconds / samples;
    rays_per_second_ = seconds > 0.0 ? (renderer_->rays_traced() - rays_before) / seconds : 0.0;
    progress_.Update(renderer_->samples_done(), rays_per_second_);
    log_(LogLevel::kDebug, "pass done: %u samples in %.3f s, %u of %u, %.0f rays", samples, seconds,
         renderer_->samples_done(), options_.spp, renderer_->rays_traced());
  }
  progress_.FinishFrame(renderer_->samples_done(), rays_per_second_);

  if (renderer_->passes_repeated() > passes_repeated_) {
    log_(LogLevel::kWarn, "%d sample passes ran again: a device had lost its accumulation",
         renderer_->passes_repeated() - passes_repeated_);
    passes_repeated_ = renderer_->passes_repeated();
  }
  // Only OpenEXR files carry the albedo, normal and depth layers: no launch for them otherwise.
  const bool layers = FormatForPath(job.path).value_or(ImageFormat::kPng) == ImageFormat::kExr;
  absl::StatusOr<RenderedImage> image = renderer_->Resolve(layers);
  if (!image.ok()) {
    log_(LogLevel::kError, "%s", image.status().message());
    return kExitFailure;
  }
  ImageMetadata metadata;
  metadata.samples = renderer_->samples_done();
  metadata.spp = options_.spp;
  metadata.seed = options_.seed;
  metadata.max_depth = options_.max_depth;
  metadata.scene = options_.scene;
  metadata.camera = camera->name;
  metadata.frame = job.frame;
  metadata.time = job.time;
  if (absl::Status s = WriteImage(job.path, *image, metadata, options_.exr_float); !s.ok()) {
    log_(LogLevel::kError, "%s", s.message());
    return kExitFailure;
  }
  // The sums travel with an image that is not finished (or when asked to): --resume goes on from
  // them. A finished image's old sums would only mislead a later --resume.
  if (stopped_early || options_.keep_accumulation) {
    Accumulation a;
    a.width = width;
    a.height = height;
    a.samples = renderer_->samples_done();
    a.key = key;
    a.sums = renderer_->accumulation();
    if (absl::Status s = WriteAccumulation(accum_path, a); !s.ok()) {
      log_(LogLevel::kError, "%s", s.message());
      return kExitFailure;
    }
  } else if (Exists(accum_path)) {
    std::remove(accum_path.c_str());
  }
  std::printf("%s\n", job.path.c_str());
  std::fflush(stdout);
  if (StopSignal() != 0) {
    log_(LogLevel::kWarn, "stopped by signal %d after %u samples; %s holds them%s", StopSignal(),
         renderer_->samples_done(), job.path,
         stopped_early ? " (--resume goes on from its .accum)" : "");
    return ExitStatusForSignal(StopSignal());
  }
  return 0;
}

}  // namespace

CLI::App* AddRenderCommand(CLI::App& app, RenderOptions& o) {
  CLI::App* render = app.add_subcommand(
      "render",
      "Render a scene file (glTF, OBJ, or builtin:cornell) into images with Tessera's "
      "path tracer");
  render->footer(
      "Examples:\n"
      "  tessera render builtin:cornell -o cornell.png\n"
      "  tessera render scene.gltf -o frame.####.exr --frames 1-48 --spp 256 --skip-existing\n"
      "  tessera render scene.gltf -o still.exr --time-limit 60 --devices local:8\n"
      "  tessera render scene.gltf -o still.exr --spp 1024 --resume   # after Ctrl-C\n"
      "Exit status: 0 done, 1 render failure, 2 usage error, 130 after SIGINT, 143 after "
      "SIGTERM.");
  render->add_option("scene", o.scene, "the scene: a .gltf, .glb or .obj file, or builtin:cornell")
      ->required();
  render
      ->add_option("-o,--output", o.output,
                   "the image: .png (sRGB, 8-bit), .exr (linear, with albedo, normal and depth "
                   "layers) or .hdr; each run of # takes the frame number, zero-padded")
      ->required()
      ->check([](const std::string& path) -> std::string {
        const auto format = FormatForPath(path);
        return format.ok() ? "" : std::string(format.status().message());
      });
  CLI::Option* spp = render->add_option("--spp", o.spp, "samples per pixel")
                         ->capture_default_str()
                         ->check(CLI::Range(1u, 1u << 24));
  render
      ->add_option("--time-limit", o.time_limit,
                   "seconds per frame: render passes until the time is up (with --spp, whichever "
                   "comes first; without it, no sample limit)")
      ->check(tessera::cli::kPositive);
  render->add_option("--max-depth", o.max_depth, "bounces per path (0: emission only)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  render
      ->add_option("--clamp-indirect", o.clamp_indirect,
                   "clamp light arriving after a bounce to this value per sample (0: off; e.g. 10 "
                   "for previews: fewer speckles from caustics, slightly darker)")
      ->capture_default_str()
      ->check(tessera::cli::kNonNegative);
  render->add_option("--width", o.width, "image width (default 1280)")->check(CLI::Range(1, 65536));
  render
      ->add_option("--height", o.height,
                   "image height (default from the camera's aspect ratio, "
                   "else 720)")
      ->check(CLI::Range(1, 65536));
  render->add_option("--camera", o.camera,
                     "the camera: its index or name in the scene (default: the first)");
  render
      ->add_option("--frames", o.frames,
                   "frames A-B[:STEP] (or one frame A); frame F is rendered at time F / --fps")
      ->check([](const std::string& text) -> std::string {
        const auto frames = ParseFrames(text);
        return frames.ok() ? "" : std::string(frames.status().message());
      });
  render->add_option("--fps", o.fps, "frames per second of --frames")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  render->add_flag("--skip-existing", o.skip_existing,
                   "leave frames whose image exists (and has no .accum beside it) alone");
  render
      ->add_option("--env", o.environment,
                   "an equirectangular environment map (.hdr, .exr, ...) seen where rays leave "
                   "the scene")
      ->check(CLI::ExistingFile);
  render->add_option("--env-intensity", o.environment_intensity, "scale of the environment map")
      ->capture_default_str()
      ->check(tessera::cli::kNonNegative);
  render
      ->add_option("--look-from", o.look_from,
                   "look from this point X,Y,Z instead of a camera of the scene (at the middle of "
                   "the scene, or --look-at)")
      ->delimiter(',')
      ->expected(3);
  render->add_option("--look-at", o.look_at, "the point X,Y,Z --look-from looks at")
      ->delimiter(',')
      ->expected(3)
      ->needs("--look-from");
  render
      ->add_option("--fov", o.fov_degrees,
                   "vertical field of view in degrees, for whichever camera the render looks "
                   "through (default: the scene camera's, else 40)")
      ->check(CLI::Range(0.01f, 179.f));
  render
      ->add_option("--point-light", o.point_lights,
                   "a point light at X,Y,Z with intensity R,G,B (radiance R/d^2 at distance d, as "
                   "Embree's pathtracer --pointlight), added to the scene's lights; repeatable")
      ->check([](const std::string& text) -> std::string {
        Light light;
        return ParsePointLight(text, &light)
                   ? ""
                   : "expected X,Y,Z,R,G,B: six numbers, the last three not negative";
      });
  render->add_option("--background", o.background, "background colour R,G,B (linear) without --env")
      ->delimiter(',')
      ->expected(3);
  render
      ->add_option("--seed", o.seed,
                   "random seed: the same seed, scene and --spp give the same "
                   "image on any devices")
      ->capture_default_str();
  render
      ->add_option("--devices", o.devices,
                   "devices, as TESSERA_DEVICES: inproc, local:N, HOST:PORT, unix:PATH, "
                   "comma-separated (default: $TESSERA_DEVICES, else local:<cores>)")
      ->check([](const std::string& spec) -> std::string {
        const char* error = nullptr;
        if (tesseraDeviceSpecValidate(spec.c_str(), &error) == RT_SUCCESS) return "";
        return error != nullptr ? error : "not a device spec";
      });
  render
      ->add_option("--threads", o.threads,
                   "threads per device (default: every core, shared by the local devices)")
      ->check(CLI::Range(1, 4096));
  render
      ->add_option("--tile-size", o.tile_size,
                   "launch tile size W or WxH (default: Tessera's choice; results do not depend "
                   "on it)")
      ->check([](const std::string& text) -> std::string {
        std::vector<RTsize> size;
        return ParseTileSize(text, &size) && size.size() <= 2 ? "" : "expected W or WxH";
      });
  render
      ->add_option("--log-level", o.log_level,
                   "messages on stderr: off, error, warn, info (with progress), debug (a line "
                   "per pass)")
      ->capture_default_str()
      ->check(CLI::IsMember({"off", "error", "warn", "info", "debug"}));
  render->add_flag("--resume", o.resume,
                   "go on from OUT.accum, which a stopped render leaves, up to --spp; the result "
                   "is the image an uninterrupted render would have written");
  render->add_flag("--keep-accum", o.keep_accumulation,
                   "also leave OUT.accum beside a finished image, for a later --resume with more "
                   "--spp");
  render
      ->add_option("--pass-samples", o.pass_samples,
                   "samples per launch (default: as many as take about a second)")
      ->check(CLI::Range(1u, 1u << 30));
  render
      ->add_option("--aov-samples", o.aov_samples,
                   "rays per pixel for the albedo, normal and depth layers")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u));
  render->add_flag("--exr-float", o.exr_float, "32-bit float EXR channels instead of half");
  render->callback([render, spp, &o] {
    if (o.frames.empty() == false) {
      const auto frames = ParseFrames(o.frames);
      if (frames->size() > 1 && !HasFramePattern(o.output)) {
        throw CLI::ValidationError("--output", "'" + o.output +
                                                   "' has no # for the frame number, and "
                                                   "--frames names several frames");
      }
    }
    if (spp->count() == 0 && o.time_limit > 0.0) o.spp = 0;  // the time limit alone
  });
  return render;
}

int RunRender(const RenderOptions& options) {
  RenderRun run(options);
  return run.Run();
}

}  // namespace tessera::render
