#include "optix7_session.h"

#include <cstring>
#include <map>
#include <mutex>

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "device_arena.h"
#include "module.h"

namespace tessera::worker {
namespace {

// Device memory committed by the sessions of this worker process: address -> (size, owner).
// Sessions of one host hold the same allocations; another host's would give the same addresses
// other contents, which one range of addresses cannot hold at once.
struct Committed {
  uint64_t size = 0;
  const Optix7Session* owner = nullptr;
};
std::mutex g_committed_mu;
std::map<uint64_t, Committed>& CommittedMemory() {
  static auto* const committed = new std::map<uint64_t, Committed>;
  return *committed;
}

std::string Range(uint64_t address, uint64_t size) {
  return absl::StrFormat("[0x%x, 0x%x)", address, address + size);
}

// The allocation holding [address, address + size) in `allocations`, or null.
const std::pair<const uint64_t, uint64_t>* Holding(const std::map<uint64_t, uint64_t>& allocations,
                                                   uint64_t address, uint64_t size) {
  auto it = allocations.upper_bound(address);
  if (it == allocations.begin()) return nullptr;
  --it;
  if (address - it->first > it->second || size > it->second - (address - it->first)) {
    return nullptr;
  }
  return &*it;
}

absl::Status CheckEntry(const v1::Optix7Entry& entry, const char* role, uint64_t group,
                        const v1::StateDelta& delta) {
  if (entry.function().empty()) return absl::OkStatus();
  const std::string& hash = entry.module_hash();
  bool carried = false;
  for (const v1::ModuleChunk& m : delta.modules()) carried = carried || m.module_hash() == hash;
  if (!carried && !ModuleCache::Get().Has(hash)) {
    return absl::FailedPreconditionError(absl::StrCat(
        "OptiX 7 program group #", group, ": ", role, " '", absl::CEscape(entry.function()),
        "' needs program module ", absl::CEscape(entry.module_path()), " (",
        absl::CEscape(hash.substr(0, 64)), "), which this device has not received"));
  }
  return absl::OkStatus();
}

}  // namespace

bool Optix7Session::Carries(const v1::StateDelta& delta) {
  if (delta.has_allocations() || delta.memory_size() > 0) return true;
  for (const v1::Object& o : delta.objects()) {
    if (o.has_optix7_program_group() || o.has_optix7_pipeline()) return true;
  }
  return false;
}

Optix7Session::~Optix7Session() {
  if (shares_host_memory_) return;
  std::lock_guard<std::mutex> lock(g_committed_mu);
  auto& committed = CommittedMemory();
  absl::StatusOr<memory::DeviceArena*> arena = memory::ProcessArena();
  for (const auto& [address, size] : state_.allocations) {
    auto it = committed.find(address);
    if (it == committed.end() || it->second.owner != this) continue;
    committed.erase(it);
    if (arena.ok()) (void)(*arena)->Release(address, size);
  }
}

absl::Status Optix7Session::Check(const v1::StateDelta& delta) const {
  for (const v1::Object& o : delta.objects()) {
    if (o.has_optix7_program_group()) {
      const v1::Optix7ProgramGroup& g = o.optix7_program_group();
      for (const auto& [entry, role] :
           {std::pair{&g.entry(), "entry"}, std::pair{&g.continuation(), "continuation callable"},
            std::pair{&g.closest_hit(), "closest-hit"}, std::pair{&g.any_hit(), "any-hit"},
            std::pair{&g.intersection(), "intersection"}}) {
        if (absl::Status s = CheckEntry(*entry, role, g.id(), delta); !s.ok()) return s;
      }
    }
  }
  std::map<uint64_t, uint64_t> allocations;
  if (delta.has_allocations()) {
    absl::StatusOr<memory::DeviceArena*> arena = memory::ProcessArena();
    if (!arena.ok()) {
      return absl::FailedPreconditionError(
          absl::StrCat("this device has no device memory range: ", arena.status().message()));
    }
    for (const v1::DeviceAllocation& a : delta.allocations()) {
      if (a.size() == 0 || !(*arena)->Contains(a.address(), a.size())) {
        return absl::OutOfRangeError(absl::StrCat("device allocation ",
                                                  Range(a.address(), a.size()),
                                                  " is empty or outside this device's range"));
      }
      auto next = allocations.lower_bound(a.address());
      const bool overlaps_next = next != allocations.end() && next->first < a.address() + a.size();
      const bool overlaps_prev = next != allocations.begin() &&
                                 std::prev(next)->first + std::prev(next)->second > a.address();
      if (overlaps_next || overlaps_prev || !allocations.emplace(a.address(), a.size()).second) {
        return absl::InvalidArgumentError(
            absl::StrCat("device allocation ", Range(a.address(), a.size()), " overlaps another"));
      }
    }
    if (!shares_host_memory_) {
      std::lock_guard<std::mutex> lock(g_committed_mu);
      const auto& committed = CommittedMemory();
      for (const auto& [address, size] : allocations) {
        auto next = committed.lower_bound(address);
        for (auto it = next == committed.begin() ? next : std::prev(next);
             it != committed.end() && it->first < address + size; ++it) {
          if (it->second.owner != this && it->first + it->second.size > address) {
            return absl::FailedPreconditionError(absl::StrCat(
                "device memory ", Range(address, size),
                " is in use by another session of this "
                "worker: a worker holds the OptiX 7 device memory of one host at a time"));
          }
        }
      }
    }
  }
  const std::map<uint64_t, uint64_t>& after =
      delta.has_allocations() ? allocations : state_.allocations;
  for (const v1::DeviceMemoryChunk& c : delta.memory()) {
    if (c.run_addresses_size() == 0) {
      if (Holding(after, c.address(), c.data().size()) == nullptr) {
        return absl::OutOfRangeError(absl::StrCat("device memory chunk ",
                                                  Range(c.address(), c.data().size()),
                                                  " is not inside one device allocation"));
      }
      continue;
    }
    if (c.run_sizes_size() != c.run_addresses_size()) {
      return absl::InvalidArgumentError("device memory runs without as many sizes as addresses");
    }
    uint64_t bytes = 0;
    for (int r = 0; r < c.run_addresses_size(); ++r) {
      if (Holding(after, c.run_addresses(r), c.run_sizes(r)) == nullptr) {
        return absl::OutOfRangeError(absl::StrCat("device memory run ",
                                                  Range(c.run_addresses(r), c.run_sizes(r)),
                                                  " is not inside one device allocation"));
      }
      bytes += c.run_sizes(r);
    }
    if (bytes != c.data().size()) {
      return absl::InvalidArgumentError(
          absl::StrCat("device memory runs of ", bytes, " bytes carry ", c.data().size()));
    }
  }
  return absl::OkStatus();
}

absl::Status Optix7Session::Apply(const v1::StateDelta& delta) {
  for (uint64_t id : delta.removed()) {
    state_.program_groups.erase(id);
    state_.pipelines.erase(id);
  }
  for (const v1::Object& o : delta.objects()) {
    if (o.has_optix7_program_group()) {
      state_.program_groups[o.optix7_program_group().id()] = o.optix7_program_group();
    } else if (o.has_optix7_pipeline()) {
      state_.pipelines[o.optix7_pipeline().id()] = o.optix7_pipeline();
    }
  }
  if (delta.has_allocations()) {
    std::map<uint64_t, uint64_t> next;
    for (const v1::DeviceAllocation& a : delta.allocations()) next.emplace(a.address(), a.size());
    if (!shares_host_memory_) {
      absl::StatusOr<memory::DeviceArena*> arena = memory::ProcessArena();
      if (!arena.ok()) return arena.status();
      std::lock_guard<std::mutex> lock(g_committed_mu);
      auto& committed = CommittedMemory();
      for (const auto& [address, size] : state_.allocations) {
        auto kept = next.find(address);
        if (kept != next.end() && kept->second == size) continue;
        committed.erase(address);
        // Pages wholly inside the allocation read as zeros again; shared boundary pages stay.
        if (absl::Status s = (*arena)->Release(address, size); !s.ok()) return s;
      }
      for (const auto& [address, size] : next) {
        auto held = state_.allocations.find(address);
        if (held != state_.allocations.end() && held->second == size) continue;
        if (absl::Status s = (*arena)->Commit(address, size); !s.ok()) return s;
        committed[address] = Committed{size, this};
      }
    }
    state_.allocations = std::move(next);
  }
  if (!shares_host_memory_) {
    for (const v1::DeviceMemoryChunk& c : delta.memory()) {
      if (c.run_addresses_size() == 0) {
        std::memcpy(reinterpret_cast<void*>(static_cast<uintptr_t>(c.address())), c.data().data(),
                    c.data().size());
        continue;
      }
      size_t at = 0;
      for (int r = 0; r < c.run_addresses_size(); ++r) {
        std::memcpy(reinterpret_cast<void*>(static_cast<uintptr_t>(c.run_addresses(r))),
                    c.data().data() + at, c.run_sizes(r));
        at += c.run_sizes(r);
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace tessera::worker
