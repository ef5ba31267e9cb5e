#include "launch_target.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "context.h"
#include "context_extension.h"
#include "hash.h"
#include "host_device_memory.h"
#include "lowering.h"
#include "status.h"

namespace tessera::optix7 {

// The devices of one OptixDeviceContext are those of an internal OptiX 3 context, which has no
// objects of its own: the pipeline and device memory ship as its extension.
class LaunchTarget final : public api::ContextExtension {
 public:
  explicit LaunchTarget(api::Context* context) : context_(context) {
    context_->set_extension(this);
  }
  ~LaunchTarget() override {
    context_->set_extension(nullptr);
    context_->DestroyAll();
  }

  absl::Status Launch(const LaunchPipeline& pipeline, const v1::Optix7Launch& launch,
                      const std::vector<uint64_t>& dims) {
    pipeline_ = &pipeline;
    absl::Status status = context_->Launch(0, dims, &launch);
    pipeline_ = nullptr;
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
      }
      // Other devices receive it before the next launch.
      (*memory)->MarkWritten(address, size);
    }
    (void)slot;
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
    const std::vector<std::pair<uintptr_t, size_t>> allocations = memory.Allocations();
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
    const uint64_t epoch = memory.epoch();
    if (epoch == sync.memory_epoch) return;
    std::vector<std::pair<uint64_t, uint64_t>> hashes;
    for (const auto& [chunk, written] : memory.ChunksWrittenSince(sync.memory_epoch)) {
      const uintptr_t chunk_end = chunk + HostDeviceMemory::kChunkBytes;
      // The allocations the chunk overlaps: the first that ends after it begins, and on.
      auto it = std::upper_bound(allocations.begin(), allocations.end(), chunk,
                                 [](uintptr_t a, const auto& b) { return a < b.first; });
      if (it != allocations.begin() && std::prev(it)->first + std::prev(it)->second > chunk) --it;
      for (; it != allocations.end() && it->first < chunk_end; ++it) {
        const uintptr_t begin = std::max<uintptr_t>(chunk, it->first);
        const uintptr_t end = std::min<uintptr_t>(chunk_end, it->first + it->second);
        if (begin >= end) continue;
        const uint64_t hash = PieceHash(begin, end - begin, written);
        auto known = sync.memory_hashes.find(begin);
        if (known != sync.memory_hashes.end() && known->second == hash) continue;
        v1::DeviceMemoryChunk* c = prepared->delta.add_memory();
        c->set_address(begin);
        c->set_data(reinterpret_cast<const char*>(begin), end - begin);
        c->set_hash(hash);
        hashes.emplace_back(begin, hash);
      }
    }
    prepared->commits.push_back([epoch, hashes = std::move(hashes)](api::DeviceSync* s) {
      s->memory_epoch = epoch;
      for (const auto& [address, hash] : hashes) s->memory_hashes[address] = hash;
    });
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
  api::Context* context_;
  const LaunchPipeline* pipeline_ = nullptr;  // during Launch
  std::map<uintptr_t, Cached> hashes_;
};

absl::StatusOr<LaunchTargetPtr> CreateLaunchTarget() {
  absl::StatusOr<api::Context*> context = api::Context::Create();
  if (!context.ok()) return context.status();
  return LaunchTargetPtr(new LaunchTarget(*context));
}

void DestroyLaunchTarget(LaunchTarget* target) { delete target; }

absl::Status LaunchOnTarget(LaunchTarget& target, const LaunchPipeline& pipeline,
                            const v1::Optix7Launch& launch, const std::vector<uint64_t>& dims) {
  return target.Launch(pipeline, launch, dims);
}

}  // namespace tessera::optix7
