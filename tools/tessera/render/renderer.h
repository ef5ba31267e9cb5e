// The path tracer's host side: a Tessera context with the programs of render/programs/, the
// scene's node graph, and the accumulation that sample passes add to.
//
// A render of one frame: SetView, optionally ResumeFrom, then RenderPass as often as wanted (one
// launch each, adding `samples` samples per pixel), then Resolve for the image. The accumulation
// holds per pixel the sum of the samples' radiance, added one sample at a time in sample order,
// and every sample's random numbers depend only on (pixel, sample index, seed): so the result is
// the same bits whatever the passes, devices and tiles, and a render resumed from a saved
// accumulation ends as an uninterrupted one does.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_RENDERER_H_
#define TESSERA_TOOLS_TESSERA_RENDER_RENDERER_H_

#include <optixu/optixpp_namespace.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "tools/tessera/render/camera_setup.h"
#include "tools/tessera/render/image_io.h"
#include "tools/tessera/render/scene_graph.h"
#include "tools/tessera/scene/scene.h"

namespace tessera::render {

struct RendererSettings {
  std::string module_dir;         // where the tessera_render_*.so modules are
  std::string devices;            // a device spec; "" for TESSERA_DEVICES or the default
  std::vector<RTsize> tile_size;  // empty: Tessera's choice
  int threads = 0;                // per device (CPU_NUM_THREADS); 0: the devices' own
  int max_depth = 8;
  float clamp_indirect = 0.f;  // 0: off
  uint32_t seed = 0;
  std::string environment;  // an equirectangular image, or ""
  float environment_intensity = 1.f;
  std::array<float, 3> background{0.f, 0.f, 0.f};
  uint32_t aov_samples = 16;
};

class Renderer {
 public:
  // Creates the context, loads the programs and builds `scene`'s assets. `scene` must outlive the
  // renderer. Errors name what failed (a missing module, an unreadable environment map, a device
  // spec that cannot be served).
  static absl::StatusOr<std::unique_ptr<Renderer>> Create(const SceneFile& scene,
                                                          const RendererSettings& settings);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Shows `frame` through `camera` at width x height and clears the accumulation.
  absl::Status SetView(const Frame& frame, const Camera& camera, int width, int height);

  // Replaces the accumulation with `sums` (width * height * 4, the layout of the .accum file)
  // holding `samples` samples per pixel.
  absl::Status ResumeFrom(const std::vector<float>& sums, uint32_t samples);

  // Called about every 0.2 s during a pass with the share of its tiles done (0..1); returning
  // true cancels the pass (RenderPass then returns CANCELLED and the accumulation is as before).
  void SetPassObserver(std::function<bool(double)> observer) { observer_ = std::move(observer); }

  // Adds `samples` samples per pixel in one launch. On failure the accumulation is as it was
  // before the pass. A pass whose result shows a device's accumulation lost (a worker that died
  // and came back, or tiles that moved to a device that never had them: every pixel's sample
  // count is checked) is run again from the last good accumulation, which is sent to every device.
  absl::Status RenderPass(uint32_t samples);

  uint32_t samples_done() const { return samples_done_; }
  // Rays traced by this renderer's passes (counted by the programs), and passes run again.
  double rays_traced() const { return rays_traced_; }
  int passes_repeated() const { return passes_repeated_; }
  // The accumulation after the last pass that completed (launch layout: row 0 at the bottom).
  const std::vector<float>& accumulation() const { return accumulation_; }
  int width() const { return width_; }
  size_t emissive_triangle_count() const { return graph_->emissive_triangle_count(); }
  int height() const { return height_; }

  // The image: accumulation / samples, rows flipped to top first, and with `layers` the albedo,
  // normal and depth layers (one more launch, of the `aovs` entry point).
  absl::StatusOr<RenderedImage> Resolve(bool layers);

 private:
  Renderer() = default;
  absl::Status Init(const SceneFile& scene, const RendererSettings& settings);
  static int TimeoutCallback();
  // Sends the last good accumulation to every device (a host write of a GPU_LOCAL buffer).
  void UploadAccumulation();

  RendererSettings settings_;
  optix::Context context_;
  std::unique_ptr<SceneGraph> graph_;
  optix::Buffer accum_;
  optix::Buffer output_;
  optix::Buffer ray_counts_;
  optix::Buffer albedo_;
  optix::Buffer normal_depth_;
  int width_ = 0, height_ = 0;
  uint32_t samples_done_ = 0;
  double rays_traced_ = 0.0;
  int passes_repeated_ = 0;
  std::vector<float> accumulation_;
  std::function<bool(double)> observer_;
};

// The directory of the path tracer's modules: $TESSERA_RENDER_MODULE_DIR, else the installed one
// beside this executable (<prefix>/<libdir>/tessera/render), else the build tree's.
std::string DefaultModuleDir();

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_RENDERER_H_
