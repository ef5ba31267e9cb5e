#include "tessera/worker/crash_report.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>

#include "thread_state.h"

namespace tessera {
namespace {

// CrashContext's text: a plain pointer in initial-exec TLS, readable from a signal handler.
__thread const char* t_crash_context __attribute__((tls_model("initial-exec"))) = nullptr;

// The program this thread last ran, kept when its ThreadState went (KeepProgramForExitReport):
// exit() destroys the calling thread's thread_local objects, the state among them, before its
// atexit handlers run. A plain initial-exec pointer that no destructor touches. The program it
// points to lives in its launch plan, which a program calling exit() is still running.
std::atomic<Optix7ProgramQuery> g_optix7_query{nullptr};

__thread const worker::BoundProgram* t_exit_program __attribute__((tls_model("initial-exec"))) =
    nullptr;

// Set by InstallCrashReporter: only a worker process gives its threads alternate signal stacks.
std::atomic<bool> g_installed{false};

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
  // The thread's state is a plain initial-exec TLS pointer: reading it allocates nothing. It is
  // null again once the state was freed (~ThreadState).
  const worker::ThreadState* ts = worker::t_state;
  const Optix7ProgramQuery optix7 = g_optix7_query.load(std::memory_order_acquire);
  const char* optix7_kind = nullptr;
  const char* optix7_name = nullptr;
  if (ts != nullptr && ts->current != nullptr) {
    line.Add(" in ");
    line.Add(ts->current->name.c_str());
  } else if (optix7 != nullptr && optix7(&optix7_kind, &optix7_name)) {
    line.Add(" in OptiX 7 ");
    line.Add(optix7_kind);
    line.Add(" program ");
    line.Add(optix7_name);
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
  // exit() has destroyed this thread's thread_local objects by now, its ThreadState among them,
  // whose destructor cleared t_state and kept the running program in t_exit_program;
  // quick_exit() destroys none, so the state is still there. Either way nothing freed is read.
  const worker::ThreadState* ts = worker::t_state;
  const worker::BoundProgram* program = ts != nullptr ? ts->current : t_exit_program;
  if (program == nullptr) return;  // the worker's own exit, or a thread that never ran a program
  Line line;
  line.Add(kCrashReportPrefix);
  line.Add("exit() called in ");
  line.Add(program->name.c_str());
  line.Add("\n");
  ssize_t ignored = write(STDERR_FILENO, line.text, line.size);
  (void)ignored;
  signal(SIGABRT, SIG_DFL);  // this line, not a second one from OnFatalSignal
  abort();
}

// A thread's alternate signal stack, with a guard page below it (a handler that overflows it
// faults instead of writing over other memory), removed and unmapped when the thread ends.
class AltSignalStack {
 public:
  AltSignalStack() {
    stack_t current{};
    // A thread that has one (an application's, a sanitizer's) keeps it.
    if (sigaltstack(nullptr, &current) != 0 || (current.ss_flags & SS_DISABLE) == 0) return;
    page_ = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    const size_t wanted = std::max<size_t>(kAltSignalStackBytes, 4 * static_cast<size_t>(SIGSTKSZ));
    size_ = (wanted + page_ - 1) / page_ * page_;
    void* mapping = mmap(nullptr, page_ + size_, PROT_READ | PROT_WRITE,
                         MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK | MAP_NORESERVE, -1, 0);
    if (mapping == MAP_FAILED) return;  // no report on overflow, as before; nothing else changes
    if (mprotect(mapping, page_, PROT_NONE) != 0) {
      munmap(mapping, page_ + size_);
      return;
    }
    stack_t stack{};
    stack.ss_sp = static_cast<char*>(mapping) + page_;
    stack.ss_size = size_;
    if (sigaltstack(&stack, nullptr) != 0) {
      munmap(mapping, page_ + size_);
      return;
    }
    mapping_ = mapping;
  }
  ~AltSignalStack() {
    if (mapping_ == nullptr) return;
    stack_t current{};
    if (sigaltstack(nullptr, &current) == 0 && (current.ss_flags & SS_DISABLE) == 0 &&
        current.ss_sp == static_cast<char*>(mapping_) + page_) {
      stack_t off{};
      off.ss_flags = SS_DISABLE;
      // Fails only while running on it (never in a destructor at thread exit): keep the memory
      // then rather than pull the stack from under a handler.
      if (sigaltstack(&off, nullptr) != 0) return;
    }
    munmap(mapping_, page_ + size_);
  }
  AltSignalStack(const AltSignalStack&) = delete;
  AltSignalStack& operator=(const AltSignalStack&) = delete;

 private:
  void* mapping_ = nullptr;
  size_t page_ = 0;
  size_t size_ = 0;
};

}  // namespace

CrashContext::CrashContext(const char* what) : previous_(t_crash_context) {
  // A module's static constructors run here, on whichever thread loads it.
  EnsureAltSignalStack();
  t_crash_context = what;
}

CrashContext::~CrashContext() { t_crash_context = previous_; }

void EnsureAltSignalStack() {
  if (!g_installed.load(std::memory_order_relaxed)) return;
  // Constructed at the thread's first call, destroyed when the thread ends.
  thread_local AltSignalStack stack;
  (void)stack;
}

void InstallCrashReporter() {
  g_installed.store(true, std::memory_order_relaxed);
  atexit(&OnExitInProgram);
  at_quick_exit(&OnExitInProgram);
  struct sigaction action;
  memset(&action, 0, sizeof(action));
  action.sa_handler = &OnFatalSignal;
  // SA_ONSTACK: on the thread's alternate stack where it has one (EnsureAltSignalStack), the only
  // stack left to a thread whose program overflowed its own; elsewhere on the thread's stack.
  action.sa_flags = SA_RESETHAND | SA_NODEFER | SA_ONSTACK;
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) sigaction(sig, &action, nullptr);
}

void SetOptix7ProgramQuery(Optix7ProgramQuery query) {
  g_optix7_query.store(query, std::memory_order_release);
}

namespace worker {

void KeepProgramForExitReport(const BoundProgram* program) { t_exit_program = program; }

}  // namespace worker
}  // namespace tessera
