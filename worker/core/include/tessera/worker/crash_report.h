// A worker process that a program crashes (a null dereference in a closest-hit program, say)
// leaves one line on stderr naming the program, so that the host can fail the launch with a
// message naming the device and the program instead of a bare "connection lost".
#ifndef TESSERA_WORKER_CRASH_REPORT_H_
#define TESSERA_WORKER_CRASH_REPORT_H_

#include <cstddef>

#include "tessera/scheduler/device.h"  // kCrashReportPrefix

namespace tessera {

// Installs handlers for SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT that write
//   tessera-worker: crashed: signal 11 (SIGSEGV) in closest hit program 'f' in /m.so
// to stderr and then die of the same signal, and an exit()/quick_exit() hook that reports
//   tessera-worker: crashed: exit() called in closest hit program 'f' in /m.so
// when a program ends the process. The handlers run on the alternate signal stack of threads
// that have one (EnsureAltSignalStack), so a program that overflows its stack is reported too.
// Only for worker processes: an application that embeds Tessera keeps its own handlers.
void InstallCrashReporter();

// Bytes of the alternate signal stack EnsureAltSignalStack gives a thread (a guard page below
// it is extra): the handler needs a few KiB, the kernel's signal frame up to a few more (AVX-512
// state), and the rest is margin.
inline constexpr size_t kAltSignalStackBytes = 64 * 1024;

// Gives the calling thread an alternate signal stack, once, in a process that installed the crash
// reporter (elsewhere it does nothing), unless the thread has one already. Without it a thread
// whose stack overflowed has no stack left to run the SIGSEGV handler on, and dies without a
// report. Freed when the thread ends. Every thread that runs program code calls it: the first
// use of its ThreadState does (tiles, bounding box programs, on any pool or thread), and so does
// CrashContext (a module's static constructors).
void EnsureAltSignalStack();

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

// What OptiX 7 program the calling thread runs, for the crash line: its kind ("closest-hit") and
// name ("__closesthit__ch in /m.so"); false when it runs none. Set once by the OptiX 7 engine;
// must be async-signal-safe (it runs in the fatal signal's handler).
using Optix7ProgramQuery = bool (*)(const char** kind, const char** name);
void SetOptix7ProgramQuery(Optix7ProgramQuery query);

}  // namespace tessera

#endif  // TESSERA_WORKER_CRASH_REPORT_H_
