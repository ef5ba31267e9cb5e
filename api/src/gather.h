// Collects what devices send back during a launch, one finished batch at a time (a batch counts
// only when its device finished it, so a lost device leaves nothing half-applied): written buffer
// regions go straight into the host copies, prints and exception reports are kept; afterwards it
// updates what each device is known to hold and writes prints in launch-index order.
#ifndef TESSERA_API_SRC_GATHER_H_
#define TESSERA_API_SRC_GATHER_H_

#include <cstdint>
#include <mutex>
#include <optional>
#include <tuple>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "device_sync.h"
#include "tessera/rt.h"
#include "tessera/scheduler/dispatcher.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::api {

class Buffer;
class Context;

class LaunchGather {
 public:
  // Records the layouts and host write epochs of the buffers results may land in. Made before
  // state ships to devices: the timeout callback, which runs meanwhile, may resize, destroy or
  // write buffers, and what devices then hold is what was shipped, not what the host has.
  explicit LaunchGather(Context& context);
  // `slots` are the devices of the launch, in the order batches index them (known once state has
  // shipped). Before the first Apply.
  void SetDevices(std::vector<DeviceSlot*> slots);

  // Launching thread only (device threads never touch host objects, and the timeout callback,
  // which runs on that thread too, cannot race with this).
  void Apply(scheduler::FinishedBatch& batch);

  // After the last batch: records which buffer chunks each device now holds as the host does,
  // writes prints to stdout (sorted by launch index z, y, x, then sequence) and keeps exception
  // reports on the context. Returns the first tile error, if any.
  absl::Status Finish();

  // After a launch that was cancelled or failed: devices may hold writes to INPUT_OUTPUT buffers
  // that never reached the host (a batch counts only when it finished), so nothing is known about
  // their copies any more; the next launch sends those buffers' contents again.
  void ForgetDeviceCopies();

  // The launch's rtTrace calls and first rays answered by packets, over every finished call
  // (TileResult.traces, packet_answers; OptiX 3 launches).
  uint64_t traces() const { return traces_; }
  uint64_t packet_answers() const { return packet_answers_; }

 private:
  static constexpr int kNoWriter = -1;
  static constexpr int kSeveralWriters = -2;

  void ApplyRegion(size_t device, const v1::BufferRegion& region);
  // One written byte range of `b`, bounds-checked, recorded and queued for CopyRuns.
  void ApplyRun(size_t device, Buffer& b, uint64_t offset, absl::string_view data);
  // A queued byte range; `data` points into the batch being applied.
  struct Run {
    Buffer* buffer;
    uint64_t offset;
    absl::string_view data;
  };
  // Copies the queued runs into their buffers (race-checking them first), on several threads when
  // they are large, in their order wherever they overlap; then forgets them.
  void CopyRuns(size_t device);
  // The part of `run` in bytes [begin, end) of its buffer.
  void CopyRun(size_t device, const Run& run, uint64_t begin, uint64_t end);
  // Race checking (tesseraContextSetRaceCheck): records who wrote each element and reports two
  // devices writing different values to one element. Slices of one buffer may check at once.
  void CheckRaces(size_t device, const Buffer& b, uint64_t offset, absl::string_view data);
  void RecordError(absl::Status status);
  void ReportExceptions();
  // Whether `b` (nullptr: destroyed) still has the layout it had when the launch began; reports
  // it once when not. The timeout callback may resize, reformat or destroy buffers mid-launch.
  bool SameLayout(uint64_t id, const Buffer* b);

  struct Layout {
    RTformat format;
    unsigned dimensionality;
    size_t dims[3];
    size_t element_size;
    bool operator==(const Layout& o) const {
      return format == o.format && dimensionality == o.dimensionality && dims[0] == o.dims[0] &&
             dims[1] == o.dims[1] && dims[2] == o.dims[2] && element_size == o.element_size;
    }
  };
  static Layout LayoutOf(const Buffer& b);

  struct RaceState {
    std::string before;          // contents before the launch
    std::vector<int16_t> owner;  // per element: the device that changed it, or -1
  };
  struct Race {
    uint64_t buffer_id, element;
    size_t first, second;  // devices
  };

  Context& context_;
  std::vector<DeviceSlot*> slots_;
  bool check_races_;
  absl::flat_hash_map<uint64_t, RaceState> race_state_;
  absl::flat_hash_map<uint64_t, Layout> layouts_;  // of every buffer results may land in
  // Buffer::host_write_epoch() of those buffers when the launch began: a host write since (the
  // timeout callback mapping one) is in no device's copy.
  absl::flat_hash_map<uint64_t, uint64_t> host_epochs_;
  absl::flat_hash_set<uint64_t> layout_reported_;
  std::vector<Run> runs_;  // of the batch being applied
  std::mutex races_mu_;    // races_ and race_count_, which slices copied at once add to
  std::vector<Race> races_;
  uint64_t race_count_ = 0;
  // Per buffer id, per content chunk: which device wrote into it (or none, or several).
  absl::flat_hash_map<uint64_t, std::vector<int>> chunk_writers_;
  // Prints (and the reports of exceptions that printing shows) in launch-index order are kept
  // only while they fit the print buffer: the host holds at most about twice its size, however
  // much a launch prints. Once one is dropped, every one after it in that order is dropped too,
  // so records at or past `print_cut_` are counted and let go on arrival.
  using PrintKey = std::tuple<uint64_t, uint64_t, uint64_t, uint64_t>;  // z, y, x, sequence
  void AddPrint(v1::PrintRecord&& p);
  void AddException(v1::ExceptionReport&& e);
  void TrimPrints();  // sorts the kept prints, keeps what fits, sets print_cut_
  void DropPrint(const v1::PrintRecord& p);

  std::vector<v1::PrintRecord> prints_;
  uint64_t print_bytes_ = 0;    // text bytes in prints_
  uint64_t trim_at_bytes_ = 0;  // TrimPrints when print_bytes_ passes this
  std::optional<PrintKey> print_cut_;
  uint64_t prints_dropped_ = 0;
  uint64_t print_bytes_dropped_ = 0;
  // Exceptions that reached no exception program: how many, how many printing did not show
  // (printing off, or another launch index selected) and the first of those in launch-index
  // order.
  uint64_t exception_count_ = 0;
  uint64_t exceptions_unshown_ = 0;
  std::optional<v1::ExceptionReport> first_exception_;
  absl::Status first_error_;
  uint64_t traces_ = 0;
  uint64_t packet_answers_ = 0;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_GATHER_H_
