#include "transport/apply_call.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <vector>

namespace tessera::transport {
namespace {

// How long a cancelled call gets to report its end, so that the caller can say why it ended; past
// it the caller returns anyway and the call's state waits for gRPC on its own.
constexpr std::chrono::seconds kCancelGrace{1};

std::chrono::steady_clock::time_point Within(absl::Duration d) {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(absl::ToChronoSeconds(d));
}

}  // namespace

// Reactors whose call ended (OnDone ran), waiting to be destroyed on a thread of the host's. A
// reactor owns its ClientContext, which holds a reference to the channel; when the device that
// made the call is already gone, that is the channel's last reference, and a channel dropped on
// one of gRPC 1.51's callback threads shuts down the callback completion queue from that very
// thread: it cannot join itself, frees the queue anyway, and the thread then aborts in
// grpc_cq_internal_unref (grpc/grpc#32584). So OnDone never destroys its reactor; it leaves it
// here, and the next call made or ended on a host thread destroys it.
class ApplyCall::Graveyard {
 public:
  static void Keep(std::shared_ptr<Reactor> reactor) {
    Graveyard& g = Get();
    std::lock_guard<std::mutex> lock(g.mu_);
    g.ended_.push_back(std::move(reactor));
  }
  // Drops the kept reactors (outside the lock: a channel's end joins gRPC's callback threads,
  // which may be about to Keep).
  static void Reap() {
    std::vector<std::shared_ptr<Reactor>> ended;
    Graveyard& g = Get();
    {
      std::lock_guard<std::mutex> lock(g.mu_);
      ended.swap(g.ended_);
    }
  }

 private:
  // Never destroyed: reactors still kept at exit are left to the process's end, not to static
  // destructors that may run after gRPC's own.
  static Graveyard& Get() {
    static Graveyard* const g = new Graveyard;
    return *g;
  }
  std::mutex mu_;
  std::vector<std::shared_ptr<Reactor>> ended_;
};

// gRPC's side of the call. It owns everything gRPC may still touch (context, reply, the message
// being written) and keeps itself alive until OnDone, so that a caller who gave up on a silent
// worker can return while gRPC finishes the call on its own (and then waits in the Graveyard).
class ApplyCall::Reactor : public grpc::ClientWriteReactor<v1::ApplyChunk> {
 public:
  void OnWriteDone(bool ok) override {
    std::lock_guard<std::mutex> lock(mu);
    writing = false;
    if (!ok) over = true;  // the call ended (refused, or the connection dropped)
    cv.notify_all();
  }
  void OnDone(const grpc::Status& s) override {
    std::shared_ptr<Reactor> ended;
    {
      std::lock_guard<std::mutex> lock(mu);
      status = s;
      done = true;
      over = true;
      ended = std::move(self);
      cv.notify_all();
    }
    Graveyard::Keep(std::move(ended));  // not destroyed on this gRPC thread (Graveyard)
  }

  grpc::ClientContext context;
  v1::ApplyReply reply;
  v1::ApplyChunk outgoing;  // read by gRPC until OnWriteDone

  std::mutex mu;
  std::condition_variable cv;
  bool writing = false;  // guarded by mu
  bool over = false;     // no more writes can succeed
  bool done = false;     // OnDone ran; `status` is final
  bool silent = false;
  grpc::Status status;
  std::shared_ptr<Reactor> self;  // released in OnDone
};

ApplyCall::ApplyCall(v1::Worker::StubInterface* stub) : reactor_(std::make_shared<Reactor>()) {
  Graveyard::Reap();
  reactor_->self = reactor_;
  stub->async()->Apply(&reactor_->context, &reactor_->reply, reactor_.get());
  // Writes start from this thread, outside gRPC's reactions: the hold keeps the call (and OnDone)
  // from ending before this side stopped writing (EndWrites).
  reactor_->AddHold();
  reactor_->StartCall();
}

ApplyCall::~ApplyCall() {
  if (!writes_ended_) {
    reactor_->context.TryCancel();
    EndWrites();
  }
  reactor_.reset();
  Graveyard::Reap();
}

bool ApplyCall::Write(const v1::ApplyChunk& message, absl::Duration silence) {
  Reactor& r = *reactor_;
  std::unique_lock<std::mutex> lock(r.mu);
  if (!r.cv.wait_until(lock, Within(silence), [&] { return !r.writing || r.over; })) {
    r.silent = true;
    lock.unlock();
    r.context.TryCancel();
    return false;
  }
  if (r.over || r.silent) return false;
  // A copy: the caller's message is gone when this returns, and gRPC reads it until the write is
  // done (a 4 MiB copy is small next to sending it).
  r.outgoing = message;
  r.writing = true;
  lock.unlock();
  r.StartWrite(&r.outgoing);
  return true;
}

void ApplyCall::EndWrites() {
  if (writes_ended_) return;
  writes_ended_ = true;
  reactor_->RemoveHold();
}

grpc::Status ApplyCall::Finish(absl::Duration wait) {
  Reactor& r = *reactor_;
  const auto deadline = Within(wait);
  std::unique_lock<std::mutex> lock(r.mu);
  // The last message must be out before the end of the stream is said.
  bool in_time = !r.silent && r.cv.wait_until(lock, deadline, [&] { return !r.writing || r.over; });
  const bool say_done = in_time && !r.over && !writes_ended_;
  lock.unlock();
  if (say_done) r.StartWritesDone();
  EndWrites();  // also after a failed write: the call can end only once the hold is gone
  lock.lock();
  if (in_time) in_time = r.cv.wait_until(lock, deadline, [&] { return r.done; });
  if (in_time) return r.status;
  r.silent = true;
  lock.unlock();
  r.context.TryCancel();
  lock.lock();
  r.cv.wait_for(lock, kCancelGrace, [&] { return r.done; });
  return grpc::Status(grpc::StatusCode::DEADLINE_EXCEEDED, "the worker stayed silent");
}

bool ApplyCall::silent() const {
  std::lock_guard<std::mutex> lock(reactor_->mu);
  return reactor_->silent;
}

}  // namespace tessera::transport
