/* Tessera extensions to the OptiX 3 host API. Every name carries a `tessera` prefix; the
 * functions follow rt.h conventions (RTresult, rtContextGetErrorString for details). C99-clean. */
#ifndef TESSERA_RT_EXT_H_
#define TESSERA_RT_EXT_H_

#include "tessera/rt.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Replaces the context's device list with the devices `spec` names ("inproc", "local:N",
 * "HOST:PORT", "unix:PATH", comma-separated; see DESIGN.md "Devices") and selects all of them.
 * Devices that cannot be created in this release: RT_ERROR_NOT_SUPPORTED. */
RTAPI RTresult tesseraContextSetDeviceSpec(RTcontext context, const char* spec);

/* Checks the syntax of a device spec. On RT_ERROR_INVALID_VALUE, `*error` (if `error` is not
 * null) points at a message naming the bad entry, valid until the calling thread's next call;
 * on success it is set to null. Thread-safety: any thread. */
RTAPI RTresult tesseraDeviceSpecValidate(const char* spec, const char** error);

/* The number of exceptions devices reported (ExceptionReport) during the context's last
 * launch. */
RTAPI RTresult tesseraContextGetExceptionReportCount(RTcontext context, RTsize* count);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_RT_EXT_H_ */
