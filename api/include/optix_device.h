/* optix_device.h: the program-side API (OptiX's optix.h includes it under __CUDACC__; a file that
 * includes it by name gets it in any C++ translation unit), with the host API beside it. */
#ifndef TESSERA_OPTIX_DEVICE_H_
#define TESSERA_OPTIX_DEVICE_H_

// clang-format off: before every other #include (see there)
#include "tessera/detail/program_prelude.h"
// clang-format on
#include "tessera/rt.h"
#ifndef RT_HOSTDEVICE
#define RT_HOSTDEVICE
#endif
#ifdef __cplusplus
#include "tessera/device.h"
#endif
#endif
