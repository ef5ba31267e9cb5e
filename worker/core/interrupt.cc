#include "interrupt.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#include <sanitizer/common_interface_defs.h>
#endif

#include <cxxabi.h>
#include <dlfcn.h>
#include <link.h>
#include <pthread.h>
#include <signal.h>
#include <ucontext.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

#include "tessera/scheduler/log.h"
#include "tessera/worker/inproc_device.h"  // CheckInterruptSignal

namespace tessera::worker {

__thread volatile bool t_interrupt_requested __attribute__((tls_model("initial-exec"))) = false;

namespace {

using Clock = std::chrono::steady_clock;

// A launch index that returns at all normally ends well within kGrace of a cancel (tiles check
// between indices); only then do signals start, one every kPeriod while the thread stays, and one
// every kFastPeriod once it has stayed kSlow: a loop that spends nearly all its time in a library
// (the C++ unwinder, say) gives each signal little chance to land in program code.
constexpr auto kGrace = std::chrono::milliseconds(50);
constexpr auto kPeriod = std::chrono::milliseconds(20);
constexpr auto kSlow = std::chrono::milliseconds(250);
constexpr auto kFastPeriod = std::chrono::milliseconds(1);

// ---- Program code ------------------------------------------------------------------------------
// Executable segments of loaded modules: appended under a lock, read by the handler without one
// (entries are written before the count that publishes them). Modules stay loaded for the
// process's life, so entries never go. Past kMaxRanges a module's loops are still taken at rtTrace.
struct CodeRange {
  uintptr_t begin, end;
};
constexpr size_t kMaxRanges = 16384;
CodeRange g_ranges[kMaxRanges];
std::atomic<size_t> g_range_count{0};
std::mutex g_ranges_mu;

bool InModuleCode(uintptr_t pc) {
  const size_t n = g_range_count.load(std::memory_order_acquire);
  for (size_t i = 0; i < n; ++i) {
    if (pc >= g_ranges[i].begin && pc < g_ranges[i].end) return true;
  }
  return false;
}

// The Itanium C++ ABI's per-thread exception state (__cxa_eh_globals): the exceptions being
// handled, innermost first, and how many were thrown and not yet caught.
struct EhGlobals {
  void* caught_exceptions;
  unsigned uncaught_exceptions;
};
EhGlobals* ThreadEhGlobals() { return reinterpret_cast<EhGlobals*>(abi::__cxa_get_globals()); }

// ---- Threads running tiles ---------------------------------------------------------------------
// A cache line each: a thread writes its own slot at every tile.
struct alignas(64) Slot {
  pthread_t thread;
  // Read by the handler on the slot's own thread and by the interrupter; written by the slot's
  // thread (and cleared by the handler).
  std::atomic<sigjmp_buf*> jump{nullptr};  // non-null while armed
  std::atomic<const std::atomic<bool>*> cancel{nullptr}, stop{nullptr};
  Clock::time_point ending{};  // the interrupter's: when it first saw this tile's launch end
};

// Never destroyed: the interrupter thread waits on it until the process is gone.
struct Registry {
  std::mutex mu;  // guards slots, and wakes the interrupter
  std::condition_variable armed_cv;
  std::vector<Slot*> slots;
  // Every tile of every device thread arms and disarms, so neither touches shared state but these
  // read-mostly flags: with a lock (and then an armed count) there, 32 threads spent more than
  // half their time in the kernel's futex locks in launches of small tiles.
  // The interrupter found no slot armed and waits: the next tile to arm wakes it. It sets the
  // flag and then looks at the slots again, and Arm stores its jump and then reads the flag
  // (seq_cst both): either the interrupter sees the jump or Arm sees the flag.
  alignas(64) std::atomic<bool> sleeping{false};
  // The interrupter is reading slots (under mu): a tile that disarms meanwhile waits for it to
  // finish (Disarm), since the slot's cancel and stop flags end with the call that owns them.
  std::atomic<bool> scanning{false};
};
Registry& Reg() {
  static Registry* r = new Registry;
  return *r;
}

__thread Slot* t_slot __attribute__((tls_model("initial-exec"))) = nullptr;

#if defined(__SANITIZE_ADDRESS__)
// The thread stack a lane running on this thread came from (EnteredLane), and a switch back to it
// begun by a jump out of the lane and finished where the jump lands (Jumped).
__thread const void* t_lane_thread_bottom = nullptr;
__thread size_t t_lane_thread_size = 0;
__thread void* t_jump_fake_stack = nullptr;
__thread const void* t_jump_landing_bottom = nullptr;  // set while such a jump is under way

inline void BeforeJump() {
  if (t_lane_thread_bottom == nullptr) return;
  __sanitizer_start_switch_fiber(&t_jump_fake_stack, t_lane_thread_bottom, t_lane_thread_size);
  t_jump_landing_bottom = t_lane_thread_bottom;
  t_lane_thread_bottom = nullptr;
}
// Inline into the frame the jump landed in. The frames it skipped on the thread's stack (the
// tile's, below this one, suspended when the lane took over) keep their redzones: AddressSanitizer
// unpoisons what a longjmp skips on the stack it leaves, and this one left the lane's. Cleared
// here before any instrumented call reuses that memory.
__attribute__((always_inline)) inline void AfterJump() {
  if (t_jump_landing_bottom == nullptr) return;
  __sanitizer_finish_switch_fiber(t_jump_fake_stack, nullptr, nullptr);
  const char* bottom = static_cast<const char*>(t_jump_landing_bottom);
  const char* here = static_cast<const char*>(__builtin_frame_address(0));
  if (bottom < here) __asan_unpoison_memory_region(bottom, static_cast<size_t>(here - bottom));
  t_jump_landing_bottom = nullptr;
}
#else
inline void BeforeJump() {}
inline void AfterJump() {}
#endif

// Unregisters the thread's slot when the thread ends, so that no signal goes to a dead thread.
struct SlotOwner {
  ~SlotOwner() {
    if (t_slot == nullptr) return;
    Registry& r = Reg();
    std::lock_guard<std::mutex> lock(r.mu);
    r.slots.erase(std::find(r.slots.begin(), r.slots.end(), t_slot));
    delete t_slot;
    t_slot = nullptr;
  }
};
thread_local SlotOwner t_slot_owner;

// ---- The signal --------------------------------------------------------------------------------
struct sigaction g_previous;

bool Ending(const Slot& s) {
  return s.cancel.load(std::memory_order_relaxed)->load(std::memory_order_relaxed) ||
         s.stop.load(std::memory_order_relaxed)->load(std::memory_order_relaxed);
}

void OnInterrupt(int sig, siginfo_t* info, void* context) {
  Slot* s = t_slot;
  sigjmp_buf* jump = s != nullptr ? s->jump.load(std::memory_order_relaxed) : nullptr;
  if (jump == nullptr) {
    // Not a tile of ours (or one that has just ended): an application's handler may want it.
    if ((g_previous.sa_flags & SA_SIGINFO) != 0 && g_previous.sa_sigaction != nullptr) {
      g_previous.sa_sigaction(sig, info, context);
    } else if (g_previous.sa_handler != SIG_DFL && g_previous.sa_handler != SIG_IGN &&
               g_previous.sa_handler != nullptr) {
      g_previous.sa_handler(sig);
    }
    return;
  }
  if (!Ending(*s)) return;
#if defined(__x86_64__)
  const auto pc =
      static_cast<uintptr_t>(static_cast<ucontext_t*>(context)->uc_mcontext.gregs[REG_RIP]);
  if (InModuleCode(pc)) {
    // Only the program's own frames, and engine frames waiting on calls into it, lie between
    // here and the tile: no lock is held and no engine state is half written.
    s->jump.store(nullptr, std::memory_order_relaxed);
    BeforeJump();
    siglongjmp(*jump, 1);
  }
#endif
  t_interrupt_requested = true;  // the engine, Embree or a library: the next engine call jumps
}

bool HandlerInstalled() {
  struct sigaction current = {};
  sigaction(InterruptSignal(), nullptr, &current);
  return (current.sa_flags & SA_SIGINFO) != 0 && current.sa_sigaction == &OnInterrupt;
}

void InstallHandler() {
  struct sigaction action = {};
  action.sa_sigaction = &OnInterrupt;
  // SA_NODEFER: the handler leaves by siglongjmp to a sigsetjmp that saved no mask; the signal
  // must not stay blocked after it.
  // Not SA_ONSTACK, unlike the crash reporter's handlers (crash_report.cc): this one runs on the
  // thread's own stack, where its siglongjmp lands (the tile's frame), so the jump never leaves
  // an alternate stack behind; in a host process the thread's alternate stack, if any, is the
  // application's (Rust gives every thread a small one), not this handler's to use; and the one
  // thread whose stack has no room for the handler's frame is one whose program is overflowing
  // its stack, where the kernel's SIGSEGV then gets the crash report on the alternate stack.
  action.sa_flags = SA_SIGINFO | SA_RESTART | SA_NODEFER;
  sigemptyset(&action.sa_mask);
  sigaction(InterruptSignal(), &action, &g_previous);
}

// Whether some thread is in a tile (under Registry::mu).
bool AnyArmed(const Registry& r) {
  for (const Slot* s : r.slots) {
    if (s->jump.load() != nullptr) return true;
  }
  return false;
}

// Signals threads whose tile's launch ended kGrace ago and that are still in it. Runs only while
// some thread is armed; sleeps on Registry::armed_cv otherwise.
[[noreturn]] void InterrupterLoop() {
  Registry& r = Reg();
  std::unique_lock<std::mutex> lock(r.mu);
  bool installed = false, replaced = false;
  for (;;) {
    if (!AnyArmed(r)) {
      r.sleeping.store(true);
      if (AnyArmed(r)) {
        r.sleeping.store(false);  // a tile armed before it could see the flag
      } else {
        r.armed_cv.wait(lock, [&] { return !r.sleeping.load(); });
      }
    }
    auto period = kPeriod;
    while (AnyArmed(r)) {
      // Not woken by threads arming meanwhile: a launch of short tiles arms a thread per tile.
      lock.unlock();
      std::this_thread::sleep_for(period);
      lock.lock();
      const Clock::time_point now = Clock::now();
      period = kPeriod;
      r.scanning.store(true);
      struct ScanEnd {
        Registry& r;
        ~ScanEnd() { r.scanning.store(false); }
      } scan_end{r};
      for (Slot* s : r.slots) {
        if (s->jump.load() == nullptr || !Ending(*s)) {
          s->ending = Clock::time_point();
          continue;
        }
        if (s->ending == Clock::time_point()) s->ending = now;
        if (now - s->ending < kGrace) continue;
        if (now - s->ending >= kSlow) period = kFastPeriod;
        if (!installed) {
          InstallHandler();
          installed = true;
        }
        if (!HandlerInstalled()) {
          // An application took the signal over after Tessera installed its handler: the
          // signal would now reach the application's handler instead.
          if (!replaced) {
            log::Warn(log::Component::kWorker,
                      "signal %d (TESSERA_INTERRUPT_SIGNAL) now has another handler: programs that "
                      "never return can no longer be stopped; set TESSERA_INTERRUPT_SIGNAL to a "
                      "real-time signal the application does not use",
                      InterruptSignal());
            replaced = true;
          }
          continue;
        }
        pthread_kill(s->thread, InterruptSignal());
      }
    }
  }
}

void StartInterrupter() {
  static std::once_flag once;
  std::call_once(once, [] { std::thread(&InterrupterLoop).detach(); });
}

}  // namespace

// TESSERA_INTERRUPT_SIGNAL picks another real-time signal for an application that uses this one;
// 0 turns interrupts off (programs that never return then keep their thread, as before).
int InterruptSignal() {
  static const int sig = [] {
    const int fallback = SIGRTMIN + 6;
    const char* env = std::getenv("TESSERA_INTERRUPT_SIGNAL");
    if (env == nullptr || *env == '\0') return fallback;
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (*end == '\0' && (n == 0 || (n >= SIGRTMIN && n <= SIGRTMAX))) return static_cast<int>(n);
    log::Warn(log::Component::kWorker,
              "TESSERA_INTERRUPT_SIGNAL='%s' is not 0 or a real-time signal (%d to %d); using %d",
              env, SIGRTMIN, SIGRTMAX, fallback);
    return fallback;
  }();
  return sig;
}

void RegisterModuleCode(void* handle) {
  link_map* map = nullptr;
  if (dlinfo(handle, RTLD_DI_LINKMAP, &map) != 0 || map == nullptr) return;
  struct Found {
    ElfW(Addr) base;
    std::vector<CodeRange> ranges;
  } found{map->l_addr, {}};
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        auto* f = static_cast<Found*>(data);
        if (info->dlpi_addr != f->base) return 0;
        for (ElfW(Half) i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          if (ph.p_type != PT_LOAD || (ph.p_flags & PF_X) == 0) continue;
          const uintptr_t begin = info->dlpi_addr + ph.p_vaddr;
          f->ranges.push_back({begin, begin + ph.p_memsz});
        }
        return 1;
      },
      &found);
  std::lock_guard<std::mutex> lock(g_ranges_mu);
  size_t n = g_range_count.load(std::memory_order_relaxed);
  for (const CodeRange& r : found.ranges) {
    if (n == kMaxRanges) break;
    g_ranges[n++] = r;
  }
  g_range_count.store(n, std::memory_order_release);
}

