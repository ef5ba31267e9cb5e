#include "gather.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "buffer.h"
#include "context.h"
#include "context_extension.h"
#include "hash.h"
#include "status.h"
#include "tessera/scheduler/device.h"
#include "tessera/scheduler/log.h"
#include "variable.h"
#include "variable_scope.h"

namespace tessera::api {
namespace {

template <typename Record>
uint64_t IndexAt(const Record& r, int i) {
  return i < r.launch_index_size() ? r.launch_index(i) : 0;
}

// Launch-index order (z, then y, then x), then the order of prints within one launch index.
std::tuple<uint64_t, uint64_t, uint64_t, uint64_t> KeyOf(const v1::PrintRecord& p) {
  return {IndexAt(p, 2), IndexAt(p, 1), IndexAt(p, 0), p.sequence()};
}

uint64_t PrintBytes(const v1::PrintRecord& p) { return p.text().size() + p.dropped_bytes(); }

}  // namespace

// Exceptions that reached no exception program: each one printing showed was printed in
// launch-index order among the prints, as rtPrintExceptionDetails would; for the others (printing
// off, or rtContextSetPrintLaunchIndex selecting another launch index) one line on stderr says how
// many there were and what the first was, so they are never silent.
void LaunchGather::ReportExceptions() {
  if (exceptions_unshown_ == 0 || !first_exception_.has_value()) return;
  const std::string& first = first_exception_->details();
  log::Warn(log::Component::kApi,
            "%llu launch index(es) raised an exception that no exception program handled%s; "
            "first: %s",
            static_cast<unsigned long long>(exceptions_unshown_),
            context_.print_enabled() ? " and printing did not show" : "", first);
}

void LaunchGather::DropPrint(const v1::PrintRecord& p) {
  prints_dropped_ += std::max<uint64_t>(p.dropped_prints(), 1);
  print_bytes_dropped_ += PrintBytes(p);
}

void LaunchGather::AddPrint(v1::PrintRecord&& p) {
  if (print_cut_.has_value() && KeyOf(p) >= *print_cut_) {
    DropPrint(p);
    return;
  }
  print_bytes_ += PrintBytes(p);
  const bool oversized = p.dropped_bytes() > 0;
  prints_.push_back(std::move(p));
  // Sorting waits until another print buffer's worth arrived, so that it costs O(log n) a print.
  if (oversized || print_bytes_ > trim_at_bytes_) TrimPrints();
}

void LaunchGather::TrimPrints() {
  std::stable_sort(
      prints_.begin(), prints_.end(),
      [](const v1::PrintRecord& a, const v1::PrintRecord& b) { return KeyOf(a) < KeyOf(b); });
  const uint64_t limit = context_.print_buffer_size();
  uint64_t kept = 0;
  size_t i = 0;
  for (; i < prints_.size(); ++i) {
    const v1::PrintRecord& p = prints_[i];
    if (p.dropped_bytes() > 0 || p.text().size() > limit - kept) break;
    kept += p.text().size();
  }
  if (i < prints_.size()) {
    print_cut_ = KeyOf(prints_[i]);
    for (size_t j = i; j < prints_.size(); ++j) DropPrint(prints_[j]);
    prints_.resize(i);
  }
  print_bytes_ = kept;
  trim_at_bytes_ = limit > std::numeric_limits<uint64_t>::max() / 2 ? limit : 2 * limit;
}

void LaunchGather::AddException(v1::ExceptionReport&& e) {
  if (e.not_sent() > 0) {  // reports a device counted instead of sending (worker/core/runtime.cc)
    exception_count_ += e.not_sent();
    exceptions_unshown_ += e.not_sent_unshown();
    return;
  }
  ++exception_count_;
  // With printing enabled, a report of an exception that reached no exception program is the last
  // output of its launch index (the exception ended it): it takes its place in launch-index order
  // among the prints and counts against the print buffer like them. Only at the launch index
  // rtContextSetPrintLaunchIndex selects, as for rtPrintf (-1: any).
  bool shown = context_.print_enabled();
  const std::array<int, 3>& only = context_.print_launch_index();
  for (int i = 0; i < 3 && shown; ++i) {
    if (only[i] >= 0 && IndexAt(e, i) != static_cast<uint64_t>(only[i])) shown = false;
  }
  if (!shown) {
    ++exceptions_unshown_;
    auto key = [](const v1::ExceptionReport& r) {
      return std::make_tuple(IndexAt(r, 2), IndexAt(r, 1), IndexAt(r, 0));
    };
    if (!first_exception_.has_value() || key(e) < key(*first_exception_)) {
      first_exception_ = std::move(e);
    }
    return;
  }
  v1::PrintRecord p;
  *p.mutable_launch_index() = e.launch_index();
  p.set_sequence(std::numeric_limits<uint64_t>::max());
  *p.mutable_text() = std::move(*e.mutable_details());
  AddPrint(std::move(p));
}

LaunchGather::LaunchGather(Context& context)
    : context_(context), check_races_(context.race_check() && context.device_slots().size() > 1) {
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() != Kind::kBuffer) continue;
    auto* b = static_cast<Buffer*>(object);
    // GPU_LOCAL: writes of devices with a pointer come back into it.
    if (b->gathers_content() || b->gpu_local()) layouts_[id] = LayoutOf(*b);
    if (!b->gathers_content()) continue;
    host_epochs_[id] = b->host_write_epoch();
    if (!check_races_ || b->element_size() == 0) continue;
    RaceState& state = race_state_[id];
    state.before.assign(reinterpret_cast<const char*>(b->bytes()), b->byte_size());
    state.owner.assign(b->byte_size() / b->element_size(), -1);
  }
}

