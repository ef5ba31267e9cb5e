// The in-process device: worker/core running inside the host process, fed the same proto messages
// a worker process receives.
#ifndef TESSERA_WORKER_INPROC_DEVICE_H_
#define TESSERA_WORKER_INPROC_DEVICE_H_

#include <memory>

#include "tessera/scheduler/device.h"

namespace tessera {

// `num_threads` <= 0 means one thread per core. The context's CPU_NUM_THREADS attribute, carried
// in ContextState.num_threads, overrides it per launch when nonzero.
// `results_in_rounds` (a worker process sets it): a large call on several threads runs in up to 8
// rounds, and each round's written regions go to `on_result` (as kFinalTileIndex results) when it
// ends, so that they travel while the next round traces instead of all after the last tile.
std::unique_ptr<Device> CreateInprocDevice(int num_threads, bool results_in_rounds = false);

}  // namespace tessera

#endif  // TESSERA_WORKER_INPROC_DEVICE_H_
