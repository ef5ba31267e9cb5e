// A buffer: description (type bits and flags), format, size, and the host copy of its contents.
// The host copy is authoritative for INPUT data; devices send OUTPUT data back into it. Host
// writes are tracked as changed byte ranges so that a launch ships only chunks whose content
// hash a device does not already have.
#ifndef TESSERA_API_SRC_BUFFER_H_
#define TESSERA_API_SRC_BUFFER_H_

#include <cstdint>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "byte_ranges.h"
#include "object.h"

namespace tessera::api {

// Buffer contents travel in chunks of at most this many bytes, each with its own content hash.
inline constexpr uint64_t kChunkBytes = uint64_t{4} << 20;

class Buffer : public Object {
 public:
  static constexpr Kind kKind = Kind::kBuffer;

  // Checks type bits and flags against the OptiX rules (GPU_LOCAL needs INPUT_OUTPUT).
  static absl::Status CheckDesc(unsigned desc);

  Buffer(Context* context, uint64_t id, unsigned desc);

  unsigned desc() const { return desc_; }
  bool is_input() const { return (desc_ & RT_BUFFER_INPUT) != 0; }
  bool is_output() const { return (desc_ & RT_BUFFER_OUTPUT) != 0; }
  bool gpu_local() const { return (desc_ & RT_BUFFER_GPU_LOCAL) != 0; }
  // Whether host contents go to devices: INPUT and INPUT_OUTPUT buffers.
  bool ships_content() const { return is_input(); }
  // Whether devices send contents back: OUTPUT and INPUT_OUTPUT buffers, unless GPU_LOCAL.
  bool gathers_content() const { return is_output() && !gpu_local(); }

  RTformat format() const { return format_; }
  absl::Status SetFormat(RTformat format);
  // The element size in bytes: from the format, or as set for RT_FORMAT_USER (0 = unset).
  size_t element_size() const;
  absl::Status SetElementSize(size_t size);

  bool sized() const { return !dims_.empty(); }
  unsigned dimensionality() const {
    return dims_.empty() ? 1 : static_cast<unsigned>(dims_.size());
  }
  const std::vector<size_t>& dims() const { return dims_; }
  // Width, height or depth; dimensions the buffer does not have read as 1 (0 when unsized).
  size_t dim(unsigned axis) const;
  absl::Status SetSize(const std::vector<size_t>& dims);
  uint64_t byte_size() const { return data_.size(); }

  bool mapped() const { return mapped_; }
  absl::StatusOr<void*> Map();
  absl::Status Unmap();
  // Treat the whole buffer as changed by the host (rtBufferMarkDirty).
  void MarkDirty();

  const unsigned char* bytes() const { return data_.data(); }
  // Applies bytes a device wrote; out-of-range regions are an error naming the buffer.
  absl::Status WriteRegion(uint64_t offset, absl::string_view bytes);

  // Content hash of every chunk, recomputed only where the contents changed.
  const std::vector<uint64_t>& ChunkHashes();
  // Bumped whenever the host may have written the contents (map, resize, mark dirty).
  uint64_t host_write_epoch() const { return host_write_epoch_; }

  void VisitEdges(EdgeVisitor visit) const override {}

 private:
  void Reallocate();
  void HostWrote(uint64_t begin, uint64_t end);

  const unsigned desc_;
  RTformat format_ = RT_FORMAT_UNKNOWN;
  size_t user_element_size_ = 0;
  std::vector<size_t> dims_;  // empty until a size is set
  std::vector<unsigned char> data_;
  bool mapped_ = false;
  ByteRanges changed_;  // not yet reflected in chunk_hashes_
  std::vector<uint64_t> chunk_hashes_;
  uint64_t host_write_epoch_ = 1;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_BUFFER_H_
