// Launch results' messages kept for reuse. A launch's results are megabytes of region data in
// messages that live until the host applied them; allocated afresh for every launch, that memory
// comes back from the kernel a page at a time (glibc returns large freed blocks to it), and the
// page faults cost about a fifth of a gathering launch. A message that held results before keeps
// its buffers when cleared, and parsing or packing into it reuses them.
#ifndef TESSERA_SCHEDULER_RESULT_POOL_H_
#define TESSERA_SCHEDULER_RESULT_POOL_H_

#include <cstddef>

#include "tessera/v1/launch.pb.h"

namespace tessera::scheduler {

// At most this many bytes of messages wait for reuse, process-wide.
inline constexpr size_t kMaxPooledResultBytes = size_t{128} << 20;

// An empty message, one that held results before when there is one.
v1::TileResult TakeTileResult();

// Keeps `result`'s memory for a later TakeTileResult, unless it is small or the pool is full.
void RecycleTileResult(v1::TileResult&& result);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_RESULT_POOL_H_
