#include "tools/tessera/render/progress.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_format.h"

namespace tessera::render {
namespace {

constexpr double kBarInterval = 0.1;   // seconds between redraws on a terminal
constexpr double kLineInterval = 2.0;  // at most this long without a line otherwise
constexpr double kLineStep = 0.05;     // and a line at every 5%
constexpr int kBarWidth = 24;

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

std::string FormatDuration(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return "?";
  const auto s = static_cast<long long>(std::llround(seconds));
  if (s >= 3600) return absl::StrFormat("%d:%02d:%02d", s / 3600, s / 60 % 60, s % 60);
  return absl::StrFormat("%d:%02d", s / 60, s % 60);
}

void Progress::StartFrame(const std::string& label, uint32_t spp, double time_limit,
                          uint32_t samples) {
  label_ = label;
  spp_ = spp;
  time_limit_ = time_limit;
  first_samples_ = samples;
  start_ = last_print_ = std::chrono::steady_clock::now();
  last_fraction_ = -1.0;
}

double Progress::Elapsed() const { return Seconds(std::chrono::steady_clock::now() - start_); }

double Progress::Fraction(double samples) const {
  double fraction = spp_ > 0 ? samples / spp_ : 0.0;
  if (time_limit_ > 0.0) fraction = std::max(fraction, Elapsed() / time_limit_);
  return std::clamp(fraction, 0.0, 1.0);
}

std::string Progress::Line(double samples, double rays_per_second) const {
  const double elapsed = Elapsed();
  const double fraction = Fraction(samples);
  // What is left: the samples still to do at this run's pace, or the time limit if sooner.
  double left = -1.0;
  const double done_here = samples - first_samples_;
  if (spp_ > 0 && done_here > 0.0) left = (spp_ - samples) * elapsed / done_here;
  if (time_limit_ > 0.0) {
    const double until_limit = std::max(0.0, time_limit_ - elapsed);
    left = left < 0.0 ? until_limit : std::min(left, until_limit);
  }
  const std::string spp = spp_ > 0 ? absl::StrFormat("%.0f/%u spp", std::floor(samples), spp_)
                                   : absl::StrFormat("%.0f spp", std::floor(samples));
  const std::string rays = absl::StrFormat("%.2f Mrays/s", rays_per_second * 1e-6);
  const std::string times = absl::StrFormat("%s elapsed, %s left", FormatDuration(elapsed),
                                            left < 0.0 ? "?" : FormatDuration(left));
  if (mode_ == Mode::kBar) {
    const int filled = static_cast<int>(fraction * kBarWidth);
    return absl::StrFormat("%s [%s%s] %s  %s  %s", label_, std::string(filled, '#'),
                           std::string(kBarWidth - filled, '-'), spp, rays, times);
  }
  return absl::StrFormat("tessera render: %s: %s (%.0f%%), %s, %s", label_, spp, 100.0 * fraction,
                         rays, times);
}

void Progress::Update(double samples, double rays_per_second) {
  if (mode_ == Mode::kOff) return;
  const auto now = std::chrono::steady_clock::now();
  const double since = Seconds(now - last_print_);
  if (mode_ == Mode::kBar) {
    if (since < kBarInterval) return;
    std::fprintf(out_, "\r%s\x1b[K", Line(samples, rays_per_second).c_str());
  } else {
    const double fraction = Fraction(samples);
    if (since < kLineInterval &&
        std::floor(fraction / kLineStep) <= std::floor(last_fraction_ / kLineStep)) {
      return;
    }
    last_fraction_ = fraction;
    std::fprintf(out_, "%s\n", Line(samples, rays_per_second).c_str());
  }
  std::fflush(out_);
  last_print_ = now;
}

void Progress::FinishFrame(uint32_t samples, double rays_per_second) {
  if (mode_ == Mode::kOff) return;
  if (mode_ == Mode::kBar) {
    std::fprintf(out_, "\r%s\x1b[K\n", Line(samples, rays_per_second).c_str());
  } else {
    std::fprintf(out_, "%s\n", Line(samples, rays_per_second).c_str());
  }
  std::fflush(out_);
}

}  // namespace tessera::render
