// The in-process device: worker/core running inside the host process, fed the same proto messages
// a worker process receives.
#ifndef TESSERA_WORKER_INPROC_DEVICE_H_
#define TESSERA_WORKER_INPROC_DEVICE_H_

#include <memory>

#include "tessera/scheduler/device.h"

namespace tessera {

// `num_threads` <= 0 means one thread per core. The context's CPU_NUM_THREADS attribute, carried
// in ContextState.num_threads, overrides it per launch when nonzero.
// `results_in_rounds` (worker processes and the host's in-process device set it): a large call
// on several threads sends its written regions to `on_result` (as kFinalTileIndex results) in up
// to 8 write epochs while it traces, so that they travel, or are applied, while later pieces trace
// instead of all after the last tile. For the host's device the gain shows in short launches: on
// 16 cores, 1024x1024 primary rays took 25.6 instead of 27.3 ms (the tutorial's 0.16 s launches
// timed the same either way).
// `shares_host_memory` (the host's in-process device sets it): OptiX 7 device memory is the
// host's own (the same process), so deltas carry no bytes of it and written ranges go back
// without their bytes; a worker process's device keeps a copy at the same addresses.
std::unique_ptr<Device> CreateInprocDevice(int num_threads, bool results_in_rounds = false,
                                           bool shares_host_memory = false);

// Says on stderr, once per process, when TESSERA_INTERRUPT_SIGNAL holds something unusable
// (docs/devices.md). The host calls it before it starts workers, which would say so only in their
// logs.
void CheckInterruptSignal();

}  // namespace tessera

#endif  // TESSERA_WORKER_INPROC_DEVICE_H_
