// The CUDA devices an OptiX 7 application sees (docs/optix7.md, "Devices"): by default one, whose
// launches are tiled over every Tessera device of TESSERA_DEVICES; with TESSERA_CUDA_DEVICES=each,
// one per Tessera device, so that applications written for several GPUs run on 1..N of them.
// Includes no optix.h of either root: launch_target.cc (OptiX 3 root, api/src) lists the Tessera
// devices, the CUDA runtime (OptiX 7 root) reports them.
#ifndef TESSERA_API_OPTIX7_CUDA_DEVICES_H_
#define TESSERA_API_OPTIX7_CUDA_DEVICES_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::optix7 {

enum class CudaDeviceMode { kOne, kEach };

// TESSERA_CUDA_DEVICES, read at every call (as TESSERA_DEVICES is): unset, blank or "one" is
// kOne, "each" kEach; anything else is said once on stderr and kOne used.
CudaDeviceMode CudaDeviceModeFromEnvironment();

struct CudaDevice {
  std::string name;  // cudaDeviceProp::name
  int threads = 0;   // cudaDeviceProp::multiProcessorCount
};

// The CUDA devices of the current mode, ordinal by ordinal: one standing for every Tessera device,
// or each Tessera device of TESSERA_DEVICES (an error naming TESSERA_DEVICES when it is bad).
absl::StatusOr<std::vector<CudaDevice>> CudaDevices();

// How CudaDevices lists Tessera devices; launch_target.cc installs it when libtessera loads
// (objects linked without api_core, as tests/optix7's are, see a single device).
using TesseraDeviceLister = absl::StatusOr<std::vector<CudaDevice>> (*)();
void SetTesseraDeviceLister(TesseraDeviceLister lister);

// The calling thread's current CUDA device (cudaSetDevice; 0 in a thread that set none).
int CurrentCudaDevice();
void SetCurrentCudaDevice(int device);

// Which Tessera device launches of an OptixDeviceContext made on the calling thread now run on:
// kEveryDevice in the default mode, else the current CUDA device's ordinal.
constexpr int kEveryDevice = -1;
int LaunchDeviceForNewContext();

// The CUDA device of a live CUcontext (cuCtxCreate, cuCtxGetCurrent: cuda_driver.cc), or -1 for
// anything else (0 included).
int CudaDeviceOfContext(const void* context);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_CUDA_DEVICES_H_