void LaunchGather::SetDevices(std::vector<DeviceSlot*> slots) {
  slots_ = std::move(slots);
  if (slots_.size() <= 1) {
    check_races_ = false;
    race_state_.clear();
  }
}

void LaunchGather::CheckRaces(size_t device, const Buffer& b, uint64_t offset,
                              absl::string_view data) {
  auto it = race_state_.find(b.id());
  if (it == race_state_.end()) return;
  RaceState& state = it->second;
  // Regions reach here only while the buffer keeps its launch-start layout (SameLayout), so
  // `before` and `owner` match its elements.
  const size_t size = b.element_size();
  const char* host = reinterpret_cast<const char*>(b.bytes());
  for (uint64_t at = 0; at + size <= data.size(); at += size) {
    const uint64_t byte = offset + at;
    const uint64_t element = byte / size;
    // Programs mark the elements they index, reads included: an element still holding its
    // value from before the launch was not written by this device.
    if (std::memcmp(data.data() + at, state.before.data() + byte, size) == 0) continue;
    int16_t& owner = state.owner[element];
    if (owner == kNoWriter) {
      owner = static_cast<int16_t>(device);
    } else if (owner >= 0 && owner != static_cast<int16_t>(device) &&
               std::memcmp(data.data() + at, host + byte, size) != 0) {
      std::lock_guard<std::mutex> lock(races_mu_);  // slices of a buffer check at once
      if (races_.size() < 10) races_.push_back({b.id(), element, size_t(owner), device});
      ++race_count_;
      owner = kSeveralWriters;  // each element is reported once
    }
  }
}

void LaunchGather::RecordError(absl::Status status) {
  if (first_error_.ok()) first_error_ = std::move(status);
}

void LaunchGather::Apply(scheduler::FinishedBatch& batch) {
  const std::string& device_name = slots_[batch.device]->desc.name;
  for (v1::TileResult& result : batch.results) {
    if (!result.error().empty()) {
      RTresult code = result.error_code() != 0 ? static_cast<RTresult>(result.error_code())
                                               : RT_ERROR_LAUNCH_FAILED;
      RecordError(RtError(code, absl::StrCat("device '", device_name, "': ", result.error())));
    }
    traces_ += result.traces();
    packet_answers_ += result.packet_answers();
    for (const v1::BufferRegion& region : result.regions()) ApplyRegion(batch.device, region);
    for (auto& p : *result.mutable_prints()) AddPrint(std::move(p));
    for (auto& e : *result.mutable_exceptions()) AddException(std::move(e));
  }
  CopyRuns(batch.device);
}

