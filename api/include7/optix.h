/* The header OptiX 7 code includes, host code and programs alike: in a program module (compiled
 * with -D__CUDACC__, as nvcc defines it) the device API (optix_device.h), otherwise the host API
 * (optix_host.h). This is the OptiX 7 include root of Tessera (api/include7, installed as
 * include/tessera/optix7); OptiX 3-6 code uses the other root (api/include, include/tessera),
 * whose optix.h has the same name, as two SDK installs would. Nothing here includes the OptiX 3
 * headers. docs/optix7.md says what is declared and what is implemented. */
#ifndef TESSERA_OPTIX7_OPTIX_H_
#define TESSERA_OPTIX7_OPTIX_H_

#include "tessera/optix7_version.h"

#ifdef __CUDACC__
#include "optix_device.h"
#else
#include "optix_host.h"
#endif

#endif /* TESSERA_OPTIX7_OPTIX_H_ */
