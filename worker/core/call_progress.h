// What a device call keeps of its tiles while their pieces run, and the heartbeats that show a
// long call's progress: shared by OptiX 3 calls (inproc_device.cc) and OptiX 7 calls
// (optix7_device_call.cc).
//
// Every piece ends here, on every thread of the device, and pieces of a small launch take
// microseconds: one lock taken at each piece's end kept 32 threads in the kernel's futex locks
// for more than half their time. A piece with nothing to say (no prints, exception reports or
// error: nearly all) only counts itself down; the lock is for tiles with something to send.
#ifndef TESSERA_WORKER_CORE_CALL_PROGRESS_H_
#define TESSERA_WORKER_CORE_CALL_PROGRESS_H_

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "tessera/scheduler/device.h"
#include "tessera/v1/launch.pb.h"
#include "tile_pieces.h"

namespace tessera::worker {

class CallTiles {
 public:
  // The tiles of `request`, cut into `pieces`; results go to `on_result`, one call at a time.
  CallTiles(const v1::LaunchRequest& request, const std::vector<TilePiece>& pieces,
            std::chrono::steady_clock::time_point started,
            const std::function<void(v1::TileResult&&)>& on_result)
      : request_(request),
        on_result_(on_result),
        tiles_(static_cast<size_t>(request.tiles_size())),
        next_heartbeat_(started + kInterval) {
    for (const TilePiece& p : pieces) tiles_[p.tile].pieces_left.fetch_add(1);
  }

  // A piece of tile `tile` ended: `done` unless a cancel stopped it; `part` holds its prints,
  // exception reports and error. The tile's last piece sends what its pieces had to say, and
  // counts the tile as finished (a heartbeat now and then) unless one was stopped.
  void PieceEnded(int tile, bool done, v1::TileResult& part) {
    Tile& t = tiles_[tile];
    if (!done) t.abandoned.store(true);
    if (Says(part)) {
      std::lock_guard<std::mutex> lock(mu_);
      t.result.MergeFrom(part);  // prints and reports carry their launch index
      t.says.store(true);
    }
    if (t.pieces_left.fetch_sub(1) > 1) return;
    const bool abandoned = t.abandoned.load();
    if (!abandoned) TileFinished();
    if (!t.says.load()) return;
    std::lock_guard<std::mutex> lock(mu_);
    // A stopped tile's prints and reports are dropped (its launch index ran again elsewhere, or
    // the launch ended); its error is not.
    if (abandoned && t.result.error().empty()) return;
    t.result.set_launch_id(request_.launch_id());
    t.result.set_tile_index(request_.tiles(tile).index());
    on_result_(std::move(t.result));
  }

 private:
  struct Tile {
    std::atomic<int> pieces_left{0};
    std::atomic<bool> abandoned{false};  // a piece stopped at a cancel
    std::atomic<bool> says{false};       // `result` holds something to send
    v1::TileResult result;               // under mu_
  };

  // A tile with nothing to say costs no message: over a worker's wire each is a message to
  // write, send and parse, and the host counts finished tiles by call, not by tile.
  static bool Says(const v1::TileResult& r) {
    return r.prints_size() > 0 || r.exceptions_size() > 0 || !r.error().empty();
  }

  // Counts a finished tile and says how many now and then (a heartbeat with tiles_done), so that
  // a long call shows progress before its results come back. Calls shorter than the interval say
  // nothing.
  void TileFinished() {
    done_.fetch_add(1);
    const auto now = std::chrono::steady_clock::now();
    if (now < next_heartbeat_.load()) return;
    std::lock_guard<std::mutex> lock(mu_);
    if (now < next_heartbeat_.load()) return;
    next_heartbeat_.store(now + kInterval);
    v1::TileResult r;
    r.set_launch_id(request_.launch_id());
    r.set_tile_index(kHeartbeatTileIndex);
    r.set_tiles_done(done_.load());
    on_result_(std::move(r));
  }

  static constexpr std::chrono::milliseconds kInterval{100};
  const v1::LaunchRequest& request_;
  const std::function<void(v1::TileResult&&)>& on_result_;
  std::vector<Tile> tiles_;
  std::mutex mu_;  // tiles' results and calls of on_result_
  std::atomic<uint32_t> done_{0};
  std::atomic<std::chrono::steady_clock::time_point> next_heartbeat_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_CALL_PROGRESS_H_
