#include "launch_target.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <deque>
#include <map>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "context.h"
#include "context_extension.h"
#include "cuda_devices.h"
#include "device_table.h"
#include "hash.h"
#include "host_device_memory.h"
#include "lowering.h"
#include "status.h"
#include "system_info.h"
#include "tessera/detail/atomic_ops.h"

namespace tessera::optix7 {

// The devices of one OptixDeviceContext are those of an internal OptiX 3 context, which has no
// objects of its own: the pipeline and device memory ship as its extension.
class LaunchTarget final : public api::ContextExtension {
 public:
  api::Context* context() const { return context_; }
  // `cuda_device`: the CUDA device whose memory the target's devices hold (kEveryDevice: all).
  LaunchTarget(api::Context* context, int cuda_device)
      : context_(context), cuda_device_(cuda_device), writer_(NextWriter()) {
    context_->set_extension(this);
  }
  ~LaunchTarget() override {
    context_->set_extension(nullptr);
    context_->DestroyAll();
  }

  absl::Status Launch(const LaunchPipeline& pipeline, const v1::Optix7Launch& launch,
                      const std::vector<uint64_t>& dims) {
    pipeline_ = &pipeline;
    if (absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get(); memory.ok()) {
      (*memory)->MarkManagedWritten();
    }
    absl::Status status = context_->Launch(0, dims, &launch);
    pipeline_ = nullptr;
    TrimRuns();
    return status;
  }

  void AddToDelta(const api::DeviceSlot& slot, api::PreparedDelta* prepared) override {
    if (pipeline_ != nullptr) AddPipeline(slot.sync, prepared);
    absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
    if (memory.ok()) AddMemory(slot, **memory, prepared);
  }

  absl::Status ApplyWritten(const api::DeviceSlot& slot, const v1::BufferRegion& region) override {
    absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
    if (!memory.ok()) return memory.status();
    // Every allocation, not only the device's own: a peer's programs may write any it reaches.
    const std::vector<std::pair<uintptr_t, size_t>> allocations = (*memory)->Allocations();
    uint64_t at = 0;
    for (int r = 0; r < region.run_offsets_size(); ++r) {
      const uint64_t address = region.run_offsets(r);
      const uint64_t size = r < region.run_sizes_size() ? region.run_sizes(r) : 0;
      // A run may span adjacent allocations (runs merge neighbouring bytes), not a gap.
      for (uint64_t at_address = address; at_address < address + size;) {
        const std::pair<uintptr_t, size_t>* holding = Holding(allocations, at_address);
        if (holding == nullptr) {
          return absl::OutOfRangeError(absl::StrFormat(
              "programs wrote device memory at 0x%x, outside every allocation", at_address));
        }
        at_address = holding->first + holding->second;
      }
      if (!region.data().empty()) {
        if (size > region.data().size() - at) {
          return absl::DataLossError("a device memory region holds fewer bytes than its runs");
        }
        std::memcpy(reinterpret_cast<void*>(static_cast<uintptr_t>(address)),
                    region.data().data() + at, size);
        at += size;
        context_->CountReceived(size);
      }
      // Other devices receive these bytes before the next launch (AddMemory).
      (*memory)->MarkWritten(address, size, writer_);
      runs_.push_back(WrittenRun{++last_run_, slot.sync.session_id, address, size});
    }
    for (const v1::DeviceMemoryAtomic& a : region.atomics()) {
      if (absl::Status s = ApplyAtomic(slot, allocations, **memory, a); !s.ok()) return s;
    }
    return absl::OkStatus();
  }

