#include "byte_ranges.h"

#include <algorithm>

namespace tessera::api {

void ByteRanges::Add(uint64_t begin, uint64_t end) {
  if (begin >= end) return;
  // Ranges touching or overlapping [begin, end) merge into it.
  auto first = std::lower_bound(ranges_.begin(), ranges_.end(), begin,
                                [](const auto& r, uint64_t b) { return r.second < b; });
  auto last = first;
  while (last != ranges_.end() && last->first <= end) {
    begin = std::min(begin, last->first);
    end = std::max(end, last->second);
    ++last;
  }
  first = ranges_.erase(first, last);
  ranges_.insert(first, {begin, end});
}

bool ByteRanges::Overlaps(uint64_t begin, uint64_t end) const {
  auto it = std::lower_bound(ranges_.begin(), ranges_.end(), begin,
                             [](const auto& r, uint64_t b) { return r.second <= b; });
  return it != ranges_.end() && it->first < end;
}

}  // namespace tessera::api
