/* Tessera's additions to the OptiX 7 host API (not in OptiX): what an application or a benchmark
 * may ask of the devices behind an OptixDeviceContext. Exported by libtessera. */
#ifndef TESSERA_OPTIX7_EXT_H_
#define TESSERA_OPTIX7_EXT_H_

#include "optix_types.h"
#include "tessera/accuracy.h"
#include "tessera/log.h" /* tesseraSetLogCallback */

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes the context's launches sent to devices (state, device memory, modules) and received from
 * them (what programs wrote to device memory) since the context was created; both 0 before its
 * first launch. OPTIX_ERROR_INVALID_VALUE for a context that is not live or null outputs. */
OptixResult tesseraOptixDeviceContextGetTransferStats(OptixDeviceContext context,
                                                      unsigned long long* bytes_sent,
                                                      unsigned long long* bytes_received);

/* The context's speed/accuracy settings for later launches and module creations:
 * TESSERA_ACCURACY_* bits (tessera/accuracy.h, docs/accuracy.md). A context starts with what
 * TESSERA_ACCURACY in the environment names (none when unset). Unknown bits:
 * OPTIX_ERROR_INVALID_VALUE. */
OptixResult tesseraOptixDeviceContextSetAccuracy(OptixDeviceContext context, unsigned int flags);
OptixResult tesseraOptixDeviceContextGetAccuracy(OptixDeviceContext context, unsigned int* flags);

/* Build flags (OptixAccelBuildOptions::buildFlags) that ask one acceleration for what the context
 * flags of the same names ask of all of them. */
#define TESSERA_OPTIX_BUILD_FLAG_ROBUST (1u << 28)
#define TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT (1u << 29)
#define TESSERA_OPTIX_BUILD_FLAG_COMPACT (1u << 30)

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_EXT_H_ */
