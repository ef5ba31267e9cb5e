// The in-process device: worker/core running inside the host process, fed the same proto messages
// a worker process receives.
#ifndef TESSERA_WORKER_INPROC_DEVICE_H_
#define TESSERA_WORKER_INPROC_DEVICE_H_

#include <memory>

#include "tessera/scheduler/device.h"

namespace tessera {

// `num_threads` <= 0 means one thread per core. The context's CPU_NUM_THREADS attribute, carried
// in ContextState.num_threads, overrides it per launch when nonzero.
std::unique_ptr<Device> CreateInprocDevice(int num_threads);

}  // namespace tessera

#endif  // TESSERA_WORKER_INPROC_DEVICE_H_
