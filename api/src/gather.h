// Collects what devices send back during a launch: written buffer regions (applied to the host
// copies), prints and exception reports; afterwards updates what each device is known to hold
// and writes prints in launch-index order.
#ifndef TESSERA_API_SRC_GATHER_H_
#define TESSERA_API_SRC_GATHER_H_

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/status.h"
#include "device_sync.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::api {

class Context;

class LaunchGather {
 public:
  // `slots` are the devices of the launch, in the order `device` indexes them below.
  LaunchGather(Context& context, std::vector<DeviceSlot>& slots);

  // Device threads: queue a result / report that a device's Launch returned. Results are applied
  // on the launching thread only (ProcessUntil), so device threads never touch host objects and
  // the timeout callback, which runs on that thread too, cannot race with them.
  void OnResult(size_t device, v1::TileResult&& result);
  void DeviceDone(size_t device, absl::Status status);

  // Launching thread: applies queued results until every device is done (true) or `deadline`
  // passes (false).
  bool ProcessUntil(std::chrono::steady_clock::time_point deadline);

  // After every device returned: records device contents in the sync state, writes prints to
  // stdout (sorted by launch index z, y, x, then sequence) and keeps exception reports on the
  // context. Returns the first tile error, if any.
  absl::Status Finish();
  // What each device's Launch returned.
  const std::vector<absl::Status>& device_statuses() const { return statuses_; }

 private:
  struct Written {
    std::vector<std::pair<uint64_t, uint64_t>> ranges;  // byte ranges the device wrote
    std::vector<uint64_t> full_hashes;  // chunk hashes of a complete final copy, if sent
  };

  void Apply(size_t device, v1::TileResult& result);
  void ApplyRegion(size_t device, bool final_tile, const v1::BufferRegion& region);
  void RecordError(absl::Status status);

  Context& context_;
  std::vector<DeviceSlot>& slots_;
  const bool multi_device_;

  std::mutex mu_;  // guards the queue and the device counters
  std::condition_variable cv_;
  std::vector<std::pair<size_t, v1::TileResult>> queue_ ABSL_GUARDED_BY(mu_);
  size_t running_devices_ ABSL_GUARDED_BY(mu_);
  std::vector<absl::Status> statuses_;  // each written once by its device thread

  // Launching thread only.
  // Multi-device: INPUT_OUTPUT contents before the launch, so a device's complete final copy
  // only contributes the bytes it changed and devices do not overwrite each other's tiles.
  absl::flat_hash_map<uint64_t, std::string> snapshots_;
  std::vector<absl::flat_hash_map<uint64_t, Written>> written_;  // per device, per buffer
  std::vector<v1::PrintRecord> prints_;
  std::vector<v1::ExceptionReport> exceptions_;
  void ReportExceptions();
  absl::Status first_error_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_GATHER_H_
