#include "host_device_memory.h"

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

absl::StatusOr<uintptr_t> HostDeviceMemory::Allocate(size_t bytes, bool managed) {
  std::lock_guard<std::mutex> lock(mutex_);
  absl::StatusOr<uintptr_t> address = allocator_.Allocate(bytes);
  if (!address.ok()) return address;
  ++allocation_generation_;
  if (managed) managed_[*address] = bytes;
  if (absl::Status s = arena_->Commit(*address, bytes); !s.ok()) {
    (void)allocator_.Free(*address);
    return s;
  }
  return address;
}

absl::Status HostDeviceMemory::Free(uintptr_t address) {
  std::lock_guard<std::mutex> lock(mutex_);
  absl::StatusOr<memory::DeviceAllocator::Freed> freed = allocator_.Free(address);
  if (!freed.ok()) return freed.status();
  ++allocation_generation_;
  managed_.erase(address);
  if (freed->release_end > freed->release_begin) {
    return arena_->Release(freed->release_begin, freed->release_end - freed->release_begin);
  }
  return absl::OkStatus();
}

bool HostDeviceMemory::IsAllocated(uintptr_t address, size_t length) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return allocator_.Find(address, length) != nullptr;
}

bool HostDeviceMemory::InArena(uintptr_t address) const { return arena_->Contains(address, 0); }

void HostDeviceMemory::MarkWritten(uintptr_t address, size_t length, bool by_device) {
  if (length == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const uint64_t epoch = ++epoch_;
  const uintptr_t base = arena_->base();
  const uintptr_t first = base + (address - base) / kChunkBytes * kChunkBytes;
  for (uintptr_t c = first; c < address + length; c += kChunkBytes) {
    Written& w = written_[c];
    w.any = epoch;
    if (!by_device) w.host = epoch;
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
    uint64_t since, bool host_only) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<uintptr_t, uint64_t>> chunks;
  if (since >= epoch_) return chunks;
  for (const auto& [chunk, w] : written_) {
    if ((host_only ? w.host : w.any) > since) chunks.emplace_back(chunk, w.any);
  }
  return chunks;
}

std::vector<uintptr_t> HostDeviceMemory::TakeWrittenChunks() {
  std::vector<uintptr_t> chunks;
  for (const auto& [chunk, epoch] : ChunksWrittenSince(taken_epoch_)) chunks.push_back(chunk);
  std::lock_guard<std::mutex> lock(mutex_);
  taken_epoch_ = epoch_;
  return chunks;
}

std::vector<std::pair<uintptr_t, size_t>> HostDeviceMemory::Allocations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<uintptr_t, size_t>> out;
  out.reserve(allocator_.live().size());
  for (const auto& [address, a] : allocator_.live()) out.emplace_back(address, a.size);
  return out;
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
