#include "auto_batching.h"

#include <string_view>

namespace tessera::api {

AutoBatching::Mode AutoBatching::Parse(const char* value, std::string* warning) {
  const std::string_view v = value != nullptr ? value : "";
  if (v.empty() || v == "0") return Mode::kNever;
  if (v == "1") return Mode::kAlways;
  if (v == "auto") return Mode::kAuto;
  *warning = "TESSERA_BATCHING=" + std::string(v) + " is not 1, 0 or auto; tracing single rays";
  return Mode::kNever;
}

bool AutoBatching::Choose(unsigned entry, const void* program) {
  Entry& e = At(entry);
  if (e.program != program) e = Entry{State::kWatching, program};
  return e.state == State::kOn;
}

bool AutoBatching::Record(unsigned entry, uint64_t indices, uint64_t traces,
                          uint64_t packet_answers) {
  if (indices == 0) return false;
  Entry& e = At(entry);
  const double n = static_cast<double>(indices);
  const bool few_rays = static_cast<double>(traces) <= kMaxTracesPerIndex * n;
  const bool answered = static_cast<double>(packet_answers) >= kMinAnswered * n;
  const State before = e.state;
  switch (e.state) {
    case State::kWatching:
      if (few_rays) e.state = State::kOn;
      break;
    case State::kOn:
      e.state = few_rays && answered ? State::kOn : State::kOff;
      break;
    case State::kOff:
      break;
  }
  return e.state != before;
}

const char* ToString(AutoBatching::State s) {
  switch (s) {
    case AutoBatching::State::kWatching:
      return "single rays, watching";
    case AutoBatching::State::kOn:
      return "packets";
    case AutoBatching::State::kOff:
      return "single rays";
  }
  return "?";
}

}  // namespace tessera::api
