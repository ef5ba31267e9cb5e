// TESSERA_LAUNCH_TIMING=1: host, in-process devices and workers each write one line per launch or
// call on stderr with where the time went (docs/devices.md "Environment"). The pieces they share.
#ifndef TESSERA_SCHEDULER_LAUNCH_TIMING_H_
#define TESSERA_SCHEDULER_LAUNCH_TIMING_H_

#include <sys/resource.h>

namespace tessera::scheduler {

// Whether TESSERA_LAUNCH_TIMING is set to something other than "" or "0" (read once).
bool LaunchTimingEnabled();

// Milliseconds from `from` to `to` (getrusage times).
inline double Milliseconds(const timeval& to, const timeval& from) {
  return 1e3 * static_cast<double>(to.tv_sec - from.tv_sec) + 1e-3 * (to.tv_usec - from.tv_usec);
}

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_LAUNCH_TIMING_H_
