// One Apply stream (a state update, worker.proto) over gRPC's callback API. The host's thread
// hands each message over and waits on its own condition variable against its own deadline, so
// a worker that stops reading (SIGSTOP, a full socket, a machine gone) holds it no longer than
// the silence deadline: with the sync API a ClientWriter::Write blocked on flow control did not
// return after TryCancel, and the host waited for ever (issue 23).
#ifndef TESSERA_SCHEDULER_TRANSPORT_APPLY_CALL_H_
#define TESSERA_SCHEDULER_TRANSPORT_APPLY_CALL_H_

#include <grpcpp/grpcpp.h>

#include <memory>

#include "absl/time/time.h"
#include "tessera/v1/worker.grpc.pb.h"

namespace tessera::transport {

class ApplyCall {
 public:
  // Starts the call on `stub`.
  explicit ApplyCall(v1::Worker::StubInterface* stub);
  // Ends the stream if the caller did not (cancelling it); never waits. The call's state lives
  // on until gRPC is done with it.
  ~ApplyCall();
  ApplyCall(const ApplyCall&) = delete;
  ApplyCall& operator=(const ApplyCall&) = delete;

  // Sends a copy of `message` once the previous one is written. False once the call is over (the
  // worker refused the update, the connection dropped: Finish says why) or when the previous
  // message was not taken within `silence` (the call is then cancelled and silent() is true).
  bool Write(const v1::ApplyChunk& message, absl::Duration silence);
  // After the last Write: says no more messages come, then waits up to `wait` for the worker's
  // answer (it builds its copy of the update meanwhile). DEADLINE_EXCEEDED, with silent() true,
  // when none came: the call is cancelled.
  grpc::Status Finish(absl::Duration wait);
  // Whether the worker stayed silent past a deadline.
  bool silent() const;

 private:
  class Reactor;
  class Graveyard;
  void EndWrites();  // releases the stream for its end (once)

  std::shared_ptr<Reactor> reactor_;
  bool writes_ended_ = false;
};

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_APPLY_CALL_H_
