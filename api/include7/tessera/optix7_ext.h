/* Tessera's additions to the OptiX 7 host API (not in OptiX): what an application or a benchmark
 * may ask of the devices behind an OptixDeviceContext. Exported by libtessera. */
#ifndef TESSERA_OPTIX7_EXT_H_
#define TESSERA_OPTIX7_EXT_H_

#include "optix_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes the context's launches sent to devices (state, device memory, modules) and received from
 * them (what programs wrote to device memory) since the context was created; both 0 before its
 * first launch. OPTIX_ERROR_INVALID_VALUE for a context that is not live or null outputs. */
OptixResult tesseraOptixDeviceContextGetTransferStats(OptixDeviceContext context,
                                                      unsigned long long* bytes_sent,
                                                      unsigned long long* bytes_received);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_EXT_H_ */
