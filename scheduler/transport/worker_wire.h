// How Device calls travel over the Worker service (proto/tessera/v1/worker.proto): deltas as
// streams of bounded ApplyChunks, tile results cut into bounded messages, and status conversion.
// Shared by the client (GrpcDevice) and the server (worker/service) so both ends agree.
#ifndef TESSERA_SCHEDULER_TRANSPORT_WORKER_WIRE_H_
#define TESSERA_SCHEDULER_TRANSPORT_WORKER_WIRE_H_

#include <grpcpp/support/status.h>

#include <cstddef>
#include <vector>

#include "absl/functional/function_ref.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "tessera/v1/worker.pb.h"

namespace tessera::transport {

// Buffer bytes per streamed message; the host's chunks are at most this large too. Object
// batches hold at most this many bytes of objects, unless one object alone is larger.
inline constexpr size_t kMaxRegionBytes = size_t{4} << 20;
// gRPC's default receive limit (4 MiB) is below one full chunk plus framing, so both ends raise
// it. Messages stay near kMaxRegionBytes in practice; only the context state or a single object
// with large variable values comes near this limit.
inline constexpr int kMaxMessageBytes = 64 << 20;

// The first message of an Apply stream: `delta` without its objects, buffer chunks and module
// slices, announcing the messages that carry them (objects in batches of kMaxRegionBytes).
v1::ApplyChunk DeltaHeader(const v1::StateDelta& delta);

// RESOURCE_EXHAUSTED, naming the largest variable, when a message of the Apply stream of `delta`
// would exceed kMaxMessageBytes: its header (the context state) or one object, whose variables
// travel whole. gRPC would refuse it with only "Sent message larger than max".
absl::Status CheckDeltaMessageSizes(const v1::StateDelta& delta);

// Sends `delta` as an Apply stream through `write`: the header, then the objects in batches of at
// most `object_batch_bytes` (an object larger than that alone), then each module slice, then each
// buffer chunk, one per message. Stops at the first write that fails (the call is over) and
// returns false then.
bool WriteApplyStream(const v1::StateDelta& delta,
                      absl::FunctionRef<bool(const v1::ApplyChunk&)> write,
                      size_t object_batch_bytes = kMaxRegionBytes);

// Rebuilds a StateDelta from an Apply stream on the worker.
class DeltaAssembler {
 public:
  // INVALID_ARGUMENT if the stream does not start with the delta, carries it twice, or carries
  // more messages than it announced. Object batches are appended to the delta's objects in the
  // order they came. Module slices are only collected: the device checks them against their
  // hashes.
  // RESOURCE_EXHAUSTED once the objects, chunks and slices received hold more than `max_bytes`: a
  // delta larger than the device's memory cannot be applied, and collecting it first would end the
  // process (every session with it) before the delta is even checked.
  explicit DeltaAssembler(uint64_t max_bytes = ~uint64_t{0}) : max_bytes_(max_bytes) {}
  absl::Status Add(v1::ApplyChunk&& part);
  // INVALID_ARGUMENT if no delta arrived, or fewer or more messages than its header announced
  // (a stream cut short by a malformed or oversized message reads as ended).
  absl::StatusOr<v1::StateDelta> Finish() &&;

 private:
  // INVALID_ARGUMENT for `what` ("a buffer chunk") before the delta or beyond the announced count.
  absl::Status Follow(absl::string_view what);

  bool has_delta_ = false;
  uint64_t following_ = 0;  // announced by the header
  uint64_t received_ = 0;   // messages after it
  uint64_t max_bytes_;
  uint64_t bytes_ = 0;  // bytes of the object batches and data bytes of the chunks and slices
  v1::StateDelta delta_;
};

// Cuts `result` into messages that each carry at most `max_bytes` of region data (a larger region
// becomes several regions by offset) and about as much of prints and exception reports. Every
// piece keeps launch_id and tile_index; the error fields go with the first.
std::vector<v1::TileResult> SplitTileResult(v1::TileResult&& result,
                                            size_t max_bytes = kMaxRegionBytes);

// Status codes are the same numbers in Abseil and gRPC.
grpc::Status ToGrpcStatus(const absl::Status& status);
// The message names the worker: "worker unix:/tmp/w0.sock: <message>".
absl::Status FromGrpcStatus(const grpc::Status& status, absl::string_view address);

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_WORKER_WIRE_H_