void LaunchGather::CopyRun(size_t device, const Run& run, uint64_t begin, uint64_t end) {
  begin = std::max(begin, run.offset);
  end = std::min(end, run.offset + run.data.size());
  if (begin >= end) return;
  const absl::string_view data = run.data.substr(begin - run.offset, end - begin);
  if (check_races_) CheckRaces(device, *run.buffer, begin, data);
  run.buffer->CopyDeviceBytes(begin, data);
}

void LaunchGather::CopyRuns(size_t device) {
  // A device's whole call arrives at once when it ends (a batch counts only when finished), so
  // a launch's last batch waits on this copy while every core is idle: large batches copy on
  // all of them (16 cores: a 1080p float4 image, 33 MB, took 9-11 ms on one).
  constexpr uint64_t kParallelBytes = uint64_t{4} << 20;
  constexpr uint64_t kSliceBytes = uint64_t{1} << 20;
  uint64_t bytes = 0;
  bool aligned = true;  // whole elements: slices then split no element between two threads
  for (const Run& r : runs_) {
    const uint64_t element = r.buffer->element_size();
    bytes += r.data.size();
    aligned = aligned && element > 0 && r.offset % element == 0 && r.data.size() % element == 0;
  }
  if (bytes < kParallelBytes || !aligned) {
    for (const Run& r : runs_) CopyRun(device, r, 0, std::numeric_limits<uint64_t>::max());
    runs_.clear();
    return;
  }
  // Each slice of a buffer is copied by one thread, its runs in their order: where runs overlap
  // (an element written again in a later epoch), the later one still lands last.
  struct Slice {
    uint64_t begin, end;
    std::vector<const Run*> runs;
  };
  std::vector<Slice> slices;
  absl::flat_hash_map<const Buffer*, size_t> first_slice;  // per buffer, its slices' start
  for (const Run& r : runs_) {
    const uint64_t element = r.buffer->element_size();
    const uint64_t slice_bytes = std::max<uint64_t>(1, kSliceBytes / element) * element;
    auto [it, added] = first_slice.try_emplace(r.buffer, slices.size());
    if (added) {
      for (uint64_t at = 0; at < r.buffer->byte_size(); at += slice_bytes) {
        slices.push_back({at, std::min(r.buffer->byte_size(), at + slice_bytes), {}});
      }
    }
    const uint64_t last = (r.offset + r.data.size() - 1) / slice_bytes;
    for (uint64_t i = r.offset / slice_bytes; i <= last; ++i) {
      slices[it->second + i].runs.push_back(&r);
    }
  }
  tbb::parallel_for(size_t{0}, slices.size(), [&](size_t i) {
    const Slice& slice = slices[i];
    for (const Run* r : slice.runs) CopyRun(device, *r, slice.begin, slice.end);
  });
  runs_.clear();
}

void LaunchGather::ForgetDeviceCopies() {
  for (const auto& [id, layout] : layouts_) {
    for (DeviceSlot* slot : slots_) {
      auto state = slot->sync.buffers.find(id);
      if (state == slot->sync.buffers.end()) continue;
      std::fill(state->second.hashes.begin(), state->second.hashes.end(), uint64_t{0});
    }
  }
}

LaunchGather::Layout LaunchGather::LayoutOf(const Buffer& b) {
  return Layout{b.format(), b.dimensionality(), {b.dim(0), b.dim(1), b.dim(2)}, b.element_size()};
}

bool LaunchGather::SameLayout(uint64_t id, const Buffer* b) {
  auto it = layouts_.find(id);
  if (it == layouts_.end() || (b != nullptr && it->second == LayoutOf(*b))) return true;
  if (layout_reported_.insert(id).second) {
    RecordError(RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat(b != nullptr ? b->Describe() : absl::StrCat("buffer #", id),
                     b != nullptr ? " was resized or reformatted" : " was destroyed",
                     " during the launch (by the timeout callback); what devices wrote to it "
                     "was dropped")));
  }
  return false;
}

