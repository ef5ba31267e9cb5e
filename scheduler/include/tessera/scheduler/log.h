// Tessera's log: one format for host and worker lines, with time and level, through spdlog
// (docs/logging.md). A logger per component names who speaks:
//
//   [2026-11-29 09:00:00.123] [api] [warn] device unix:/run/w1.sock not answering; ...
//
// The level comes from TESSERA_LOG_LEVEL (trace, debug, info, warn, error, off; default info), or
// from SetLevel (tessera-worker --log-level). Lines go to stderr, or to the callback an embedding
// application installed (tesseraSetLogCallback, tessera/log.h). spdlog stays behind this header:
// callers format with absl::StrFormat, and no global spdlog state (its registry, its default
// logger) is touched, so an application's own spdlog use is left alone.
#ifndef TESSERA_SCHEDULER_LOG_H_
#define TESSERA_SCHEDULER_LOG_H_

#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/str_format.h"
#include "absl/strings/string_view.h"

namespace tessera::log {

// The values of TesseraLogLevel (tessera/log.h), which are spdlog's.
enum class Level : int { kTrace = 0, kDebug = 1, kInfo = 2, kWarn = 3, kError = 4, kOff = 6 };

// Who speaks: the name in the line's second bracket.
enum class Component : int {
  kApi,        // "api": libtessera's host API (OptiX 3 and OptiX 7 layers)
  kScheduler,  // "scheduler": tiles, devices and their transport, on the host
  kWorker,     // "worker": the engine (worker/core, also in-process) and tessera-worker
  kRender,     // "render": tessera render
  kGrpc,       // "grpc": gRPC's own lines (RouteGrpcLogs)
};

// The level in effect: SetLevel's, else TESSERA_LOG_LEVEL's (read once; a value that is not a
// level is said once, as a warning, and info used), else info.
Level CurrentLevel();
// From now on, overriding TESSERA_LOG_LEVEL. Thread-safety: any thread.
void SetLevel(Level level);
// "trace", "debug", "info", "warn" (or "warning"), "error", "off", in any case; INVALID_ARGUMENT
// naming the text and the levels otherwise.
absl::StatusOr<Level> ParseLevel(absl::string_view text);
const char* LevelName(Level level);

// Whether a line at `level` would be written now (cheap: one atomic load).
bool Enabled(Level level);

// Writes one line (a trailing newline is dropped) if `level` is enabled. Thread-safety: any
// thread; lines are written whole, one at a time.
void Write(Component component, Level level, absl::string_view message);

template <typename... Args>
void Log(Component component, Level level, const absl::FormatSpec<Args...>& format,
         const Args&... args) {
  if (Enabled(level)) Write(component, level, absl::StrFormat(format, args...));
}
template <typename... Args>
void Trace(Component c, const absl::FormatSpec<Args...>& format, const Args&... args) {
  Log(c, Level::kTrace, format, args...);
}
template <typename... Args>
void Debug(Component c, const absl::FormatSpec<Args...>& format, const Args&... args) {
  Log(c, Level::kDebug, format, args...);
}
template <typename... Args>
void Info(Component c, const absl::FormatSpec<Args...>& format, const Args&... args) {
  Log(c, Level::kInfo, format, args...);
}
template <typename... Args>
void Warn(Component c, const absl::FormatSpec<Args...>& format, const Args&... args) {
  Log(c, Level::kWarn, format, args...);
}
template <typename... Args>
void Error(Component c, const absl::FormatSpec<Args...>& format, const Args&... args) {
  Log(c, Level::kError, format, args...);
}

// Where lines go instead of stderr: `callback(level, message, user)` for every enabled line, the
// message without time, level or component, one call at a time. Null restores stderr. Once this
// returns, the previous callback is not running and will not be called again (unless this is
// called from inside it). A line the callback itself logs goes to stderr. Thread-safety: any
// thread.
using Callback = void (*)(int level, const char* message, void* user);
void SetCallback(Callback callback, void* user);

// A line as written to stderr, "[time] [component] [level] message", split back into its level
// and message (for a host that passes on what a worker it spawned printed). False for a line of
// another form.
bool ParseLine(absl::string_view line, Level* level, absl::string_view* message);

}  // namespace tessera::log

#endif  // TESSERA_SCHEDULER_LOG_H_