InterruptibleTile::InterruptibleTile(const std::atomic<bool>& cancel,
                                     const std::atomic<bool>& stop) {
  if (InterruptSignal() <= 0) return;
  StartInterrupter();
  if (t_slot == nullptr) {
    (void)&t_slot_owner;  // constructs the owner, which unregisters the slot at thread exit
    auto* s = new Slot;
    s->thread = pthread_self();
    // A thread that blocks signals (say, one an application made before starting TBB's) would
    // otherwise never take the interrupt.
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, InterruptSignal());
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    Registry& r = Reg();
    std::lock_guard<std::mutex> lock(r.mu);
    r.slots.push_back(s);
    t_slot = s;
  }
  t_slot->cancel.store(&cancel, std::memory_order_relaxed);
  t_slot->stop.store(&stop, std::memory_order_relaxed);
}

InterruptibleTile::~InterruptibleTile() { Disarm(); }

void InterruptibleTile::Arm(sigjmp_buf* jump) {
  if (t_slot == nullptr) return;
  t_interrupt_requested = false;
  const EhGlobals* globals = ThreadEhGlobals();
  caught_exceptions_ = globals->caught_exceptions;
  uncaught_exceptions_ = globals->uncaught_exceptions;
  Registry& r = Reg();
  t_slot->jump.store(jump);  // after the tile's cancel and stop flags
  armed_ = true;
  if (r.sleeping.load()) {
    std::lock_guard<std::mutex> lock(r.mu);
    r.sleeping.store(false);
    r.armed_cv.notify_one();
  }
}

