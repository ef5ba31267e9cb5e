#include "buffer.h"

#include <algorithm>
#include <cstring>
#include <new>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "buffer_format.h"
#include "context.h"
#include "dirty.h"
#include "hash.h"
#include "status.h"
#include "tessera/detail/mip_levels.h"
#include "tessera/detail/texture_view.h"
#include "tessera/scheduler/device.h"
#include "variable.h"
#include "variable_scope.h"

namespace tessera::api {
namespace {

// Larger than any machine Tessera runs on; keeps size arithmetic far from overflow.
constexpr uint64_t kMaxBufferBytes = uint64_t{1} << 46;

absl::Status MappedError() { return RtError(RT_ERROR_ALREADY_MAPPED, "buffer is mapped"); }

}  // namespace

absl::Status Buffer::CheckDesc(unsigned desc) {
  constexpr unsigned kTypeBits = RT_BUFFER_INPUT | RT_BUFFER_OUTPUT;
  constexpr unsigned kFlagBits =
      RT_BUFFER_GPU_LOCAL | RT_BUFFER_COPY_ON_DIRTY | RT_BUFFER_LAYERED | RT_BUFFER_CUBEMAP;
  if ((desc & ~(kTypeBits | kFlagBits)) != 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("buffer description 0x", absl::Hex(desc),
                                " has unknown bits (expected RTbuffertype | RTbufferflag)"));
  }
  if ((desc & kTypeBits) == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   "buffer description needs RT_BUFFER_INPUT, RT_BUFFER_OUTPUT or "
                   "RT_BUFFER_INPUT_OUTPUT");
  }
  if ((desc & RT_BUFFER_GPU_LOCAL) != 0 && (desc & kTypeBits) != RT_BUFFER_INPUT_OUTPUT) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   "RT_BUFFER_GPU_LOCAL can only be combined with RT_BUFFER_INPUT_OUTPUT");
  }
  return absl::OkStatus();
}

Buffer::Buffer(Context* context, uint64_t id, unsigned desc)
    : Object(Kind::kBuffer, context, id), desc_(desc) {
  Touch();
}

size_t Buffer::element_size() const {
  return format_ == RT_FORMAT_USER ? user_element_size_ : FormatElementSize(format_);
}

absl::Status Buffer::SetFormat(int format) {
  if (!IsValidFormat(format) || format == RT_FORMAT_UNKNOWN) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("0x", absl::Hex(format), " is not a format"));
  }
  if (format == RT_FORMAT_PROGRAM_ID && is_output()) {
    // As OptiX: programs may not make up program ids.
    return RtError(RT_ERROR_INVALID_VALUE,
                   "RT_FORMAT_PROGRAM_ID needs an RT_BUFFER_INPUT buffer (not OUTPUT or "
                   "INPUT_OUTPUT)");
  }
  if (mapped()) return MappedError();
  return Reallocate(dims_, static_cast<RTformat>(format), user_element_size_, mip_levels_);
}

absl::Status Buffer::SetElementSize(size_t size) {
  if (format_ != RT_FORMAT_USER) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("element size can only be set for RT_FORMAT_USER, format is ",
                                FormatName(format_)));
  }
  if (size == 0) return RtError(RT_ERROR_INVALID_VALUE, "element size must not be 0");
  if (size > kMaxElementBytes) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("element size ", size, " exceeds ", kMaxElementBytes,
                                " bytes, the largest element devices accept"));
  }
  if (mapped()) return MappedError();
  return Reallocate(dims_, format_, size, mip_levels_);
}

size_t Buffer::dim(unsigned axis) const {
  if (axis < dims_.size()) return dims_[axis];
  return dims_.empty() && axis == 0 ? 0 : 1;
}

absl::Status Buffer::SetSize(const std::vector<size_t>& dims) {
  if (dims.empty() || dims.size() > 3) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("dimensionality ", dims.size(), " is not 1, 2 or 3"));
  }
  if (mapped()) return MappedError();
  if (mip_levels_ > 1) {
    std::array<uint64_t, 3> d{dims[0], dims.size() > 1 ? dims[1] : 1,
                              dims.size() > 2 ? dims[2] : 1};
    const unsigned most =
        detail::MaxMipLevels(d, static_cast<unsigned>(dims.size()), keeps_depth());
    if (mip_levels_ > most) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("a ", absl::StrJoin(dims, "x"), " buffer has at most ", most,
                                  " mip levels, but its mip level count is ", mip_levels_));
    }
  }
  return Reallocate(dims, format_, user_element_size_, mip_levels_);
}

