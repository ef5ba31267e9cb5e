// tessera* extension functions (tessera/rt_ext.h).
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "device_spec.h"
#include "device_table.h"
#include "status.h"
#include "tessera/log.h"
#include "tessera/rt_ext.h"
#include "tessera/scheduler/log.h"

using namespace tessera::api;  // NOLINT: C entry points only

static_assert(TESSERA_LOG_TRACE == static_cast<int>(tessera::log::Level::kTrace) &&
                  TESSERA_LOG_DEBUG == static_cast<int>(tessera::log::Level::kDebug) &&
                  TESSERA_LOG_INFO == static_cast<int>(tessera::log::Level::kInfo) &&
                  TESSERA_LOG_WARN == static_cast<int>(tessera::log::Level::kWarn) &&
                  TESSERA_LOG_ERROR == static_cast<int>(tessera::log::Level::kError) &&
                  TESSERA_LOG_OFF == static_cast<int>(tessera::log::Level::kOff),
              "tessera/log.h's levels are the log's");

extern "C" {

// No handle to look up and no error to report: nothing but running out of memory before the first
// line can go wrong, and then lines go on to stderr.
void tesseraSetLogCallback(TesseraLogCallback callback, void* user) {
  try {
    tessera::log::SetCallback(callback, user);
  } catch (...) {
  }
}

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

RTresult tesseraDeviceGetAddress(int ordinal, RTsize size, char* address) {
  return CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(address, "address pointer"));
    if (size == 0) return RtError(RT_ERROR_INVALID_VALUE, "the address needs size > 0");
    TS_ASSIGN_OR_RETURN(DeviceDesc device, GlobalDevice(ordinal));
    CopyString(device.address, size, address);
    return absl::OkStatus();
  });
}

RTresult tesseraContextGetExceptionReportCount(RTcontext context, RTsize* count) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = c.last_exception_count();
    return absl::OkStatus();
  });
}

RTresult tesseraContextGetLastLaunchBatched(RTcontext context, int* batched) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(batched, "batched pointer"));
    *batched = c.last_launch_batched() ? 1 : 0;
    return absl::OkStatus();
  });
}

RTresult tesseraContextGetTransferStats(RTcontext context, unsigned long long* bytes_sent,
                                        unsigned long long* bytes_received) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (bytes_sent != nullptr) *bytes_sent = c.bytes_sent();
    if (bytes_received != nullptr) *bytes_received = c.bytes_received();
    return absl::OkStatus();
  });
}

RTresult tesseraContextSetTileSize(RTcontext context, unsigned int dimensionality,
                                   const RTsize* size) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (dimensionality > 3) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("tile size dimensionality ", dimensionality, " is not 0..3"));
    }
    std::vector<uint64_t> tile(dimensionality);
    if (dimensionality > 0) TS_RETURN_IF_ERROR(NotNull(size, "tile size"));
    for (unsigned d = 0; d < dimensionality; ++d) {
      if (size[d] == 0) {
        return RtError(RT_ERROR_INVALID_VALUE,
                       absl::StrCat("tile size entry ", d, " is 0; tiles need a positive size"));
      }
      tile[d] = size[d];
    }
    return c.SetTileSize(std::move(tile));
  });
}

RTresult tesseraContextSetRaceCheck(RTcontext context, int enabled) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.set_race_check(enabled != 0);
    return absl::OkStatus();
  });
}

RTresult tesseraContextSetAccuracy(RTcontext context, unsigned int flags) {
  return Call<Context>(__func__, context, [&](Context& c) { return c.SetAccuracy(flags); });
}

RTresult tesseraContextGetAccuracy(RTcontext context, unsigned int* flags) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(flags, "flags pointer"));
    *flags = c.accuracy_flags();
    return absl::OkStatus();
  });
}

RTresult tesseraContextGetRaceCount(RTcontext context, RTsize* count) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = c.last_race_count();
    return absl::OkStatus();
  });
}

RTresult tesseraContextGetLaunchProgress(RTcontext context, RTsize* tiles_done,
                                         RTsize* tiles_total) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (tiles_done != nullptr) *tiles_done = c.tiles_done();
    if (tiles_total != nullptr) *tiles_total = c.tiles_total();
    return absl::OkStatus();
  });
}

}  // extern "C"
