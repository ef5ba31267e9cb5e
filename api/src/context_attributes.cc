// Context attributes (rtContext{Get,Set}Attribute) and exception enables.
#include <climits>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "accuracy_flags.h"
#include "buffer.h"
#include "context.h"
#include "status.h"
#include "system_info.h"

namespace tessera::api {
namespace {

constexpr uint32_t Bit(int code) { return 1u << (code - RT_EXCEPTION_PROGRAM_ID_INVALID); }

constexpr uint32_t kAllExceptionBits =
    Bit(RT_EXCEPTION_PROGRAM_ID_INVALID) | Bit(RT_EXCEPTION_TEXTURE_ID_INVALID) |
    Bit(RT_EXCEPTION_BUFFER_ID_INVALID) | Bit(RT_EXCEPTION_INDEX_OUT_OF_BOUNDS) |
    Bit(RT_EXCEPTION_STACK_OVERFLOW) | Bit(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS) |
    Bit(RT_EXCEPTION_INVALID_RAY) | Bit(RT_EXCEPTION_INTERNAL_ERROR);

// The bit of a specific built-in exception code, 0 for USER/ALL, nullopt-like -1 if unknown.
int64_t ExceptionBit(int exception) {
  switch (exception) {
    case RT_EXCEPTION_PROGRAM_ID_INVALID:
    case RT_EXCEPTION_TEXTURE_ID_INVALID:
    case RT_EXCEPTION_BUFFER_ID_INVALID:
    case RT_EXCEPTION_INDEX_OUT_OF_BOUNDS:
    case RT_EXCEPTION_STACK_OVERFLOW:
    case RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS:
    case RT_EXCEPTION_INVALID_RAY:
    case RT_EXCEPTION_INTERNAL_ERROR:
      return Bit(exception);
    case RT_EXCEPTION_USER:
    case RT_EXCEPTION_ALL:
      return 0;
    default:
      return -1;
  }
}

absl::Status UnknownException(int exception) {
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat("0x", absl::Hex(exception), " is not an RTexception"));
}

absl::Status SizeError(const char* name, RTsize size, size_t expected) {
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat(name, " needs size ", expected, ", got ", size));
}

template <typename T>
absl::Status Put(const char* name, RTsize size, void* out, T value) {
  if (size != sizeof(T)) return SizeError(name, size, sizeof(T));
  std::memcpy(out, &value, sizeof(T));
  return absl::OkStatus();
}

}  // namespace

absl::Status Context::SetExceptionEnabled(int exception, bool enabled) {
  int64_t bit = ExceptionBit(exception);
  if (bit < 0) return UnknownException(exception);
  uint32_t bits = exception == RT_EXCEPTION_ALL ? kAllExceptionBits : static_cast<uint32_t>(bit);
  exception_mask_ = enabled ? (exception_mask_ | bits) : (exception_mask_ & ~bits);
  if (exception == RT_EXCEPTION_USER || exception == RT_EXCEPTION_ALL) user_exceptions_ = enabled;
  Touch();
  return absl::OkStatus();
}

absl::StatusOr<bool> Context::ExceptionEnabled(int exception) const {
  int64_t bit = ExceptionBit(exception);
  if (bit < 0) return UnknownException(exception);
  if (exception == RT_EXCEPTION_USER) return user_exceptions_;
  if (exception == RT_EXCEPTION_ALL) {
    return user_exceptions_ && (exception_mask_ & kAllExceptionBits) == kAllExceptionBits;
  }
  return (exception_mask_ & bit) != 0;
}

absl::Status Context::SetAccuracy(uint32_t flags) {
  if (!KnownAccuracy(flags)) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("accuracy flags 0x", absl::Hex(flags),
                                " hold bits no TESSERA_ACCURACY_* flag has (known: 0x1F)"));
  }
  if (running()) {
    return RtError(RT_ERROR_INVALID_CONTEXT, "cannot change accuracy settings while a launch runs");
  }
  if (flags != accuracy_flags_) {
    accuracy_flags_ = flags;
    Touch();
  }
  return absl::OkStatus();
}

absl::Status Context::SetAttribute(RTcontextattribute attribute, RTsize size, const void* value) {
  switch (attribute) {
    case RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS: {
      if (size != sizeof(int)) return SizeError("RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS", size, 4);
      int threads;
      std::memcpy(&threads, value, sizeof(int));
      if (threads < 1) {
        return RtError(RT_ERROR_INVALID_VALUE,
                       absl::StrCat("CPU thread count must be at least 1, got ", threads));
      }
      num_threads_ = threads;
      num_threads_set_ = true;
      Touch();
      return absl::OkStatus();
    }
    case RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE:
    case RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF:
      return RtError(RT_ERROR_NOT_SUPPORTED,
                     "GPU paging attributes do not apply to CPU devices (there is no paging "
                     "to turn off)");
    case RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT:
    case RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY:
      return RtError(RT_ERROR_INVALID_VALUE, "this context attribute is read-only");
    default:
      if (attribute >= RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY) {
        return RtError(RT_ERROR_INVALID_VALUE, "this context attribute is read-only");
      }
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("unknown context attribute ", static_cast<int>(attribute)));
  }
}

absl::Status Context::GetAttribute(RTcontextattribute attribute, RTsize size, void* value) const {
  switch (attribute) {
    case RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS:
      return Put<int>("RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS", size, value, num_threads_);
    case RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT:
      // Samplers are host memory and ids, with no hardware texture units to run out of.
      return Put<int>("RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT", size, value, INT_MAX);
    case RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY: {
      RTsize bytes = 0;
      for (const auto& [id, object] : objects_) {
        if (object->kind() == Kind::kBuffer) bytes += static_cast<Buffer*>(object)->byte_size();
      }
      return Put<RTsize>("RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY", size, value, bytes);
    }
    case RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE:
      return Put<int>("RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE", size, value, 0);
    case RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF:
      return Put<int>("RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF", size, value, 0);
    default:
      break;
  }
  if (attribute >= RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY) {
    unsigned ordinal = attribute - RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY;
    if (ordinal >= selected_.size()) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY: device ", ordinal,
                                  " is out of range (", selected_.size(), " devices)"));
    }
    // In-process devices share the host's memory.
    return Put<RTsize>("RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY", size, value,
                       static_cast<RTsize>(AvailableSystemMemory()));
  }
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat("unknown context attribute ", static_cast<int>(attribute)));
}

}  // namespace tessera::api