void InterruptibleTile::Jumped() {
  AfterJump();
  Disarm();
  // A catch block the jump left never ended its exception (which stays allocated).
  EhGlobals* globals = ThreadEhGlobals();
  globals->caught_exceptions = caught_exceptions_;
  globals->uncaught_exceptions = uncaught_exceptions_;
}

void InterruptibleTile::Disarm() {
  if (!armed_) return;
  Registry& r = Reg();
  t_slot->jump.store(nullptr);  // the handler may have cleared it
  armed_ = false;
  // A scan that began before the store above may still read this tile's flags: wait for it to end.
  // One that begins after it sees no jump and leaves the flags alone (both orders are seq_cst).
  if (r.scanning.load()) std::lock_guard<std::mutex> wait_for_scan(r.mu);
}

void TakeInterruptRequest() {
  t_interrupt_requested = false;
  Slot* s = t_slot;
  sigjmp_buf* jump = s != nullptr ? s->jump.load(std::memory_order_relaxed) : nullptr;
  if (jump == nullptr || !Ending(*s)) return;
  s->jump.store(nullptr, std::memory_order_relaxed);
  BeforeJump();
  siglongjmp(*jump, 1);
}

#if defined(__SANITIZE_ADDRESS__)
void EnteredLane(const void* thread_stack_bottom, size_t thread_stack_size) {
  t_lane_thread_bottom = thread_stack_bottom;
  t_lane_thread_size = thread_stack_size;
}
void LeftLane() { t_lane_thread_bottom = nullptr; }
#endif

}  // namespace tessera::worker

namespace tessera {
void CheckInterruptSignal() { (void)worker::InterruptSignal(); }
}  // namespace tessera