absl::Status Buffer::SetMipLevelCount(unsigned levels) {
  if (levels < 1 || levels > TESSERA_TEXTURE_MAX_LEVELS) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("mip level count ", levels, " is not between 1 and ",
                                TESSERA_TEXTURE_MAX_LEVELS));
  }
  if (sized()) {
    const unsigned most = detail::MaxMipLevels(LevelDims(0), dimensionality(), keeps_depth());
    if (levels > most) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("a ", absl::StrJoin(dims_, "x"), " buffer has at most ", most,
                                  " mip levels, not ", levels));
    }
  }
  if (mapped()) return MappedError();
  return Reallocate(dims_, format_, user_element_size_, levels);
}

std::array<uint64_t, 3> Buffer::LevelDims(unsigned level) const {
  const std::array<uint64_t, 3> d{dim(0), dim(1), dim(2)};
  return detail::MipLevelDims(d, dimensionality(), keeps_depth(), level);
}

uint64_t Buffer::LevelByteOffset(unsigned level) const {
  const std::array<uint64_t, 3> d{dim(0), dim(1), dim(2)};
  return detail::MipLevelOffset(d, dimensionality(), keeps_depth(), level) * element_size();
}

uint64_t Buffer::LevelBytes(unsigned level) const {
  const std::array<uint64_t, 3> d{dim(0), dim(1), dim(2)};
  return detail::MipLevelElements(d, dimensionality(), keeps_depth(), level) * element_size();
}

absl::Status Buffer::CheckLevel(unsigned level) const {
  if (level >= mip_levels_) {
    return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("mip level ", level, " is past the ",
                                                        mip_levels_, " levels the buffer has"));
  }
  return absl::OkStatus();
}

absl::Status Buffer::Reallocate(const std::vector<size_t>& dims, RTformat format,
                                size_t user_element_size, unsigned mip_levels) {
  // Elements times element size, checked step by step so that no product can wrap around.
  const uint64_t element = format == RT_FORMAT_USER ? user_element_size : FormatElementSize(format);
  uint64_t bytes = dims.empty() ? 0 : std::max<uint64_t>(element, 1);
  std::string size_text = absl::StrCat(element, "-byte elements");
  for (size_t d : dims) {
    if (d != 0 && bytes > kMaxBufferBytes / d) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("buffer size is too large: ", absl::StrJoin(dims, "x"), " of ",
                                  size_text, " exceed ", kMaxBufferBytes, " bytes"));
    }
    bytes *= d;
  }
  if (element == 0) bytes = 0;  // no format or element size yet: nothing to hold
  if (mip_levels > 1 && bytes != 0) {
    // Levels past 0 add at most as much again as level 0 (a 1D chain halves each time).
    const std::array<uint64_t, 3> d{dims[0], dims.size() > 1 ? dims[1] : 1,
                                    dims.size() > 2 ? dims[2] : 1};
    bytes =
        detail::MipLevelOffset(d, static_cast<unsigned>(dims.size()), keeps_depth(), mip_levels) *
        element;
  }
  // Allocate before changing anything: a buffer that cannot grow keeps its size and contents.
  // Contents are zero-initialised on every resize, as documented in COMPATIBILITY.md.
  std::vector<unsigned char> data;
  try {
    data.assign(bytes, 0);
  } catch (const std::bad_alloc&) {
    return RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED,
                   absl::StrCat("cannot allocate ", bytes, " bytes for ", absl::StrJoin(dims, "x"),
                                " ", size_text, "; the buffer keeps its previous size"));
  }
  dims_ = dims;
  format_ = format;
  user_element_size_ = user_element_size;
  mip_levels_ = mip_levels;
  data_.swap(data);
  chunk_hashes_.clear();
  changed_.Clear();
  changed_.Add(0, bytes);
  ++host_write_epoch_;
  views_.clear();  // device pointers name memory of the old size
  Touch();
  NotifyStructureChanged(this);
  return absl::OkStatus();
}