void LaunchGather::ApplyRegion(size_t device, const v1::BufferRegion& region) {
  if (region.device_memory()) {
    absl::Status applied =
        context_.extension() == nullptr
            ? absl::InvalidArgumentError("device memory regions without OptiX 7 state")
            : context_.extension()->ApplyWritten(*slots_[device], region);
    if (!applied.ok()) {
      RecordError(
          RtError(RT_ERROR_LAUNCH_FAILED,
                  absl::StrCat("device '", slots_[device]->desc.name, "': ", applied.message())));
    }
    return;
  }
  Object* object = context_.FindById(region.buffer_id());
  if (!SameLayout(region.buffer_id(), object != nullptr && object->kind() == Kind::kBuffer
                                          ? static_cast<const Buffer*>(object)
                                          : nullptr)) {
    return;
  }
  if (object == nullptr || object->kind() != Kind::kBuffer) {
    RecordError(
        RtError(RT_ERROR_LAUNCH_FAILED,
                absl::StrCat("device '", slots_[device]->desc.name,
                             "' sent contents for unknown buffer id ", region.buffer_id())));
    return;
  }
  auto* b = static_cast<Buffer*>(object);
  // INPUT and GPU_LOCAL buffers never come back to the host (docs/devices.md "Buffers across
  // devices"), except into the views of GPU_LOCAL buffers with device pointers.
  if (!b->gathers_content() && !b->gpu_local()) return;
  const absl::string_view data = region.data();
  if (region.run_offsets_size() == 0) {
    ApplyRun(device, *b, region.offset(), data);
    return;
  }
  uint64_t at = 0;
  for (int r = 0; r < region.run_offsets_size(); ++r) {
    const uint64_t size = r < region.run_sizes_size() ? region.run_sizes(r) : 0;
    if (r >= region.run_sizes_size() || size > data.size() - at) {
      RecordError(
          RtError(RT_ERROR_LAUNCH_FAILED,
                  absl::StrCat("device '", slots_[device]->desc.name, "' sent packed runs of ",
                               b->Describe(), " that do not add up to their data")));
      return;
    }
    ApplyRun(device, *b, region.run_offsets(r), data.substr(at, size));
    at += size;
  }
}

void LaunchGather::ApplyRun(size_t device, Buffer& b, uint64_t offset, absl::string_view data) {
  if (offset > b.byte_size() || data.size() > b.byte_size() - offset) {
    RecordError(RtError(RT_ERROR_LAUNCH_FAILED,
                        absl::StrCat("device '", slots_[device]->desc.name, "' wrote bytes [",
                                     offset, ", ", offset + data.size(), ") outside ", b.Describe(),
                                     " (", b.byte_size(), " bytes)")));
    return;
  }
  if (data.empty()) return;
  if (b.gpu_local()) {
    // One device's own copy (it has a pointer): nothing to merge or race-check.
    b.CopyToDeviceView(slots_[device]->sync.ordinal, offset, data);
    context_.CountReceived(data.size());
    return;
  }
  // Runs hold exactly the elements the device's programs touched: applying them in any order
  // merges the devices' work (two devices writing one element is a race, as in OptiX). Their
  // bytes are copied once the batch's runs are known (CopyRuns).
  runs_.push_back(Run{&b, offset, data});
  b.NoteDeviceWrite(offset, data.size());
  context_.CountReceived(data.size());
  std::vector<int>& writers = chunk_writers_[b.id()];
  writers.resize((b.byte_size() + kChunkBytes - 1) / kChunkBytes, kNoWriter);
  const int d = static_cast<int>(device);
  for (uint64_t c = offset / kChunkBytes; c <= (offset + data.size() - 1) / kChunkBytes; ++c) {
    if (writers[c] == kNoWriter) {
      writers[c] = d;
    } else if (writers[c] != d) {
      writers[c] = kSeveralWriters;
    }
  }
}

