/* Tessera extensions to the OptiX 3 host API. Every name carries a `tessera` prefix; the
 * functions follow rt.h conventions (RTresult, rtContextGetErrorString for details). C99-clean. */
#ifndef TESSERA_RT_EXT_H_
#define TESSERA_RT_EXT_H_

#include "tessera/accuracy.h"
#include "tessera/log.h" /* tesseraSetLogCallback */
#include "tessera/rt.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Replaces the context's device list with the devices `spec` names ("inproc", "local:N",
 * "HOST:PORT", "unix:PATH", comma-separated; see docs/devices.md "Device specs") and selects all of
 * them. Devices that cannot be created in this release: RT_ERROR_NOT_SUPPORTED. */
RTAPI RTresult tesseraContextSetDeviceSpec(RTcontext context, const char* spec);

/* Checks the syntax of a device spec. On RT_ERROR_INVALID_VALUE, `*error` (if `error` is not
 * null) points at a message naming the bad entry, valid until the calling thread's next call;
 * on success it is set to null. Thread-safety: any thread. */
RTAPI RTresult tesseraDeviceSpecValidate(const char* spec, const char** error);

/* Where device `ordinal` (as for rtDeviceGetAttribute) lives: "inproc", "local:N/i" (the i-th
 * worker process the host spawns for a local:N entry), "HOST:PORT" or "unix:PATH". Copies at most
 * `size` bytes into `address`, always NUL-terminated, as RT_DEVICE_ATTRIBUTE_NAME does. */
RTAPI RTresult tesseraDeviceGetAddress(int ordinal, RTsize size, char* address);

/* The number of exceptions devices reported (ExceptionReport) during the context's last
 * launch. */
RTAPI RTresult tesseraContextGetExceptionReportCount(RTcontext context, RTsize* count);

/* Whether the context's last launch traced its launch indices' first rays as Embree packets
 * (batched tracing: TESSERA_BATCHING=1, or =auto and chosen for its entry point from what the
 * entry's earlier launches measured; docs/programs.md "Batched tracing"). 0 before any launch,
 * and after one that ended before it traced (invalid, or cancelled while state shipped). */
RTAPI RTresult tesseraContextGetLastLaunchBatched(RTcontext context, int* batched);

/* Bytes of buffer contents that travelled for this context's launches since it was created:
 * host → devices (chunks of state deltas) and devices → host (written regions of OUTPUT and
 * INPUT_OUTPUT buffers). Either pointer may be null. */
RTAPI RTresult tesseraContextGetTransferStats(RTcontext context, unsigned long long* bytes_sent,
                                              unsigned long long* bytes_received);

/* The tile size of later launches: `dimensionality` entries (1..3) of `size`, each > 0; a launch
 * of other dimensionality repeats the last entry. 0 and null restore the automatic choice (from
 * the launch size and the devices' thread count, or TESSERA_TILE_SIZE such as "32x32"). */
RTAPI RTresult tesseraContextSetTileSize(RTcontext context, unsigned int dimensionality,
                                         const RTsize* size);

/* Race checking for multi-device launches: when on (or with TESSERA_RACE_CHECK=1 in the
 * environment), the host reports on stderr every element of a shared OUTPUT or INPUT_OUTPUT
 * buffer that two devices set to different values in one launch (the multi-GPU race OptiX leaves
 * undefined), naming the buffer, the element and the devices. Costs a copy of those buffers and a
 * comparison per gathered element. */
RTAPI RTresult tesseraContextSetRaceCheck(RTcontext context, int enabled);
/* How many elements the last launch found written by two devices (0 unless checking). */
RTAPI RTresult tesseraContextGetRaceCount(RTcontext context, RTsize* count);

/* How far the running launch got: tiles the devices finished, and tiles in all. Call it from the
 * timeout callback (which runs on the launching thread during long launches) or from another
 * thread to show progress; devices say how far a long call got about every 0.1 s, before its
 * results reach the host. Tiles done go down only when a device is lost during the launch (its
 * unfinished call's tiles run again elsewhere). After a launch it gives that launch's final
 * figures (done < total when it failed or was cancelled). Before any launch both are 0. Either
 * pointer may be null. */
RTAPI RTresult tesseraContextGetLaunchProgress(RTcontext context, RTsize* tiles_done,
                                               RTsize* tiles_total);

/* The context's speed/accuracy settings for later launches: TESSERA_ACCURACY_* bits
 * (tessera/accuracy.h, docs/accuracy.md). A context starts with what TESSERA_ACCURACY in the
 * environment names (none when unset). Unknown bits: RT_ERROR_INVALID_VALUE. An acceleration's
 * properties "robust", "watertight" and "compact" ("1") ask the same of that one acceleration. */
RTAPI RTresult tesseraContextSetAccuracy(RTcontext context, unsigned int flags);
RTAPI RTresult tesseraContextGetAccuracy(RTcontext context, unsigned int* flags);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_RT_EXT_H_ */
