/* optix_device.h: the same as optix.h (OptiX programs include either). */
#ifndef TESSERA_OPTIX_DEVICE_H_
#define TESSERA_OPTIX_DEVICE_H_
#include "tessera/rt.h"
#ifdef __cplusplus
#include "tessera/device.h"
#endif
#endif
