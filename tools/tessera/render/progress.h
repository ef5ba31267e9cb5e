// Progress of a render on stderr: on a terminal one line redrawn in place (a bar, samples done of
// those asked for, rays per second, elapsed time and what is left), otherwise a plain line at
// every 5% or every 2 seconds, whichever comes first.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRESS_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRESS_H_

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace tessera::render {

class Progress {
 public:
  enum class Mode { kOff, kBar, kLines };

  explicit Progress(Mode mode, std::FILE* out = stderr) : mode_(mode), out_(out) {}

  // A frame begins: `label` names it ("frame 12", or the output path), `spp` is the samples per
  // pixel asked for (0: no limit), `time_limit` the seconds allowed (0: none), `samples` those
  // already done (a resumed render).
  void StartFrame(const std::string& label, uint32_t spp, double time_limit, uint32_t samples);
  // `samples` done so far (fractional while a pass runs), `rays_per_second` measured so far.
  void Update(double samples, double rays_per_second);
  // The frame ended with `samples` done; a terminal's line is ended.
  void FinishFrame(uint32_t samples, double rays_per_second);

  // Seconds since StartFrame.
  double Elapsed() const;

 private:
  double Fraction(double samples) const;
  std::string Line(double samples, double rays_per_second) const;

  Mode mode_;
  std::FILE* out_;
  std::string label_;
  uint32_t spp_ = 0;
  uint32_t first_samples_ = 0;
  double time_limit_ = 0.0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  double last_fraction_ = -1.0;
};

// "1:05", "1:02:03": a duration of whole seconds for people.
std::string FormatDuration(double seconds);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRESS_H_
