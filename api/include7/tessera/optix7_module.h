/* The module side of the engine ABI (tessera/optix7_device_abi.h): the engine's table for this
 * module's programs, set once by tessera_optix7_module_init, before any program runs. Included by
 * optix_device.h and by device_atomic_functions.h (cuda_runtime.h includes that one in programs),
 * whichever a program includes first. Weak definitions, so that every translation unit of a
 * module may include this header and the module still has one of each. */
#ifndef TESSERA_OPTIX7_MODULE_H_
#define TESSERA_OPTIX7_MODULE_H_

#include "tessera/optix7_device_abi.h"

extern "C" {
__attribute__((weak, visibility("default"))) const TesseraOptix7Runtime* tessera_optix7_runtime =
    nullptr;

__attribute__((weak, visibility("default"))) unsigned int tessera_optix7_module_init(
    const TesseraOptix7Runtime* runtime, unsigned int abi_version) {
  if (abi_version != TESSERA_OPTIX7_MODULE_ABI_VERSION || !runtime ||
      runtime->abi_version != TESSERA_OPTIX7_MODULE_ABI_VERSION)
    return TESSERA_OPTIX7_MODULE_ABI_VERSION;
  tessera_optix7_runtime = runtime;
  return 0;
}
}

#endif /* TESSERA_OPTIX7_MODULE_H_ */
