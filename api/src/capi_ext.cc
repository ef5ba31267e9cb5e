// tessera* extension functions (tessera/rt_ext.h).
#include <string>

#include "boundary.h"
#include "device_spec.h"
#include "tessera/rt_ext.h"

using namespace tessera::api;  // NOLINT: C entry points only

extern "C" {

RTresult tesseraContextSetDeviceSpec(RTcontext context, const char* spec) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(spec, "device spec"));
    return c.SetDeviceSpec(spec);
  });
}

RTresult tesseraDeviceSpecValidate(const char* spec, const char** error) {
  thread_local std::string message;
  if (error != nullptr) *error = nullptr;
  RTresult result = CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(spec, "device spec"));
    auto entries = ParseDeviceSpec(spec);
    if (entries.ok()) return absl::OkStatus();
    message = std::string(entries.status().message());
    return entries.status();
  });
  if (result != RT_SUCCESS && error != nullptr) {
    if (message.empty()) message = "device spec is null";
    *error = message.c_str();
  }
  return result;
}

RTresult tesseraContextGetExceptionReportCount(RTcontext context, RTsize* count) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = c.last_exceptions().size();
    return absl::OkStatus();
  });
}

}  // extern "C"