 private:
  // The launch's pipeline and program groups, and their modules, where the device lacks them;
  // program groups and pipelines of earlier launches leave the device.
  void AddPipeline(const api::DeviceSync& sync, api::PreparedDelta* prepared) {
    std::vector<std::pair<uint64_t, uint64_t>> shipped;
    auto ship = [&](auto wire, auto set) {
      shipped.emplace_back(wire.id(), wire.version());
      auto known = sync.optix7_versions.find(wire.id());
      if (known != sync.optix7_versions.end() && known->second == wire.version()) return;
      set(prepared->delta.add_objects(), std::move(wire));
    };
    for (const LaunchProgramGroup* group : pipeline_->groups) {
      for (const LaunchModule* module : group->modules) {
        api::LowerModuleBytes(module->hash, module->bytes, sync, prepared);
      }
      ship(group->wire, [](v1::Object* o, v1::Optix7ProgramGroup g) {
        *o->mutable_optix7_program_group() = std::move(g);
      });
    }
    ship(pipeline_->wire,
         [](v1::Object* o, v1::Optix7Pipeline p) { *o->mutable_optix7_pipeline() = std::move(p); });
    std::vector<uint64_t> gone;
    for (const auto& [id, version] : sync.optix7_versions) {
      if (std::none_of(shipped.begin(), shipped.end(),
                       [id = id](const auto& s) { return s.first == id; })) {
        gone.push_back(id);
      }
    }
    std::sort(gone.begin(), gone.end());
    for (uint64_t id : gone) prepared->delta.add_removed(id);
    prepared->commits.push_back([shipped, gone](api::DeviceSync* s) {
      for (uint64_t id : gone) s->optix7_versions.erase(id);
      for (const auto& [id, version] : shipped) s->optix7_versions[id] = version;
    });
  }

