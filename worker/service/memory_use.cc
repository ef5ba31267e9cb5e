#include "memory_use.h"

#include <unistd.h>

#include <cstdio>
#include <limits>

namespace tessera::worker {
namespace {

// element_size × dims, saturating: a host's claim, not yet a checked allocation.
uint64_t BufferSize(const v1::Buffer& b) {
  if (b.dims_size() == 0) return 0;  // unsized
  uint64_t bytes = b.element_size();
  for (uint64_t d : b.dims()) {
    if (d != 0 && bytes > std::numeric_limits<uint64_t>::max() / d) {
      return std::numeric_limits<uint64_t>::max();
    }
    bytes *= d;
  }
  return bytes;
}

uint64_t SaturatingAdd(uint64_t a, uint64_t b) {
  return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max()
                                                      : a + b;
}

}  // namespace

void BufferBytes::Apply(const v1::StateDelta& delta) {
  if (delta.sequence() == 1) bytes_.clear();
  for (uint64_t id : delta.removed()) bytes_.erase(id);
  for (const v1::Object& o : delta.objects()) {
    if (o.kind_case() == v1::Object::kBuffer) bytes_[o.buffer().id()] = BufferSize(o.buffer());
  }
  total_ = 0;
  for (const auto& [id, bytes] : bytes_) total_ = SaturatingAdd(total_, bytes);
}

uint64_t ResidentBytes() {
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return 0;
  unsigned long long size = 0, resident = 0;
  const int read = std::fscanf(statm, "%llu %llu", &size, &resident);
  std::fclose(statm);
  const long page = sysconf(_SC_PAGESIZE);
  if (read != 2 || page <= 0) return 0;
  return resident * static_cast<uint64_t>(page);
}

}  // namespace tessera::worker
