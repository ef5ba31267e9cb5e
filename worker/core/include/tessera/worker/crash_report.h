// A worker process that a program crashes (a null dereference in a closest-hit program, say)
// leaves one line on stderr naming the program, so that the host can fail the launch with a
// message naming the device and the program instead of a bare "connection lost".
#ifndef TESSERA_WORKER_CRASH_REPORT_H_
#define TESSERA_WORKER_CRASH_REPORT_H_

#include "tessera/scheduler/device.h"  // kCrashReportPrefix

namespace tessera {

// Installs handlers for SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT that write
//   tessera-worker: crashed: signal 11 (SIGSEGV) in closest hit program 'f' in /m.so
// to stderr and then die of the same signal. Only for worker processes: an application that
// embeds Tessera keeps its own handlers.
void InstallCrashReporter();

// What the calling thread does outside programs while it lives, for the crash line: a module
// whose static constructor crashes reads "signal 11 (SIGSEGV) while loading program module m.cu
// (cached as …)" instead of "outside any program". `what` must outlive the scope.
class CrashContext {
 public:
  explicit CrashContext(const char* what);
  ~CrashContext();
  CrashContext(const CrashContext&) = delete;
  CrashContext& operator=(const CrashContext&) = delete;

 private:
  const char* const previous_;
};

}  // namespace tessera

#endif  // TESSERA_WORKER_CRASH_REPORT_H_
