#include "tessera/scheduler/launch_timing.h"

#include <cstdlib>

namespace tessera::scheduler {

bool LaunchTimingEnabled() {
  static const bool enabled = [] {
    const char* env = std::getenv("TESSERA_LAUNCH_TIMING");
    return env != nullptr && *env != '\0' && !(env[0] == '0' && env[1] == '\0');
  }();
  return enabled;
}

}  // namespace tessera::scheduler
