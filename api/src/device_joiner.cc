#include "device_joiner.h"

#include <algorithm>
#include <exception>
#include <new>
#include <system_error>
#include <thread>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "tessera/scheduler/log.h"

namespace tessera::api {

struct DeviceJoiner::State {
  std::string address;
  Create create;
  Backoff backoff;
  bool lost_before = false;  // it worked before: its return is news even at the first try

  mutable absl::Mutex mu;
  bool stop ABSL_GUARDED_BY(mu) = false;
  bool kicked ABSL_GUARDED_BY(mu) = false;
  bool trying ABSL_GUARDED_BY(mu) = false;
  uint64_t started ABSL_GUARDED_BY(mu) = 0;
  uint64_t finished ABSL_GUARDED_BY(mu) = 0;
  absl::Status last_error ABSL_GUARDED_BY(mu);
  std::unique_ptr<Device> device ABSL_GUARDED_BY(mu);
  bool ready ABSL_GUARDED_BY(mu) = false;  // a try made the device (taken or not)

  // One try, with every exception a status (as CreateDevices makes of them at a launch).
  absl::StatusOr<std::unique_ptr<Device>> Try() {
    try {
      return create();
    } catch (const std::bad_alloc&) {
      return absl::ResourceExhaustedError("out of memory");
    } catch (const std::system_error& e) {
      return absl::ResourceExhaustedError(absl::StrCat("could not start a thread: ", e.what()));
    } catch (const std::exception& e) {
      return absl::InternalError(absl::StrCat("threw: ", e.what()));
    }
  }

  void Run(bool try_at_once) {
    absl::Duration delay = backoff.first;
    bool say = false;
    if (!try_at_once) {
      absl::MutexLock lock(&mu);
      auto woken = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu) { return stop || kicked; };
      mu.AwaitWithDeadline(absl::Condition(&woken), absl::Now() + backoff.first);
    }
    while (true) {
      {
        absl::MutexLock lock(&mu);
        if (stop) return;
        kicked = false;
        trying = true;
        ++started;
      }
      absl::StatusOr<std::unique_ptr<Device>> created = Try();
      std::unique_ptr<Device> unwanted;  // made after the context let go: destroyed unlocked
      {
        absl::MutexLock lock(&mu);
        trying = false;
        ++finished;
        if (stop) {
          if (created.ok()) unwanted = *std::move(created);
          return;
        }
        if (created.ok()) {
          device = *std::move(created);
          ready = true;
          // A worker that answers its first try at a context's first launch is just starting.
          say = lost_before || !last_error.ok();
          break;
        }
        last_error = created.status();
        // Until the delay passes, a kick or a stop.
        const absl::Time until = absl::Now() + delay;
        auto woken = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu) { return stop || kicked; };
        mu.AwaitWithDeadline(absl::Condition(&woken), until);
        if (stop) return;
        delay = kicked ? backoff.first : std::min(delay * 2, backoff.most);
      }
    }
    // Said here, when it answered, not at the launch that takes it: that may come much later.
    if (say) log::Info(log::Component::kApi, "device %s is up; joining", address);
  }
};

DeviceJoiner::DeviceJoiner(std::string address, Create create, bool try_at_once, bool lost,
                           Backoff backoff)
    : state_(std::make_shared<State>()) {
  state_->address = std::move(address);
  state_->lost_before = lost;
  state_->create = std::move(create);
  state_->backoff = backoff;
  try {
    std::thread([state = state_, try_at_once] { state->Run(try_at_once); }).detach();
  } catch (const std::system_error& e) {
    // No thread to be had (a process limit): no try will come; a launch waiting for one does not
    // wait, and the device stays out until the context tries afresh (rtContextSetDevices).
    absl::MutexLock lock(&state_->mu);
    state_->finished = ~uint64_t{0};
    state_->last_error =
        absl::ResourceExhaustedError(absl::StrCat("could not start a thread: ", e.what()));
  }
}

DeviceJoiner::~DeviceJoiner() {
  std::unique_ptr<Device> device;
  {
    absl::MutexLock lock(&state_->mu);
    state_->stop = true;
    device = std::move(state_->device);
  }
}

std::unique_ptr<Device> DeviceJoiner::Take() {
  absl::MutexLock lock(&state_->mu);
  return std::move(state_->device);
}

uint64_t DeviceJoiner::Kick() {
  absl::MutexLock lock(&state_->mu);
  state_->kicked = true;
  // The try under way counts: it began before, but it is as fresh as a launch can wait for.
  return state_->trying ? state_->started : state_->started + 1;
}

bool DeviceJoiner::Wait(uint64_t tries, absl::Time deadline) {
  absl::MutexLock lock(&state_->mu);
  State* s = state_.get();
  auto done = [s, tries]()
                  ABSL_EXCLUSIVE_LOCKS_REQUIRED(s->mu) { return s->ready || s->finished >= tries; };
  state_->mu.AwaitWithDeadline(absl::Condition(&done), deadline);
  return state_->device != nullptr;
}

absl::Status DeviceJoiner::last_error() const {
  absl::MutexLock lock(&state_->mu);
  return state_->last_error;
}

uint64_t DeviceJoiner::tries() const {
  absl::MutexLock lock(&state_->mu);
  return state_->finished;
}

}  // namespace tessera::api
