// A set of half-open byte ranges, kept sorted and merged: what the host may have changed in a
// buffer since its chunk hashes were last computed.
#ifndef TESSERA_API_SRC_BYTE_RANGES_H_
#define TESSERA_API_SRC_BYTE_RANGES_H_

#include <cstdint>
#include <utility>
#include <vector>

namespace tessera::api {

class ByteRanges {
 public:
  void Add(uint64_t begin, uint64_t end);
  void Clear() { ranges_.clear(); }
  bool empty() const { return ranges_.empty(); }
  bool Overlaps(uint64_t begin, uint64_t end) const;
  const std::vector<std::pair<uint64_t, uint64_t>>& ranges() const { return ranges_; }

 private:
  std::vector<std::pair<uint64_t, uint64_t>> ranges_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_BYTE_RANGES_H_