  // The allocation list when it changed, and (to devices in other processes) every piece of
  // device memory written since the device's last delta whose content it lacks.
  void AddMemory(const api::DeviceSlot& slot, HostDeviceMemory& memory,
                 api::PreparedDelta* prepared) {
    const api::DeviceSync& sync = slot.sync;
    const uint64_t generation = memory.allocation_generation();
    // Only what the device may reach (with one CUDA device per Tessera device: the CUDA device's
    // allocations and its peers'), so N devices that each hold a copy of a scene do not each
    // receive all N copies.
    const std::vector<std::pair<uintptr_t, size_t>> allocations = memory.Allocations(cuda_device_);
    if (generation != sync.allocation_generation) {
      v1::StateDelta& delta = prepared->delta;
      delta.set_has_allocations(true);
      for (const auto& [address, size] : allocations) {
        v1::DeviceAllocation* a = delta.add_allocations();
        a->set_address(address);
        a->set_size(size);
      }
      prepared->commits.push_back([generation, allocations](api::DeviceSync* s) {
        s->allocation_generation = generation;
        // Pieces outside every allocation are gone from the device (released or unknown).
        absl::erase_if(s->memory_hashes, [&](const auto& entry) {
          return Holding(allocations, entry.first) == nullptr;
        });
      });
    }
    if (slot.desc.type == api::DeviceSpecEntry::Type::kInproc) return;  // the host's own memory
    // A device that has all of device memory takes what the host wrote since, by chunk, and the
    // bytes other devices' programs wrote, as they were written: a launch that writes 1% of a
    // buffer costs the other devices 1% of it, and one that writes what was there costs nothing.
    // What programs of another target (OptixDeviceContext) wrote comes by chunk, as host writes
    // do: this target never saw those runs. A new device takes every chunk ever written.
    const bool whole = !sync.memory_synced;
    const uint64_t epoch = memory.epoch();
    const uint64_t cursor = last_run_;
    std::vector<std::pair<uint64_t, uint64_t>> hashes;
    std::vector<std::pair<uintptr_t, uintptr_t>> stale;  // pieces whose hash the device lost
    if (!whole) {
      for (const WrittenRun& run : runs_) {
        if (run.sequence <= sync.memory_run_cursor) continue;
        // The device's copy of these pieces no longer has the content its hashes say.
        stale.emplace_back(run.address, run.address + run.size);
      }
    }
    // A piece programs wrote since the device's last delta is sent whatever its hash: the hash is
    // of the content before those writes (a buffer freed and allocated again reads zeros on the
    // host, the hash of the zeros the device was sent before the programs wrote there).
    auto written_since = [&](uintptr_t begin, uintptr_t end) {
      return std::any_of(stale.begin(), stale.end(),
                         [&](const auto& r) { return r.first < end && r.second > begin; });
    };
    if (whole || epoch != sync.memory_epoch) {
      for (const auto& [chunk, written] :
           memory.ChunksWrittenSince(whole ? 0 : sync.memory_epoch, whole ? 0 : writer_)) {
        ForEachPiece(allocations, chunk, chunk + HostDeviceMemory::kChunkBytes,
                     [&](uintptr_t begin, uintptr_t end) {
                       const uint64_t hash = PieceHash(begin, end - begin, written);
                       auto known = sync.memory_hashes.find(begin);
                       if (!whole && known != sync.memory_hashes.end() && known->second == hash &&
                           !written_since(begin, end)) {
                         return;
                       }
                       AddBytes(begin, end, hash, prepared);
                       hashes.emplace_back(begin, hash);
                     });
      }
    }
    if (!whole) {
      std::vector<std::pair<uintptr_t, uintptr_t>> ranges;
      for (const WrittenRun& run : runs_) {
        if (run.sequence <= sync.memory_run_cursor) continue;
        if (run.writer != sync.session_id || run.to_writer) {
          ranges.emplace_back(run.address, run.address + run.size);
        }
      }
      // Packed many to a message: scattered writes are many small ranges.
      v1::DeviceMemoryChunk* packed = nullptr;
      for (const auto& [begin, end] : Coalesced(std::move(ranges))) {
        for (uintptr_t c = memory.ChunkOf(begin); c < end; c += HostDeviceMemory::kChunkBytes) {
          ForEachPiece(allocations, std::max(c, begin),
                       std::min<uintptr_t>(c + HostDeviceMemory::kChunkBytes, end),
                       [&](uintptr_t b, uintptr_t e) {
                         if (packed == nullptr ||
                             packed->data().size() + (e - b) > HostDeviceMemory::kChunkBytes) {
                           packed = prepared->delta.add_memory();
                         }
                         packed->add_run_addresses(b);
                         packed->add_run_sizes(e - b);
                         packed->mutable_data()->append(reinterpret_cast<const char*>(b), e - b);
                       });
        }
      }
    }
    prepared->commits.push_back([&memory, epoch, cursor, allocations, hashes = std::move(hashes),
                                 stale = std::move(stale)](api::DeviceSync* s) {
      for (const auto& [begin, end] : stale) {
        for (uintptr_t c = memory.ChunkOf(begin); c < end; c += HostDeviceMemory::kChunkBytes) {
          ForEachPiece(allocations, c, c + HostDeviceMemory::kChunkBytes,
                       [&, begin = begin, end = end](uintptr_t b, uintptr_t e) {
                         if (b < end && e > begin) s->memory_hashes.erase(b);
                       });
        }
      }
      s->memory_synced = true;
      s->memory_epoch = epoch;
      s->memory_run_cursor = cursor;
      for (const auto& [address, hash] : hashes) s->memory_hashes[address] = hash;
    });
  }

  // Calls f(begin, end) for each part of [begin, end) inside one allocation, in order.
  template <typename F>
  static void ForEachPiece(const std::vector<std::pair<uintptr_t, size_t>>& allocations,
                           uintptr_t begin, uintptr_t end, F&& f) {
    auto it = std::upper_bound(allocations.begin(), allocations.end(), begin,
                               [](uintptr_t a, const auto& b) { return a < b.first; });
    if (it != allocations.begin() && std::prev(it)->first + std::prev(it)->second > begin) --it;
    for (; it != allocations.end() && it->first < end; ++it) {
      const uintptr_t b = std::max<uintptr_t>(begin, it->first);
      const uintptr_t e = std::min<uintptr_t>(end, it->first + it->second);
      if (b < e) f(b, e);
    }
  }

