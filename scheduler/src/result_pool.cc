#include "tessera/scheduler/result_pool.h"

#include <mutex>
#include <utility>
#include <vector>

namespace tessera::scheduler {
namespace {

// Smaller messages cost little to allocate: not worth a place in the pool.
constexpr size_t kMinPooledBytes = size_t{64} << 10;

struct Pool {
  std::mutex mu;
  std::vector<std::pair<v1::TileResult, size_t>> messages;  // with their bytes
  size_t bytes = 0;
};

Pool& ThePool() {
  static auto* pool = new Pool;  // never destroyed: results may be recycled during exit
  return *pool;
}

}  // namespace

v1::TileResult TakeTileResult() {
  Pool& pool = ThePool();
  v1::TileResult result;
  {
    std::lock_guard<std::mutex> lock(pool.mu);
    if (pool.messages.empty()) return result;
    result = std::move(pool.messages.back().first);
    pool.bytes -= pool.messages.back().second;
    pool.messages.pop_back();
  }
  result.Clear();  // keeps the regions and their buffers for reuse
  return result;
}

void RecycleTileResult(v1::TileResult&& result) {
  const size_t bytes = result.SpaceUsedLong();
  if (bytes < kMinPooledBytes) return;
  Pool& pool = ThePool();
  std::lock_guard<std::mutex> lock(pool.mu);
  if (pool.bytes + bytes > kMaxPooledResultBytes) return;
  pool.bytes += bytes;
  pool.messages.emplace_back(std::move(result), bytes);
}

}  // namespace tessera::scheduler
