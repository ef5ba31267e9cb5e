#include "device_allocator.h"

#include <algorithm>
#include <iterator>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace tessera::memory {

DeviceAllocator::DeviceAllocator(uintptr_t base, size_t size, size_t page_size)
    : base_(base), size_(size / kAlignment * kAlignment), page_(page_size) {
  if (size_ > 0) free_[base_] = size_;
}

absl::StatusOr<uintptr_t> DeviceAllocator::Allocate(size_t bytes) {
  if (bytes == 0 || bytes > size_) {
    return absl::ResourceExhaustedError(
        absl::StrCat("cannot allocate ", bytes, " bytes of device memory (at most ", size_,
                     " bytes in all, ", LargestFree(), " free in one range)"));
  }
  const size_t need = Rounded(bytes);
  // First fit by address: the lowest addresses fill first, whatever the order of earlier frees.
  for (auto it = free_.begin(); it != free_.end(); ++it) {
    if (it->second < need) continue;
    const uintptr_t address = it->first;
    const size_t left = it->second - need;
    free_.erase(it);
    if (left > 0) free_[address + need] = left;
    live_[address] = Allocation{address, bytes};
    bytes_in_use_ += need;
    return address;
  }
  return absl::ResourceExhaustedError(
      absl::StrCat("cannot allocate ", bytes, " bytes of device memory: ", bytes_in_use_,
                   " bytes are in use and the largest free range holds ", LargestFree()));
}

absl::StatusOr<DeviceAllocator::Freed> DeviceAllocator::Free(uintptr_t address) {
  auto it = live_.find(address);
  if (it == live_.end()) {
    const Allocation* inside = Find(address, 0);
    return absl::NotFoundError(
        inside != nullptr
            ? absl::StrFormat("0x%x is inside the allocation at 0x%x, not its start", address,
                              inside->address)
            : absl::StrFormat("0x%x is not an allocation of device memory (never allocated, or "
                              "freed already)",
                              address));
  }
  Freed freed;
  freed.allocation = it->second;
  const size_t span = Rounded(it->second.size);
  bytes_in_use_ -= span;
  live_.erase(it);

  // Back into the free ranges, merged with free neighbours.
  uintptr_t begin = address;
  size_t length = span;
  auto next = free_.lower_bound(address);
  if (next != free_.begin()) {
    auto prev = std::prev(next);
    if (prev->first + prev->second == begin) {
      begin = prev->first;
      length += prev->second;
      free_.erase(prev);
    }
  }
  if (next != free_.end() && next->first == address + span) {
    length += next->second;
    free_.erase(next);
  }
  free_[begin] = length;

  // Pages of the freed range that no live allocation touches: the whole free range around it,
  // cut to pages.
  const uintptr_t first = (begin + page_ - 1) / page_ * page_;
  const uintptr_t end = (begin + length) / page_ * page_;
  const uintptr_t lo = std::max(first, address / page_ * page_);
  const uintptr_t hi = std::min(end, (address + span + page_ - 1) / page_ * page_);
  if (hi > lo) {
    freed.release_begin = lo;
    freed.release_end = hi;
  }
  return freed;
}

const DeviceAllocator::Allocation* DeviceAllocator::Find(uintptr_t address, size_t length) const {
  auto it = live_.upper_bound(address);
  if (it == live_.begin()) return nullptr;
  const Allocation& a = std::prev(it)->second;
  const size_t offset = address - a.address;
  if (offset > a.size || length > a.size - offset) return nullptr;
  if (length == 0 && offset == a.size) return nullptr;  // one past the end is not inside
  return &a;
}

size_t DeviceAllocator::LargestFree() const {
  size_t largest = 0;
  for (const auto& [address, length] : free_) largest = std::max(largest, length);
  return largest;
}

}  // namespace tessera::memory
