// Installs worker/core's in-process device into libtessera when worker/core is part of the
// build (TESSERA_HAVE_WORKER_CORE, set by api/CMakeLists.txt). Kept out of tessera::api_core so
// the core can be tested with fake devices alone.
#include "device_table.h"

#ifdef TESSERA_HAVE_WORKER_CORE
#include "tessera/worker/inproc_device.h"

namespace tessera::api {
namespace {

std::unique_ptr<Device> MakeInprocDevice(int num_threads) {
  // Written regions go out in rounds while the launch traces, as a worker's do: on 16 cores a
  // 30 ms launch (1024x1024 primary rays) took 25.6 instead of 27.3 ms (medians of five pairs).
  return CreateInprocDevice(num_threads, /*results_in_rounds=*/true,
                            /*shares_host_memory=*/true);
}

[[maybe_unused]] const bool kInstalled = [] {
  SetInprocDeviceFactory(&MakeInprocDevice);
  return true;
}();

}  // namespace
}  // namespace tessera::api
#endif
