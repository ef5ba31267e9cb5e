/* Tessera's log, for applications that embed it (docs/devices.md "Logs"). Tessera writes its
 * lines (a worker that does not answer, a lost device, a race, timings when asked) to stderr as
 *   [2026-11-29 09:00:00.123] [api] [warn] device unix:/run/w1.sock not answering; ...
 * at the level TESSERA_LOG_LEVEL names (trace, debug, info, warn, error, off; default info). An
 * application can take them instead. Shared by the OptiX 3 (tessera/rt_ext.h) and OptiX 7
 * (tessera/optix7_ext.h) layers. C99-clean. */
#ifndef TESSERA_LOG_H_
#define TESSERA_LOG_H_

#if defined(__GNUC__)
#define TESSERA_LOG_API __attribute__((visibility("default")))
#else
#define TESSERA_LOG_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* A line's level, as the callback receives it. */
typedef enum TesseraLogLevel {
  TESSERA_LOG_TRACE = 0,
  TESSERA_LOG_DEBUG = 1,
  TESSERA_LOG_INFO = 2,
  TESSERA_LOG_WARN = 3,
  TESSERA_LOG_ERROR = 4,
  TESSERA_LOG_OFF = 6 /* only as a level to set: no line has it */
} TesseraLogLevel;

/* Receives one line: its level (a TesseraLogLevel), the text without time, level or component and
 * without a trailing newline (valid during the call only), and the `user` pointer given with it. */
typedef void (*TesseraLogCallback)(int level, const char* message, void* user);

/* Every line of this process's Tessera host side (libtessera: the host API, its devices, in-process
 * devices, gRPC's lines about workers) at or above TESSERA_LOG_LEVEL goes to `callback` instead of
 * stderr, one call at a time, on whichever thread logged it. Null restores stderr. Once this
 * returns, the previous callback is not running and is not called again (unless this is called
 * from inside it). Lines the callback itself logs go to stderr; it must not block for long (a
 * launch may wait for it). Workers in other processes keep their own logs. Thread-safety: any
 * thread. */
TESSERA_LOG_API void tesseraSetLogCallback(TesseraLogCallback callback, void* user);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_LOG_H_ */
