#include "tools/tessera/render/stop_signals.h"

#include <signal.h>

#include <atomic>

namespace tessera::render {
namespace {

std::atomic<int> g_first_signal{0};
std::atomic<int> g_count{0};

void OnStopSignal(int sig) {
  int expected = 0;
  g_first_signal.compare_exchange_strong(expected, sig);
  if (g_count.fetch_add(1) + 1 >= 3) {
    // Enough asking: die of the signal, as without a handler.
    signal(sig, SIG_DFL);
    raise(sig);
  }
}

}  // namespace

void InstallStopSignalHandlers() {
  static bool installed = false;
  if (installed) return;
  installed = true;
  struct sigaction action {};
  action.sa_handler = &OnStopSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int StopSignal() { return g_first_signal.load(); }

bool AbandonPass() { return g_count.load() >= 2; }

int ExitStatusForSignal(int signal) { return 128 + signal; }

}  // namespace tessera::render
