#include "cuda_devices.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "tessera/scheduler/log.h"

namespace tessera::optix7 {
namespace {

std::atomic<TesseraDeviceLister> g_lister{nullptr};
// CUDA's current device is per host thread; a new thread starts on device 0.
thread_local int t_current_device = 0;

}  // namespace

CudaDeviceMode CudaDeviceModeFromEnvironment() {
  const char* env = std::getenv("TESSERA_CUDA_DEVICES");
  const std::string value = env == nullptr ? "" : env;
  if (value.empty() || value == "one") return CudaDeviceMode::kOne;
  if (value == "each") return CudaDeviceMode::kEach;
  // A typo must not silently change how many GPUs an application believes it has.
  static std::atomic<bool> said{false};
  if (!said.exchange(true)) {
    log::Warn(log::Component::kApi,
              "TESSERA_CUDA_DEVICES='%s' is neither 'one' nor 'each'; using 'one' (one CUDA device "
              "tiled over every device of TESSERA_DEVICES)",
              value);
  }
  return CudaDeviceMode::kOne;
}

absl::StatusOr<std::vector<CudaDevice>> CudaDevices() {
  TesseraDeviceLister lister = g_lister.load();
  if (CudaDeviceModeFromEnvironment() == CudaDeviceMode::kEach && lister != nullptr) {
    return lister();
  }
  // Its launches run on every Tessera device, so it has every core of this machine.
  return std::vector<CudaDevice>{
      {"Tessera CPU device", static_cast<int>(std::thread::hardware_concurrency())}};
}

void SetTesseraDeviceLister(TesseraDeviceLister lister) { g_lister.store(lister); }

int CurrentCudaDevice() { return t_current_device; }
void SetCurrentCudaDevice(int device) { t_current_device = device; }

int LaunchDeviceForNewContext() {
  return CudaDeviceModeFromEnvironment() == CudaDeviceMode::kEach ? t_current_device : kEveryDevice;
}

}  // namespace tessera::optix7
