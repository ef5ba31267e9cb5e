/* OptiX compatibility: from C, the host API; from C++, the host API and the program-side API,
 * as OptiX's own optix.h gives both. */
#ifndef TESSERA_OPTIX_H_
#define TESSERA_OPTIX_H_
#include "tessera/rt.h"
#ifdef __cplusplus
#include "tessera/device.h"
#endif
#endif
