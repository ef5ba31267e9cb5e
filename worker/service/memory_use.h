// What a worker can say cheaply about its memory, for its Health answer: the bytes each session's
// buffers hold (from the deltas its device accepted, so nothing in worker/core is walked) and the
// process's resident memory.
#ifndef TESSERA_WORKER_SERVICE_MEMORY_USE_H_
#define TESSERA_WORKER_SERVICE_MEMORY_USE_H_

#include <cstdint>

#include "absl/container/flat_hash_map.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

// The bytes of a session's buffers as its replica holds them: each buffer's elements times their
// size, by buffer id. Scenes, plans and results come on top; modules are shared by all sessions.
class BufferBytes {
 public:
  // After the session's device accepted `delta`: sequence 1 starts afresh (the device was
  // replaced), changed buffers take their new size, removed objects go.
  void Apply(const v1::StateDelta& delta);
  uint64_t total() const { return total_; }

 private:
  absl::flat_hash_map<uint64_t, uint64_t> bytes_;  // buffer id → bytes
  uint64_t total_ = 0;
};

// The calling process's resident memory in bytes (/proc/self/statm); 0 when unknown.
uint64_t ResidentBytes();

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_MEMORY_USE_H_
