#include "tessera/worker/crash_report.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "thread_state.h"

namespace tessera {
namespace {

// CrashContext's text: a plain pointer in initial-exec TLS, readable from a signal handler.
__thread const char* t_crash_context __attribute__((tls_model("initial-exec"))) = nullptr;

// Async-signal-safe appends into a fixed buffer.
struct Line {
  char text[1024];
  size_t size = 0;
  void Add(const char* s) {
    while (*s != '\0' && size + 1 < sizeof(text)) text[size++] = *s++;
  }
  void AddNumber(int n) {
    char digits[16];
    int count = 0;
    unsigned u = n < 0 ? 0u : static_cast<unsigned>(n);
    do {
      digits[count++] = static_cast<char>('0' + u % 10);
      u /= 10;
    } while (u != 0 && count < 15);
    while (count > 0 && size + 1 < sizeof(text)) text[size++] = digits[--count];
  }
};

const char* SignalName(int sig) {
  switch (sig) {
    case SIGSEGV:
      return "SIGSEGV";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGILL:
      return "SIGILL";
    case SIGABRT:
      return "SIGABRT";
    default:
      return "signal";
  }
}

void OnFatalSignal(int sig) {
  Line line;
  line.Add(kCrashReportPrefix);
  line.Add("signal ");
  line.AddNumber(sig);
  line.Add(" (");
  line.Add(SignalName(sig));
  line.Add(")");
  // The thread's state is a plain initial-exec TLS pointer: reading it allocates nothing.
  const worker::ThreadState* ts = worker::t_state;
  if (ts != nullptr && ts->current != nullptr) {
    line.Add(" in ");
    line.Add(ts->current->name.c_str());
  } else if (t_crash_context != nullptr) {
    line.Add(" while ");
    line.Add(t_crash_context);
  } else {
    line.Add(" outside any program");
  }
  line.Add("\n");
  ssize_t ignored = write(STDERR_FILENO, line.text, line.size);
  (void)ignored;
  // SA_RESETHAND restored the default action: dying of the same signal keeps the exit status
  // (and a core dump, where enabled) truthful.
  raise(sig);
}

// exit() or quick_exit() called by a program (a program's own error path, say): the worker would
// otherwise end with a plain exit status, the host would take it for a lost device and run the
// tiles again on the others, and the program would end them all ("every device was lost").
// Reported as a crash naming the program, and ended with SIGABRT so that the host reads it.
void OnExitInProgram() {
  const worker::ThreadState* ts = worker::t_state;
  if (ts == nullptr || ts->current == nullptr) return;  // the worker's own exit
  Line line;
  line.Add(kCrashReportPrefix);
  line.Add("exit() called in ");
  line.Add(ts->current->name.c_str());
  line.Add("\n");
  ssize_t ignored = write(STDERR_FILENO, line.text, line.size);
  (void)ignored;
  signal(SIGABRT, SIG_DFL);  // this line, not a second one from OnFatalSignal
  abort();
}

}  // namespace

CrashContext::CrashContext(const char* what) : previous_(t_crash_context) {
  t_crash_context = what;
}

CrashContext::~CrashContext() { t_crash_context = previous_; }

void InstallCrashReporter() {
  atexit(&OnExitInProgram);
  at_quick_exit(&OnExitInProgram);
  struct sigaction action;
  memset(&action, 0, sizeof(action));
  action.sa_handler = &OnFatalSignal;
  action.sa_flags = SA_RESETHAND | SA_NODEFER;
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(sig, &action, nullptr);
}

}  // namespace tessera
