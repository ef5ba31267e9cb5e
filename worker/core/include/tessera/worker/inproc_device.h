// The in-process device: worker/core running inside the host process, fed the same proto messages
// a worker process receives.
#ifndef TESSERA_WORKER_INPROC_DEVICE_H_
#define TESSERA_WORKER_INPROC_DEVICE_H_

#include <memory>

#include "tessera/scheduler/device.h"

namespace tessera {

// `num_threads` <= 0 means one thread per core. The context's CPU_NUM_THREADS attribute, carried
// in ContextState.num_threads, overrides it per launch when nonzero.
// `results_in_rounds` (a worker process sets it): a large call on several threads sends its
// written regions to `on_result` (as kFinalTileIndex results) in up to 8 write epochs while it
// traces, so that they travel while later pieces trace instead of all after the last tile. The
// host's own in-process device does not: measured on 16 cores, applying while tracing gained
// nothing there (the host copies the results at memory speed).
std::unique_ptr<Device> CreateInprocDevice(int num_threads, bool results_in_rounds = false);

}  // namespace tessera

#endif  // TESSERA_WORKER_INPROC_DEVICE_H_
