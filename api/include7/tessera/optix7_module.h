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

// TESSERA_FAST_MATH comes with tessera_add_optix7_program_module(... FAST_MATH) and the host's
// compile for a context with TESSERA_ACCURACY_FAST_MATH; plain -ffast-math defines __FAST_MATH__.
// `extern`: a const variable of C++ is otherwise not exported.
__attribute__((weak, visibility("default"))) extern const unsigned int tessera_optix7_module_flags =
#if defined(TESSERA_FAST_MATH) || defined(__FAST_MATH__)
    TESSERA_OPTIX7_MODULE_FLAG_FAST_MATH;
#else
    0;
#endif
}

#endif /* TESSERA_OPTIX7_MODULE_H_ */
