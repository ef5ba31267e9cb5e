#include "transport/call_watchdog.h"

#include <condition_variable>
#include <mutex>
#include <thread>
#include <unordered_set>

namespace tessera::transport {

// How often running calls are looked at: a cancel reaches the workers within this, and an idle
// host does not wake at all (the thread sleeps while no call runs).
constexpr std::chrono::milliseconds kCancelPoll{20};

class CallWatchdog {
 public:
  // Never destroyed: calls may still run while the process exits.
  static CallWatchdog& Get() {
    static CallWatchdog* const watchdog = new CallWatchdog;
    return *watchdog;
  }

  void Add(WatchedCall* call) {
    std::lock_guard<std::mutex> lock(mu_);
    calls_.insert(call);
    if (calls_.size() == 1) cv_.notify_one();
  }
  void Remove(WatchedCall* call) {
    std::lock_guard<std::mutex> lock(mu_);
    calls_.erase(call);
  }

 private:
  CallWatchdog() {
    std::thread([this] { Run(); }).detach();
  }

  void Run() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      if (calls_.empty()) {
        cv_.wait(lock, [&] { return !calls_.empty(); });
      } else {
        cv_.wait_for(lock, kCancelPoll);
      }
      const int64_t now = WatchedCall::Now();
      for (WatchedCall* call : calls_) {
        if (call->fired_) continue;
        if (call->cancel_.load()) {
          call->fired_ = true;
          call->context_->TryCancel();
        } else if (now - call->last_heard_.load(std::memory_order_relaxed) > call->silence_ns_) {
          call->fired_ = true;
          call->silent_ = true;
          call->context_->TryCancel();
        }
      }
    }
  }

  std::mutex mu_;
  std::condition_variable cv_;
  std::unordered_set<WatchedCall*> calls_;  // guarded by mu_
};

WatchedCall::WatchedCall(grpc::ClientContext* context, const std::atomic<bool>& cancel,
                         absl::Duration silence)
    : context_(context),
      cancel_(cancel),
      silence_ns_(absl::ToInt64Nanoseconds(silence)),
      last_heard_(Now()) {
  CallWatchdog::Get().Add(this);
}

WatchedCall::~WatchedCall() { CallWatchdog::Get().Remove(this); }

}  // namespace tessera::transport