namespace {

// The name an application knows a buffer by, or its id.
std::string BufferName(Context& context, uint64_t id) {
  const auto* b = static_cast<const Buffer*>(context.FindById(id));
  const std::string name = b != nullptr ? b->VariableName() : "";
  return name.empty() ? absl::StrCat("#", id) : absl::StrCat("'", name, "'");
}

}  // namespace

absl::Status LaunchGather::Finish() {
  if (race_count_ > 0) {
    for (const Race& r : races_) {
      // The timeout callback may have destroyed the buffer or emptied it since.
      const auto* b = static_cast<const Buffer*>(context_.FindById(r.buffer_id));
      const uint64_t w = b != nullptr ? std::max<uint64_t>(b->dim(0), 1) : 1;
      const uint64_t h = b != nullptr ? std::max<uint64_t>(b->dim(1), 1) : 1;
      log::Warn(log::Component::kApi,
                "race check: buffer %s element (%llu, %llu, %llu): devices '%s' and '%s' wrote "
                "different values in one launch",
                BufferName(context_, r.buffer_id), static_cast<unsigned long long>(r.element % w),
                static_cast<unsigned long long>(r.element / w % h),
                static_cast<unsigned long long>(r.element / (w * h)), slots_[r.first]->desc.name,
                slots_[r.second]->desc.name);
    }
    if (race_count_ > races_.size()) {
      log::Warn(log::Component::kApi, "race check: %llu more elements written by two devices",
                static_cast<unsigned long long>(race_count_ - races_.size()));
    }
  }
  context_.set_last_race_count(race_count_);
  // A device holds the host's contents of a chunk it alone wrote into (its own writes are what the
  // host applied); chunks other devices wrote into differ there and travel again next launch.
  for (const auto& [id, writers] : chunk_writers_) {
    Object* object = context_.FindById(id);
    if (object == nullptr) continue;
    const auto* b = static_cast<const Buffer*>(object);
    // A chunk a device alone wrote into matches the host's only if the host did not write the
    // buffer during the launch (the timeout callback may map it): otherwise it travels again.
    auto epoch = host_epochs_.find(id);
    const bool host_wrote = epoch == host_epochs_.end() || epoch->second != b->host_write_epoch();
    const bool ships = b->ships_content() && !host_wrote;
    for (size_t d = 0; d < slots_.size(); ++d) {
      auto state = slots_[d]->sync.buffers.find(id);
      if (state == slots_[d]->sync.buffers.end()) continue;
      std::vector<uint64_t>& hashes = state->second.hashes;
      for (size_t c = 0; c < writers.size() && c < hashes.size(); ++c) {
        if (writers[c] == kNoWriter) continue;
        const uint64_t begin = c * kChunkBytes;
        if (begin >= b->byte_size()) {  // the timeout callback shrank the buffer since
          hashes[c] = 0;
          continue;
        }
        const uint64_t n = std::min<uint64_t>(kChunkBytes, b->byte_size() - begin);
        hashes[c] = writers[c] == static_cast<int>(d) && ships
                        ? ChunkHash(reinterpret_cast<const char*>(b->bytes()) + begin, n)
                        : 0;
      }
    }
  }

  // The print buffer bounds a launch's output as in OptiX: whole prints, in launch-index order so
  // that what is kept does not depend on the device set, while they fit; the rest is dropped and
  // said so on stderr.
  TrimPrints();
  for (const v1::PrintRecord& p : prints_) std::fwrite(p.text().data(), 1, p.text().size(), stdout);
  std::fflush(stdout);
  if (prints_dropped_ > 0) {
    log::Warn(log::Component::kApi,
              "rtPrintf output of this launch exceeds the print buffer size (%llu bytes, "
              "rtContextSetPrintBufferSize): %llu prints (%llu bytes) were dropped",
              static_cast<unsigned long long>(context_.print_buffer_size()),
              static_cast<unsigned long long>(prints_dropped_),
              static_cast<unsigned long long>(print_bytes_dropped_));
  }
  prints_.clear();
  ReportExceptions();
  context_.set_last_exception_count(exception_count_);
  return first_error_;
}

}  // namespace tessera::api
