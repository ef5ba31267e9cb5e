// The module cache's hook into the OptiX 7 engine (module.cc): a module without an OptiX 3
// registry may be an OptiX 7 one, which receives the engine's TesseraOptix7Runtime table through
// its exported tessera_optix7_module_init. Kept apart from optix7_engine.h so that module.cc
// needs none of the OptiX 7 headers.
#ifndef TESSERA_WORKER_CORE_OPTIX7_MODULE_INIT_H_
#define TESSERA_WORKER_CORE_OPTIX7_MODULE_INIT_H_

#include <string>

#include "absl/status/statusor.h"

namespace tessera::worker {

inline constexpr char kOptix7ModuleInitSymbol[] = "tessera_optix7_module_init";
// TESSERA_OPTIX7_MODULE_FLAGS_SYMBOL and TESSERA_OPTIX7_MODULE_FLAG_FAST_MATH
// (tessera/optix7_device_abi.h; optix7_engine.cc checks they agree).
inline constexpr char kOptix7ModuleFlagsSymbol[] = "tessera_optix7_module_flags";
inline constexpr unsigned kOptix7ModuleFlagFastMath = 0x1u;

// Hands the OptiX 7 engine's table to the module loaded at `handle` (named `path` in messages):
// false when it exports no kOptix7ModuleInitSymbol, FAILED_PRECONDITION when it was built against
// another TESSERA_OPTIX7_MODULE_ABI_VERSION.
absl::StatusOr<bool> InitOptix7Module(void* handle, const std::string& path);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_MODULE_INIT_H_
