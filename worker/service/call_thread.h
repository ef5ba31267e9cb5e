// One long-lived thread that runs a session's launch calls one after the other. A thread per call
// set up its thread-local state afresh at every call (TBB's per-thread data, every program
// module's thread_local variables): one-thread workers take dozens of calls per launch.
#ifndef TESSERA_WORKER_SERVICE_CALL_THREAD_H_
#define TESSERA_WORKER_SERVICE_CALL_THREAD_H_

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <utility>

namespace tessera::worker {

class CallThread {
 public:
  CallThread() = default;
  CallThread(const CallThread&) = delete;
  CallThread& operator=(const CallThread&) = delete;
  // Runs what was posted, then ends the thread.
  ~CallThread() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stopping_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  // Runs `call` on the thread (started on first use) after the calls posted before it; the future
  // is ready once `call` returned. Throws std::system_error when the thread cannot start.
  std::future<void> Post(std::function<void()> call) {
    std::packaged_task<void()> task(std::move(call));
    std::future<void> ran = task.get_future();
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (!thread_.joinable()) thread_ = std::thread([this] { Loop(); });
      queue_.push_back(std::move(task));
    }
    cv_.notify_one();
    return ran;
  }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      cv_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping, nothing left
      std::packaged_task<void()> task = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      task();
      lock.lock();
    }
  }

  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::packaged_task<void()>> queue_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_CALL_THREAD_H_
