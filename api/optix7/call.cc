#include "call.h"

#include <algorithm>
#include <cstring>

namespace tessera::optix7 {
namespace {

const char* TagFor(unsigned level) {
  switch (level) {
    case kLogFatal:
      return "FATAL";
    case kLogError:
      return "ERROR";
    case kLogWarning:
      return "WARNING";
    default:
      return "INFO";
  }
}

}  // namespace

void Call::Log(unsigned level, absl::string_view message) {
  const std::string text = absl::StrCat(function_, ": ", message);
  if (log_string_size_ != nullptr) absl::StrAppend(&log_, log_.empty() ? "" : "\n", text);
  if (context_ != nullptr) context_->Log(level, TagFor(level), text);
}

absl::Status Call::NotNull(const void* pointer, absl::string_view argument) const {
  if (pointer != nullptr) return absl::OkStatus();
  return OptixError(OPTIX_ERROR_INVALID_VALUE, absl::StrCat(argument, " is null"));
}

OptixResult Call::Finish(const absl::Status& status, OptixResult otherwise) {
  if (!status.ok()) Log(kLogError, status.message());
  if (log_string_size_ != nullptr) {
    const size_t capacity = *log_string_size_;
    if (log_string_ != nullptr && capacity > 0) {
      const size_t n = std::min(capacity - 1, log_.size());
      std::memcpy(log_string_, log_.data(), n);
      log_string_[n] = '\0';
    }
    *log_string_size_ = log_.empty() ? 0 : log_.size() + 1;
  }
  return ToOptixResult(status, otherwise);
}

}  // namespace tessera::optix7
