// Cancels running Launch calls from one thread of the host process: a call whose launch was
// cancelled, or whose worker has sent nothing (not even a heartbeat) past its silence deadline.
// Blocking reads on a stream cannot watch either themselves. One thread for every call of every
// worker, instead of a thread per call: a launch over 16 workers makes hundreds of calls, and
// each thread started and joined is host time on the launch's critical path.
#ifndef TESSERA_SCHEDULER_TRANSPORT_CALL_WATCHDOG_H_
#define TESSERA_SCHEDULER_TRANSPORT_CALL_WATCHDOG_H_

#include <grpcpp/client_context.h>

#include <atomic>
#include <chrono>

#include "absl/time/time.h"

namespace tessera::transport {

// One watched call, for as long as it lives (declare it after the ClientContext it watches).
class WatchedCall {
 public:
  WatchedCall(grpc::ClientContext* context, const std::atomic<bool>& cancel,
              absl::Duration silence);
  ~WatchedCall();  // once it returns, the watchdog no longer touches the context
  WatchedCall(const WatchedCall&) = delete;
  WatchedCall& operator=(const WatchedCall&) = delete;

  // The worker sent something: the silence deadline starts again.
  void Heard() { last_heard_.store(Now(), std::memory_order_relaxed); }
  // The worker is about to work for up to `extra` without sending anything (applying a large
  // state update): the silence deadline starts again, `extra` later.
  void Expect(absl::Duration extra) {
    last_heard_.store(Now() + absl::ToInt64Nanoseconds(extra), std::memory_order_relaxed);
  }
  // Whether the call was cancelled because the worker stayed silent.
  bool silent() const { return silent_.load(); }

 private:
  friend class CallWatchdog;
  static int64_t Now() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  grpc::ClientContext* const context_;
  const std::atomic<bool>& cancel_;
  const int64_t silence_ns_;
  std::atomic<int64_t> last_heard_;
  std::atomic<bool> silent_{false};
  bool fired_ = false;  // cancelled already; guarded by the watchdog's lock
};

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_CALL_WATCHDOG_H_