  // Sorted, overlapping and touching ranges merged.
  static std::vector<std::pair<uintptr_t, uintptr_t>> Coalesced(
      std::vector<std::pair<uintptr_t, uintptr_t>> ranges) {
    std::sort(ranges.begin(), ranges.end());
    std::vector<std::pair<uintptr_t, uintptr_t>> out;
    for (const auto& r : ranges) {
      if (!out.empty() && r.first <= out.back().second) {
        out.back().second = std::max(out.back().second, r.second);
      } else {
        out.push_back(r);
      }
    }
    return out;
  }

  static void AddBytes(uintptr_t begin, uintptr_t end, uint64_t hash,
                       api::PreparedDelta* prepared) {
    v1::DeviceMemoryChunk* c = prepared->delta.add_memory();
    c->set_address(begin);
    c->set_data(reinterpret_cast<const char*>(begin), end - begin);
    c->set_hash(hash);
  }

  // Forgets runs every device has taken (devices lost since take all of memory again).
  void TrimRuns() {
    uint64_t taken = last_run_;
    for (const api::DeviceSlot& slot : context_->device_slots()) {
      if (slot.device == nullptr || slot.desc.type == api::DeviceSpecEntry::Type::kInproc) {
        continue;
      }
      taken = std::min(taken, slot.sync.memory_synced ? slot.sync.memory_run_cursor : last_run_);
    }
    while (!runs_.empty() && runs_.front().sequence <= taken) runs_.pop_front();
  }

  // One address's atomics from one device (docs/device_memory.md, "Atomics across devices"):
  // op(host value, combined operand), atomically, since an in-process device's programs may be
  // updating the same value right now. The result goes to every device, the sender included:
  // its copy holds only its own atomics' effect.
  absl::Status ApplyAtomic(const api::DeviceSlot& slot,
                           const std::vector<std::pair<uintptr_t, size_t>>& allocations,
                           HostDeviceMemory& memory, const v1::DeviceMemoryAtomic& a) {
    const uint32_t size = atomic_ops::SizeOf(a.op());
    const std::pair<uintptr_t, size_t>* holding = Holding(allocations, a.address());
    if (size == 0 || a.address() % size != 0) {
      return absl::InvalidArgumentError(absl::StrFormat(
          "device sent an atomic operation of unknown kind %u or misaligned address 0x%x", a.op(),
          a.address()));
    }
    if (holding == nullptr || holding->first + holding->second - a.address() < size) {
      return absl::OutOfRangeError(absl::StrFormat(
          "programs' atomics reached device memory at 0x%x, outside every allocation",
          a.address()));
    }
    void* address = reinterpret_cast<void*>(static_cast<uintptr_t>(a.address()));
    atomic_ops::Apply(a.op(), address, a.operand(), a.limit());
    context_->CountReceived(size);
    memory.MarkWritten(a.address(), size, writer_);
    runs_.push_back(WrittenRun{++last_run_, slot.sync.session_id, a.address(), size,
                               /*to_writer=*/true});
    return absl::OkStatus();
  }

  // The allocation holding `address`, or null.
  static const std::pair<uintptr_t, size_t>* Holding(
      const std::vector<std::pair<uintptr_t, size_t>>& allocations, uint64_t address) {
    auto it = std::upper_bound(allocations.begin(), allocations.end(), address,
                               [](uint64_t a, const auto& b) { return a < b.first; });
    if (it == allocations.begin()) return nullptr;
    --it;
    return address - it->first < it->second ? &*it : nullptr;
  }

