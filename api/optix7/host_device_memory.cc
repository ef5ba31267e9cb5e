#include "host_device_memory.h"

#include <algorithm>
#include <iterator>

namespace tessera::optix7 {

HostDeviceMemory::HostDeviceMemory(memory::DeviceArena* arena)
    : arena_(arena), allocator_(arena_->base(), arena_->size(), memory::DeviceArena::PageSize()) {}

absl::StatusOr<HostDeviceMemory*> HostDeviceMemory::Get() {
  static absl::StatusOr<HostDeviceMemory*>* const memory = [] {
    auto* result = new absl::StatusOr<HostDeviceMemory*>(nullptr);
    absl::StatusOr<memory::DeviceArena*> arena = memory::ProcessArena();
    if (!arena.ok()) {
      *result = arena.status();
    } else {
      *result = new HostDeviceMemory(*arena);  // lives as long as the process
    }
    return result;
  }();
  return *memory;
}

absl::StatusOr<uintptr_t> HostDeviceMemory::Allocate(size_t bytes, int owner, bool managed) {
  std::lock_guard<std::mutex> lock(mutex_);
  absl::StatusOr<uintptr_t> address = allocator_.Allocate(bytes);
  if (!address.ok()) return address;
  ++allocation_generation_;
  if (managed) managed_[*address] = bytes;
  if (absl::Status s = arena_->Commit(*address, bytes); !s.ok()) {
    (void)allocator_.Free(*address);
    return s;
  }
  owners_[*address] = owner;
  return address;
}

absl::Status HostDeviceMemory::Free(uintptr_t address) {
  std::lock_guard<std::mutex> lock(mutex_);
  absl::StatusOr<memory::DeviceAllocator::Freed> freed = allocator_.Free(address);
  if (!freed.ok()) return freed.status();
  ++allocation_generation_;
  managed_.erase(address);
  owners_.erase(address);
  if (freed->release_end > freed->release_begin) {
    // Released pages read zeros here from now on, while devices in other processes keep what they
    // had: a host write, so that an allocation made there again reaches them as the host has it
    // (otherwise a device that believes it holds the old bytes skips sending back writes equal to
    // them, and the host keeps its zeros).
    MarkWrittenLocked(freed->release_begin, freed->release_end - freed->release_begin, 0);
    return arena_->Release(freed->release_begin, freed->release_end - freed->release_begin);
  }
  return absl::OkStatus();
}

bool HostDeviceMemory::IsAllocated(uintptr_t address, size_t length) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return allocator_.Find(address, length) != nullptr;
}

bool HostDeviceMemory::InArena(uintptr_t address) const { return arena_->Contains(address, 0); }

void HostDeviceMemory::MarkWritten(uintptr_t address, size_t length, uint64_t device_writer) {
  if (length == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  MarkWrittenLocked(address, length, device_writer);
}

void HostDeviceMemory::MarkWrittenLocked(uintptr_t address, size_t length, uint64_t device_writer) {
  const uint64_t epoch = ++epoch_;
  const uintptr_t base = arena_->base();
  const uintptr_t first = base + (address - base) / kChunkBytes * kChunkBytes;
  for (uintptr_t c = first; c < address + length; c += kChunkBytes) {
    Written& w = written_[c];
    w.any = epoch;
    if (device_writer == 0) {
      w.host = epoch;
      continue;
    }
    auto it = std::find_if(w.by_writer.begin(), w.by_writer.end(),
                           [&](const auto& e) { return e.first == device_writer; });
    if (it == w.by_writer.end()) {
      w.by_writer.emplace_back(device_writer, epoch);
    } else {
      it->second = epoch;
    }
  }
}

void HostDeviceMemory::MarkManagedWritten() {
  std::vector<std::pair<uintptr_t, size_t>> managed;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    managed.assign(managed_.begin(), managed_.end());
  }
  for (const auto& [address, size] : managed) MarkWritten(address, size);
}

uint64_t HostDeviceMemory::epoch() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return epoch_;
}

std::vector<std::pair<uintptr_t, uint64_t>> HostDeviceMemory::ChunksWrittenSince(
    uint64_t since, uint64_t except_writer) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<uintptr_t, uint64_t>> chunks;
  if (since >= epoch_) return chunks;
  for (const auto& [chunk, w] : written_) {
    bool by_others = except_writer == 0 ? w.any > since : w.host > since;
    for (const auto& [writer, epoch] : w.by_writer) {
      if (by_others) break;
      by_others = writer != except_writer && epoch > since;
    }
    if (by_others) chunks.emplace_back(chunk, w.any);
  }
  return chunks;
}

std::vector<uintptr_t> HostDeviceMemory::TakeWrittenChunks() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<uintptr_t> chunks;
  for (const auto& [chunk, w] : written_) {
    if (w.any > taken_epoch_) chunks.push_back(chunk);
  }
  taken_epoch_ = epoch_;
  return chunks;
}

std::vector<std::pair<uintptr_t, size_t>> HostDeviceMemory::Allocations(int device) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<uintptr_t, size_t>> out;
  out.reserve(allocator_.live().size());
  const auto peers = peers_.find(device);
  for (const auto& [address, a] : allocator_.live()) {
    if (device != kAllDevices) {
      const auto owner = owners_.find(address);
      const int o = owner == owners_.end() ? 0 : owner->second;
      if (o != device &&
          (peers == peers_.end() ||
           std::find(peers->second.begin(), peers->second.end(), o) == peers->second.end())) {
        continue;
      }
    }
    out.emplace_back(address, a.size);
  }
  return out;
}

int HostDeviceMemory::OwnerOf(uintptr_t address) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const memory::DeviceAllocator::Allocation* a = allocator_.Find(address, 1);
  if (a == nullptr) return -1;
  auto it = owners_.upper_bound(address);
  return it == owners_.begin() ? -1 : std::prev(it)->second;
}

bool HostDeviceMemory::SetPeerAccess(int device, int peer, bool enabled) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<int>& peers = peers_[device];
  auto it = std::find(peers.begin(), peers.end(), peer);
  if ((it != peers.end()) == enabled) return false;
  if (enabled) {
    peers.push_back(peer);
  } else {
    peers.erase(it);
  }
  ++allocation_generation_;  // what the device's launches ship changed
  return true;
}

uint64_t HostDeviceMemory::allocation_generation() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return allocation_generation_;
}

size_t HostDeviceMemory::bytes_in_use() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return allocator_.bytes_in_use();
}

}  // namespace tessera::optix7
