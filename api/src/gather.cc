#include "gather.h"

#include <algorithm>
#include <cstdio>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "buffer.h"
#include "context.h"
#include "hash.h"
#include "status.h"
#include "tessera/scheduler/device.h"

namespace tessera::api {
namespace {

uint64_t IndexAt(const v1::PrintRecord& r, int i) {
  return i < r.launch_index_size() ? r.launch_index(i) : 0;
}

}  // namespace

// Exceptions that reached no exception program: with printing enabled each one is printed in
// launch-index order, as rtPrintExceptionDetails would; otherwise one line on stderr says how many
// there were, so they are never silent.
void LaunchGather::ReportExceptions() {
  if (exceptions_.empty()) return;
  std::stable_sort(exceptions_.begin(), exceptions_.end(),
                   [](const v1::ExceptionReport& a, const v1::ExceptionReport& b) {
                     auto key = [](const v1::ExceptionReport& e) {
                       auto at = [&](int i) {
                         return i < e.launch_index_size() ? e.launch_index(i) : uint64_t{0};
                       };
                       return std::make_tuple(at(2), at(1), at(0));
                     };
                     return key(a) < key(b);
                   });
  if (context_.print_enabled()) {
    for (const auto& e : exceptions_)
      std::fwrite(e.details().data(), 1, e.details().size(), stdout);
    std::fflush(stdout);
    return;
  }
  std::fprintf(stderr,
               "tessera: %zu launch index(es) raised an exception and the entry point has no "
               "exception program; first: %s",
               exceptions_.size(), exceptions_.front().details().c_str());
  if (exceptions_.front().details().empty() || exceptions_.front().details().back() != '\n') {
    std::fputc('\n', stderr);
  }
}

LaunchGather::LaunchGather(Context& context, std::vector<DeviceSlot>& slots)
    : context_(context),
      slots_(slots),
      multi_device_(slots.size() > 1),
      running_devices_(slots.size()),
      statuses_(slots.size()),
      written_(slots.size()) {
  if (!multi_device_) return;
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() != Kind::kBuffer) continue;
    auto* b = static_cast<Buffer*>(object);
    if (b->gathers_content() && b->ships_content()) {
      snapshots_[id].assign(reinterpret_cast<const char*>(b->bytes()), b->byte_size());
    }
  }
}

void LaunchGather::RecordError(absl::Status status) {
  if (first_error_.ok()) first_error_ = std::move(status);
}

void LaunchGather::OnResult(size_t device, v1::TileResult&& result) {
  std::lock_guard<std::mutex> lock(mu_);
  queue_.emplace_back(device, std::move(result));
  cv_.notify_all();
}

void LaunchGather::DeviceDone(size_t device, absl::Status status) {
  std::lock_guard<std::mutex> lock(mu_);
  statuses_[device] = std::move(status);
  --running_devices_;
  cv_.notify_all();
}

bool LaunchGather::ProcessUntil(std::chrono::steady_clock::time_point deadline) {
  while (true) {
    std::vector<std::pair<size_t, v1::TileResult>> batch;
    bool done;
    {
      std::unique_lock<std::mutex> lock(mu_);
      auto ready = [&] { return !queue_.empty() || running_devices_ == 0; };
      if (deadline == std::chrono::steady_clock::time_point::max()) {
        cv_.wait(lock, ready);
      } else {
        cv_.wait_until(lock, deadline, ready);
      }
      batch.swap(queue_);
      done = running_devices_ == 0;
    }
    for (auto& [device, result] : batch) Apply(device, result);
    if (done) {
      // Devices finished: nothing more can arrive once the queue is drained.
      std::lock_guard<std::mutex> lock(mu_);
      if (queue_.empty()) return true;
      continue;
    }
    // Keep the timeout callback on schedule even while results stream in.
    if (std::chrono::steady_clock::now() >= deadline) return false;
  }
}

void LaunchGather::Apply(size_t device, v1::TileResult& result) {
  const std::string& device_name = slots_[device].desc.name;
  if (!result.error().empty()) {
    RTresult code = result.error_code() != 0 ? static_cast<RTresult>(result.error_code())
                                             : RT_ERROR_LAUNCH_FAILED;
    RecordError(RtError(code, absl::StrCat("device '", device_name, "': ", result.error())));
  }
  const bool final_tile = result.tile_index() == kFinalTileIndex;
  for (const v1::BufferRegion& region : result.regions()) ApplyRegion(device, final_tile, region);
  for (auto& p : *result.mutable_prints()) prints_.push_back(std::move(p));
  for (auto& e : *result.mutable_exceptions()) exceptions_.push_back(std::move(e));
}