  // The content hash of [address, address + size), computed once per write epoch of its chunk
  // (every device of the context compares against the same value).
  uint64_t PieceHash(uintptr_t address, size_t size, uint64_t epoch) {
    Cached& cached = hashes_[address];
    if (cached.epoch != epoch || cached.size != size) {
      cached.epoch = epoch;
      cached.size = size;
      cached.hash = api::Hash64(reinterpret_cast<const void*>(address), size);
    }
    return cached.hash;
  }

  struct Cached {
    uint64_t epoch = 0;
    size_t size = 0;
    uint64_t hash = 0;
  };
  // Bytes a device's programs wrote, in the order the host applied them, until every device has
  // them: `writer` is the session of the device that wrote them, which has them already unless
  // `to_writer` (the host combined them with other devices' atomics).
  struct WrittenRun {
    uint64_t sequence = 0;
    uint64_t writer = 0;
    uintptr_t address = 0;
    size_t size = 0;
    bool to_writer = false;
  };

  // Writers of device memory are told apart by a number never reused in the process (0: the
  // host), not by address: a target destroyed and another made at its address must not take
  // the first one's writes for its own.
  static uint64_t NextWriter() {
    static std::atomic<uint64_t> next{1};
    return next++;
  }

  api::Context* context_;
  const int cuda_device_;
  const uint64_t writer_;
  const LaunchPipeline* pipeline_ = nullptr;  // during Launch
  std::map<uintptr_t, Cached> hashes_;
  std::deque<WrittenRun> runs_;
  uint64_t last_run_ = 0;
};

absl::StatusOr<LaunchTargetPtr> CreateLaunchTarget(int cuda_device) {
  absl::StatusOr<api::Context*> context = api::Context::Create();
  if (!context.ok()) return context.status();
  if (cuda_device != kEveryDevice) {
    // One Tessera device only: it is CUDA device `cuda_device` (TESSERA_CUDA_DEVICES=each).
    if (absl::Status s = (*context)->SetDevices({cuda_device}); !s.ok()) {
      (*context)->DestroyAll();
      return absl::FailedPreconditionError(
          absl::StrCat("CUDA device ", cuda_device, " has no Tessera device: ", s.message(),
                       " (TESSERA_DEVICES changed since the context was created?)"));
    }
  }
  return LaunchTargetPtr(new LaunchTarget(*context, cuda_device));
}

namespace {

// Each Tessera device of TESSERA_DEVICES as a CUDA device (cuda_devices.h). Remote workers are
// not asked for their threads: cudaGetDeviceCount must not wait on the network.
absl::StatusOr<std::vector<CudaDevice>> ListTesseraDevices() {
  absl::StatusOr<std::vector<api::DeviceDesc>> devices = api::DevicesFromEnvironment();
  if (!devices.ok()) return devices.status();
  std::vector<CudaDevice> out;
  for (const api::DeviceDesc& d : *devices) {
    int threads = 1;
    if (d.type == api::DeviceSpecEntry::Type::kInproc) threads = api::HardwareThreads();
    if (d.type == api::DeviceSpecEntry::Type::kLocal) {
      threads = std::max(1, api::HardwareThreads() / std::max(1, d.local_count));
    }
    out.push_back({absl::StrCat(d.name, " (", d.address, ")"), threads});
  }
  return out;
}

// Installed when libtessera loads: the CUDA runtime's objects do not link api_core.
[[maybe_unused]] const bool g_lister_installed = [] {
  SetTesseraDeviceLister(&ListTesseraDevices);
  return true;
}();

}  // namespace

void DestroyLaunchTarget(LaunchTarget* target) { delete target; }

void TargetTransferStats(LaunchTarget& target, uint64_t* sent, uint64_t* received) {
  *sent = target.context()->bytes_sent();
  *received = target.context()->bytes_received();
}

absl::Status LaunchOnTarget(LaunchTarget& target, const LaunchPipeline& pipeline,
                            const v1::Optix7Launch& launch, const std::vector<uint64_t>& dims) {
  return target.Launch(pipeline, launch, dims);
}

}  // namespace tessera::optix7
