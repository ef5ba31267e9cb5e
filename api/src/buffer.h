// A buffer: description (type bits and flags), format, size, and the host copy of its contents.
// The host copy is authoritative for INPUT data; devices send OUTPUT data back into it. Host
// writes are tracked as changed byte ranges so that a launch ships only chunks whose content
// hash a device does not already have.
#ifndef TESSERA_API_SRC_BUFFER_H_
#define TESSERA_API_SRC_BUFFER_H_

#include <array>
#include <cstdint>
#include <map>
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
  // Whether host contents go to devices: INPUT and INPUT_OUTPUT buffers, OUTPUT buffers that
  // built-in triangles take vertices, indices or material indices from (an animated mesh a launch
  // computed): each device builds its acceleration from the merged contents, not its own writes;
  // and OUTPUT buffers with a device pointer, whose contents are the device's copy (what the
  // application wrote there before the launch is what programs see and what they leave alone).
  bool ships_content() const { return is_input() || !views_.empty() || FeedsTriangles(); }
  bool FeedsTriangles() const;
  // The name the application knows the buffer by: the first variable bound to it (on the
  // context first), empty when none is.
  std::string VariableName() const;
  // Describe() with that name, "buffer #4 ('accum')", for messages about a launch.
  std::string DescribeNamed() const;
  // Whether devices send contents back: OUTPUT and INPUT_OUTPUT buffers, unless GPU_LOCAL.
  bool gathers_content() const { return is_output() && !gpu_local(); }
  // GPU_LOCAL with a device pointer for device `ordinal`: that device sends its writes back too,
  // into its view (CopyToDeviceView), never into the host contents.
  bool returns_device_writes(int ordinal) const {
    return gpu_local() && views_.find(ordinal) != views_.end();
  }
  // Bytes device `ordinal` wrote, into its view; dropped when it has none (with a pointer for one
  // device, the others' writes stay on them). The caller checked the range against byte_size().
  void CopyToDeviceView(int ordinal, uint64_t offset, absl::string_view bytes);

  RTformat format() const { return format_; }
  // `format` is an RTformat as a C caller passed it: any int, checked here before it is one.
  absl::Status SetFormat(int format);
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
  // Every mip level's bytes, level 0 first.
  uint64_t byte_size() const { return data_.size(); }

  // ---- Mip levels (OptiX 3.9). A layered or cube map buffer's depth counts layers or faces.
  bool keeps_depth() const { return (desc_ & (RT_BUFFER_LAYERED | RT_BUFFER_CUBEMAP)) != 0; }
  unsigned mip_levels() const { return mip_levels_; }
  // Reallocates (contents zeroed, as a resize).
  absl::Status SetMipLevelCount(unsigned levels);
  // Width, height and depth of `level` (< mip_levels()); unused dimensions 1.
  std::array<uint64_t, 3> LevelDims(unsigned level) const;
  uint64_t LevelByteOffset(unsigned level) const;
  uint64_t LevelBytes(unsigned level) const;

  bool mapped() const { return mapped_levels_ != 0; }
  // rtBufferGetId: programs can now reach the buffer by id, bound to a variable or not.
  void NoteIdTaken() { id_taken_ = true; }
  bool id_taken() const { return id_taken_; }
  absl::StatusOr<void*> Map(unsigned level = 0);
  absl::Status Unmap(unsigned level = 0);
  // Treat the whole buffer as changed by the host (rtBufferMarkDirty).
  void MarkDirty();

  const unsigned char* bytes() const { return data_.data(); }
  // Bytes a device wrote, in two steps so that a large gather copies on several threads:
  // NoteDeviceWrite records that [offset, offset + size) changed (one thread at a time), and
  // CopyDeviceBytes puts the bytes into the host contents and the views of an INPUT_OUTPUT buffer
  // (threads at once, on disjoint ranges). Both take ranges the caller checked against
  // byte_size().
  void NoteDeviceWrite(uint64_t offset, uint64_t size);
  void CopyDeviceBytes(uint64_t offset, absl::string_view bytes);

  // Content hash of every chunk, recomputed only where the contents changed.
  const std::vector<uint64_t>& ChunkHashes();
  // Bumped whenever the host may have written the contents (map, resize, mark dirty).
  uint64_t host_write_epoch() const { return host_write_epoch_; }

  // ---- Device pointers (OptiX guide ch. 7, "Interoperability with CUDA"): a host-side view of
  // one device's copy, by device ordinal. A device's copy lives in its worker process, so the
  // view is host memory that stands for it: before a launch its contents become that device's
  // copy, after a launch it shows what devices wrote to gathered buffers (OUTPUT: the merged
  // contents; INPUT_OUTPUT: the elements devices wrote, its own data elsewhere). A resize drops
  // views.
  bool for_cuda() const { return for_cuda_; }
  void set_for_cuda() { for_cuda_ = true; }
  // The view for device `ordinal`, created from the host contents if there is none yet.
  absl::StatusOr<void*> GetDevicePointer(int ordinal);
  // Makes application memory of byte_size() bytes the view for device `ordinal`.
  absl::Status SetDevicePointer(int ordinal, void* pointer);
  size_t device_pointer_count() const { return views_.size(); }
  // Before a launch on devices `ordinals`: pointers for more than one but fewer than all of them
  // are an error (as in OptiX). A device with a pointer gets its own view. With one pointer, the
  // view is also copied into the host contents, which reach the other devices: every launch, or
  // with COPY_ON_DIRTY only after the pointer was taken or set and after rtBufferMarkDirty.
  absl::Status SyncDevicePointersBeforeLaunch(const std::vector<int>& ordinals);
  // After devices took the launch's state: what SyncDevicePointersBeforeLaunch copied counts as
  // copied (COPY_ON_DIRTY pointers are clean again unless marked dirty since).
  void DevicePointersShipped();
  // The bytes device `ordinal` gets when it has a view of an INPUT buffer; null otherwise.
  const unsigned char* PerDeviceBytes(int ordinal) const;
  // After a launch: views of OUTPUT buffers show the merged contents. (Views of INPUT_OUTPUT
  // buffers take each element a device wrote as it arrives, CopyDeviceBytes, and keep the others.)
  void SyncDevicePointersAfterLaunch();

  void VisitEdges(EdgeVisitor visit) const override {}

 private:
  struct View {
    std::vector<unsigned char> owned;  // rtBufferGetDevicePointer
    void* application = nullptr;       // rtBufferSetDevicePointer
    unsigned char* data() {
      return application != nullptr ? static_cast<unsigned char*>(application) : owned.data();
    }
    const unsigned char* data() const {
      return application != nullptr ? static_cast<const unsigned char*>(application) : owned.data();
    }
  };

  // Makes the buffer `dims` elements of `format` (of `user_element_size` bytes for USER), zeroed;
  // on failure (too large, out of memory) nothing changes.
  absl::Status Reallocate(const std::vector<size_t>& dims, RTformat format,
                          size_t user_element_size, unsigned mip_levels);
  absl::Status CheckLevel(unsigned level) const;
  void HostWrote(uint64_t begin, uint64_t end);
  // A device got its first pointer (taken or set).
  void ViewAdded();

  const unsigned desc_;
  RTformat format_ = RT_FORMAT_UNKNOWN;
  size_t user_element_size_ = 0;
  std::vector<size_t> dims_;  // empty until a size is set
  std::vector<unsigned char> data_;
  unsigned mip_levels_ = 1;
  uint32_t mapped_levels_ = 0;  // bit i: level i is mapped
  bool id_taken_ = false;
  ByteRanges changed_;  // not yet reflected in chunk_hashes_
  std::vector<uint64_t> chunk_hashes_;
  uint64_t host_write_epoch_ = 1;
  bool for_cuda_ = false;
  std::map<int, View> views_;
  // Counts pointers taken or set, host writes through a map and rtBufferMarkDirty calls; with
  // COPY_ON_DIRTY one pointer is copied to the other devices while it differs from the count
  // that devices took (views_shipped_, as of the last launch whose state updates went out).
  uint64_t views_dirty_ = 0;
  uint64_t views_pending_ = 0;  // the count the running launch's SyncDevicePointersBeforeLaunch saw
  uint64_t views_shipped_ = 0;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_BUFFER_H_
