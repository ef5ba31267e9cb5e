// The boundary of every OptiX 7 host function: the body runs inside Call::Run, which catches
// everything, sends a failure's message to the device context's log callback (level 2, the
// function named) and to the call's log buffer when it has one, and maps the status to an
// OptixResult. Nothing throws across the boundary; nothing aborts on a user's error.
#ifndef TESSERA_API_OPTIX7_CALL_H_
#define TESSERA_API_OPTIX7_CALL_H_

#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <type_traits>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "host_objects.h"
#include "result.h"

namespace tessera::optix7 {

class Call {
 public:
  // `function` names the API function in messages ("optixModuleCreate"). `log_string` and
  // `log_string_size` are the create functions' log buffer, or null: on return the buffer holds
  // as much of the call's log as fits, NUL-terminated, and *log_string_size the log's whole size
  // with its NUL (more than the buffer's size when it was cut short), or 0 when nothing was
  // logged.
  explicit Call(const char* function, char* log_string = nullptr, size_t* log_string_size = nullptr)
      : function_(function), log_string_(log_string), log_string_size_(log_string_size) {}

  const char* function() const { return function_; }

  // The context messages go to, once the body has found it.
  void set_context(std::shared_ptr<DeviceContext> context) { context_ = std::move(context); }
  const std::shared_ptr<DeviceContext>& context() const { return context_; }

  // A message for the log buffer, and for the callback at `level`.
  void Log(unsigned level, absl::string_view message);

  // OPTIX_ERROR_INVALID_VALUE naming `argument` when it is null.
  absl::Status NotNull(const void* pointer, absl::string_view argument) const;

  // The live object of `handle`, or INVALID_VALUE naming `argument`; makes its context this
  // call's.
  template <typename T>
  absl::Status Lookup(const void* handle, absl::string_view argument, std::shared_ptr<T>* out);

  // Runs `body` (absl::Status(Call&)) and maps its status; `otherwise` is the result of failures
  // that carry no OptixResult and have no canonical mapping (result.h).
  template <typename F>
  OptixResult Run(F&& body, OptixResult otherwise = OPTIX_ERROR_INTERNAL_ERROR) {
    absl::Status status;
    try {
      status = body(*this);
    } catch (const std::bad_alloc&) {
      status = OptixError(OPTIX_ERROR_HOST_OUT_OF_MEMORY, "out of host memory");
    } catch (const std::exception& e) {
      status = OptixError(OPTIX_ERROR_INTERNAL_ERROR, absl::StrCat("internal error: ", e.what()));
    } catch (...) {
      status = OptixError(OPTIX_ERROR_INTERNAL_ERROR, "internal error: unknown exception");
    }
    return Finish(status, otherwise);
  }

 private:
  OptixResult Finish(const absl::Status& status, OptixResult otherwise);

  const char* function_;
  char* log_string_;
  size_t* log_string_size_;
  std::shared_ptr<DeviceContext> context_;
  std::string log_;
};

template <typename T>
absl::Status Call::Lookup(const void* handle, absl::string_view argument, std::shared_ptr<T>* out) {
  static constexpr const char* kNames[] = {"OptixDeviceContext", "OptixModule", "OptixTask",
                                           "OptixProgramGroup", "OptixPipeline"};
  const char* type = kNames[static_cast<int>(T::kKind)];
  if (handle == nullptr) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE, absl::StrCat(argument, " is a null ", type));
  }
  *out = Find<T>(handle);
  if (*out == nullptr) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(argument, " (0x", absl::Hex(reinterpret_cast<uintptr_t>(handle)),
                                   ") is not a live ", type,
                                   " (destroyed, never created, or another kind of handle)"));
  }
  if constexpr (std::is_same_v<T, DeviceContext>) {
    if (context_ == nullptr) context_ = *out;
  } else {
    if (context_ == nullptr) context_ = (*out)->context;
  }
  return absl::OkStatus();
}

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_CALL_H_