absl::StatusOr<void*> Buffer::Map(unsigned level) {
  TS_RETURN_IF_ERROR(CheckLevel(level));
  if ((mapped_levels_ & (1u << level)) != 0) {
    return RtError(RT_ERROR_ALREADY_MAPPED,
                   level == 0 ? std::string("buffer is already mapped")
                              : absl::StrCat("mip level ", level, " is already mapped"));
  }
  if (format_ == RT_FORMAT_UNKNOWN) {
    return RtError(RT_ERROR_INVALID_VALUE, "buffer has no format; call rtBufferSetFormat first");
  }
  if (element_size() == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   "RT_FORMAT_USER buffer has no element size; call rtBufferSetElementSize");
  }
  const bool first = !mapped();
  mapped_levels_ |= 1u << level;
  // Only data that travels to devices (ships_content) counts a map as a host write.
  if (ships_content()) {
    // With one device pointer every device runs on the pointer's contents: the map shows them
    // (Unmap hands what the host wrote back to the pointers).
    if (first && views_.size() == 1 && !data_.empty()) {
      std::memcpy(data_.data(), views_.begin()->second.data(), data_.size());
    }
    const uint64_t begin = LevelByteOffset(level);
    HostWrote(begin, begin + LevelBytes(level));
  }
  static unsigned char empty_buffer_storage[16];
  return data_.empty() ? static_cast<void*>(empty_buffer_storage)
                       : data_.data() + LevelByteOffset(level);
}

absl::Status Buffer::Unmap(unsigned level) {
  TS_RETURN_IF_ERROR(CheckLevel(level));
  if ((mapped_levels_ & (1u << level)) == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   level == 0 ? std::string("buffer is not mapped")
                              : absl::StrCat("mip level ", level, " is not mapped"));
  }
  mapped_levels_ &= ~(1u << level);
  // A device pointer takes the contents when the last mapped level is unmapped.
  if (mapped()) return absl::OkStatus();
  // With one device pointer, every device runs on the pointer's contents before a launch: the
  // pointer takes what the host wrote (and with COPY_ON_DIRTY the write is news for every
  // device). With a pointer per device each runs on its own data; the host copy does not replace
  // them (docs/devices.md).
  if (ships_content() && !data_.empty() && views_.size() == 1) {
    std::memcpy(views_.begin()->second.data(), data_.data(), data_.size());
    ++views_dirty_;
  }
  return absl::OkStatus();
}

void Buffer::MarkDirty() {
  HostWrote(0, data_.size());
  ++views_dirty_;
}

absl::StatusOr<void*> Buffer::GetDevicePointer(int ordinal) {
  if (!sized() || element_size() == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(Describe(), " needs a format and a size before a device pointer"));
  }
  auto [it, inserted] = views_.try_emplace(ordinal);
  if (inserted) it->second.owned = data_;
  ++views_dirty_;
  if (inserted) ViewAdded();
  static unsigned char empty_buffer_storage[16];
  return data_.empty() ? static_cast<void*>(empty_buffer_storage)
                       : static_cast<void*>(it->second.data());
}

absl::Status Buffer::SetDevicePointer(int ordinal, void* pointer) {
  if (!sized() || element_size() == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(Describe(), " needs a format and a size before a device pointer"));
  }
  const bool added = views_.find(ordinal) == views_.end();
  View& view = views_[ordinal];
  view.owned.clear();
  view.application = pointer;
  ++views_dirty_;
  if (added) ViewAdded();
  return absl::OkStatus();
}

void Buffer::ViewAdded() {
  // A device learns from the buffer's description that its writes to it travel back
  // (returns_device_writes); a device takes a description as a new buffer and is sent every chunk.
  if (gpu_local()) Touch();
}

void Buffer::CopyToDeviceView(int ordinal, uint64_t offset, absl::string_view bytes) {
  auto it = views_.find(ordinal);
  if (it == views_.end() || bytes.empty()) return;
  std::memcpy(it->second.data() + offset, bytes.data(), bytes.size());
}

std::string Buffer::VariableName() const {
  if (context() == nullptr) return "";
  auto name_in = [&](Object* owner) -> std::string {
    VariableScope* scope = owner->scope();
    if (scope == nullptr) return "";
    for (const Variable* v : scope->variables()) {
      if (v->object() == this) return v->name();
    }
    return "";
  };
  std::string name = name_in(context());
  for (const auto& [id, object] : context()->objects()) {
    if (!name.empty()) break;
    name = name_in(object);
  }
  return name;
}

std::string Buffer::DescribeNamed() const {
  const std::string name = VariableName();
  return name.empty() ? Describe() : absl::StrCat(Describe(), " ('", name, "')");
}