void LaunchGather::ApplyRegion(size_t device, bool final_tile, const v1::BufferRegion& region) {
  Object* object = context_.FindById(region.buffer_id());
  if (object == nullptr || object->kind() != Kind::kBuffer) {
    RecordError(
        RtError(RT_ERROR_LAUNCH_FAILED,
                absl::StrCat("device '", slots_[device].desc.name,
                             "' sent contents for unknown buffer id ", region.buffer_id())));
    return;
  }
  auto* b = static_cast<Buffer*>(object);
  // INPUT and GPU_LOCAL buffers never come back to the host (DESIGN.md buffer table).
  if (!b->gathers_content()) return;
  const std::string& data = region.data();
  const uint64_t offset = region.offset();
  if (offset > b->byte_size() || data.size() > b->byte_size() - offset) {
    RecordError(RtError(RT_ERROR_LAUNCH_FAILED,
                        absl::StrCat("device '", slots_[device].desc.name, "' wrote bytes [",
                                     offset, ", ", offset + data.size(), ") outside ",
                                     b->Describe(), " (", b->byte_size(), " bytes)")));
    return;
  }
  Written& w = written_[device][b->id()];
  w.ranges.emplace_back(offset, offset + data.size());
  if (final_tile && offset == 0 && data.size() == b->byte_size() && b->ships_content()) {
    // A complete copy: the device's contents are now exactly known.
    w.full_hashes.clear();
    for (uint64_t begin = 0; begin < data.size(); begin += kChunkBytes) {
      uint64_t n = std::min<uint64_t>(kChunkBytes, data.size() - begin);
      w.full_hashes.push_back(ChunkHash(data.data() + begin, n));
    }
  }
  if (!final_tile || !multi_device_) {
    b->WriteRegion(offset, data).IgnoreError();  // bounds checked above
    return;
  }
  // Several devices: a device's final copy is stale outside its own tiles, so only the bytes it
  // changed during this launch count. Before the launch it held the host's contents (INPUT_OUTPUT
  // buffers are synced) or, for OUTPUT buffers, its own previous final copy (zeros when new).
  const std::string* before = nullptr;
  std::string zeros;
  auto& copies = slots_[device].sync.output_copies;
  if (b->ships_content()) {
    before = &snapshots_[b->id()];
  } else if (auto it = copies.find(b->id());
             it != copies.end() && it->second.size() == b->byte_size()) {
    before = &it->second;
  } else {
    zeros.assign(b->byte_size(), '\0');
    before = &zeros;
  }
  size_t i = 0;
  while (i < data.size()) {
    if (data[i] == (*before)[offset + i]) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < data.size() && data[j] != (*before)[offset + j]) ++j;
    b->WriteRegion(offset + i, absl::string_view(data).substr(i, j - i)).IgnoreError();
    i = j;
  }
  if (!b->ships_content()) {
    std::string& copy = copies[b->id()];
    if (copy.size() != b->byte_size()) copy = std::move(zeros);
    copy.resize(b->byte_size(), '\0');
    copy.replace(offset, data.size(), data);
  }
}

absl::Status LaunchGather::Finish() {
  ProcessUntil(std::chrono::steady_clock::time_point::max());
  for (size_t d = 0; d < slots_.size(); ++d) {
    for (auto& [id, w] : written_[d]) {
      auto state = slots_[d].sync.buffers.find(id);
      if (state == slots_[d].sync.buffers.end()) continue;
      std::vector<uint64_t>& hashes = state->second.hashes;
      if (!w.full_hashes.empty() && w.full_hashes.size() == hashes.size()) {
        hashes = std::move(w.full_hashes);
        continue;
      }
      // Partial writes: those chunks are no longer known; the next launch resends them.
      for (const auto& [begin, end] : w.ranges) {
        if (begin == end) continue;
        for (uint64_t c = begin / kChunkBytes; c <= (end - 1) / kChunkBytes && c < hashes.size();
             ++c) {
          hashes[c] = 0;
        }
      }
    }
  }

  std::stable_sort(
      prints_.begin(), prints_.end(), [](const v1::PrintRecord& a, const v1::PrintRecord& b) {
        return std::make_tuple(IndexAt(a, 2), IndexAt(a, 1), IndexAt(a, 0), a.sequence()) <
               std::make_tuple(IndexAt(b, 2), IndexAt(b, 1), IndexAt(b, 0), b.sequence());
      });
  for (const v1::PrintRecord& p : prints_) std::fwrite(p.text().data(), 1, p.text().size(), stdout);
  std::fflush(stdout);
  prints_.clear();
  ReportExceptions();
  context_.set_last_exceptions(std::move(exceptions_));
  exceptions_.clear();
  return first_error_;
}

}  // namespace tessera::api