absl::Status Buffer::SyncDevicePointersBeforeLaunch(const std::vector<int>& ordinals) {
  // Still dirty until devices took the launch's state (DevicePointersShipped): a launch that
  // fails before that (another buffer's pointers, a device rejecting its update) copies again.
  views_pending_ = views_dirty_;
  if (views_.empty()) {
    if (for_cuda_ && !data_.empty()) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(DescribeNamed(),
                                  " was created with rtBufferCreateForCUDA and has no "
                                  "device pointer; call rtBufferSetDevicePointer"));
    }
    return absl::OkStatus();
  }
  for (const auto& [ordinal, view] : views_) {
    if (std::find(ordinals.begin(), ordinals.end(), ordinal) == ordinals.end()) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(DescribeNamed(), " has a device pointer for device ", ordinal,
                                  ", which the context does not run on"));
    }
  }
  const size_t k = views_.size(), n = ordinals.size();
  if (k > 1 && k < n) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat(DescribeNamed(), " has device pointers for ", k, " of the context's ", n,
                     " devices; give one device a pointer, or every device"));
  }
  if (!ships_content()) return absl::OkStatus();
  // A device with a pointer runs on its own view (PerDeviceBytes), as a GPU on its own memory.
  if (k == 1 && ((desc_ & RT_BUFFER_COPY_ON_DIRTY) == 0 || views_dirty_ != views_shipped_)) {
    // One device's view reaches every device through the host contents. Devices' GPU_LOCAL
    // copies diverge from the host's as programs write them, so those get the view again even
    // when the host contents already equal it.
    const unsigned char* source = views_.begin()->second.data();
    const bool differs = !data_.empty() && std::memcmp(source, data_.data(), data_.size()) != 0;
    if (differs) std::memcpy(data_.data(), source, data_.size());
    if (!data_.empty() && (differs || gpu_local())) HostWrote(0, data_.size());
  }
  return absl::OkStatus();
}

void Buffer::DevicePointersShipped() { views_shipped_ = views_pending_; }

const unsigned char* Buffer::PerDeviceBytes(int ordinal) const {
  if (!ships_content()) return nullptr;
  auto it = views_.find(ordinal);
  return it == views_.end() ? nullptr : it->second.data();
}

void Buffer::SyncDevicePointersAfterLaunch() {
  // INPUT_OUTPUT views got the devices' writes as they arrived (CopyDeviceBytes); copying the host
  // contents over them would undo what the application wrote there and no device overwrote (a
  // COPY_ON_DIRTY view the host contents did not take, or every device's own data).
  if (!gathers_content() || ships_content() || data_.empty()) return;
  for (auto& [ordinal, view] : views_) std::memcpy(view.data(), data_.data(), data_.size());
}

bool Buffer::FeedsTriangles() const {
  for (const auto& [parent, count] : parents()) {
    if (parent->alive() && parent->kind() == Kind::kGeometryTriangles) return true;
  }
  return false;
}

void Buffer::HostWrote(uint64_t begin, uint64_t end) {
  changed_.Add(begin, end);
  ++host_write_epoch_;
  NotifyStructureChanged(this);
}

void Buffer::NoteDeviceWrite(uint64_t offset, uint64_t size) {
  if (size == 0) return;
  // Device writes change what other devices must receive, not what the host wrote. Recorded by
  // whole chunks, the unit that is rehashed: a multi-device gather writes one region per run of
  // changed bytes (up to one per few bytes of a buffer), and a set of that many ranges made
  // every Add linear (minutes for one 640x480 float4 launch on two devices).
  const uint64_t begin = offset / kChunkBytes * kChunkBytes;
  const uint64_t end = std::min<uint64_t>(
      data_.size(), (offset + size + kChunkBytes - 1) / kChunkBytes * kChunkBytes);
  changed_.Add(begin, end);
}

void Buffer::CopyDeviceBytes(uint64_t offset, absl::string_view bytes) {
  if (bytes.empty()) return;
  std::memcpy(data_.data() + offset, bytes.data(), bytes.size());
  // Device pointers of an INPUT_OUTPUT buffer show what devices wrote, and keep the rest.
  if (ships_content()) {
    for (auto& [ordinal, view] : views_) {
      std::memcpy(view.data() + offset, bytes.data(), bytes.size());
    }
  }
}

const std::vector<uint64_t>& Buffer::ChunkHashes() {
  uint64_t size = data_.size();
  size_t chunks = static_cast<size_t>((size + kChunkBytes - 1) / kChunkBytes);
  if (chunk_hashes_.size() != chunks) {
    chunk_hashes_.assign(chunks, 0);
    changed_.Add(0, size);
  }
  if (changed_.empty()) return chunk_hashes_;
  for (size_t i = 0; i < chunks; ++i) {
    uint64_t begin = i * kChunkBytes;
    uint64_t end = std::min(size, begin + kChunkBytes);
    if (chunk_hashes_[i] == 0 || changed_.Overlaps(begin, end)) {
      chunk_hashes_[i] = ChunkHash(data_.data() + begin, end - begin);
    }
  }
  changed_.Clear();
  return chunk_hashes_;
}

}  // namespace tessera::api
