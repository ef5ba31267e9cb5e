#include "result.h"

#include <string>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace tessera::optix7 {
namespace {

constexpr char kPayloadUrl[] = "type.tessera.dev/optix7.OptixResult";

struct ResultText {
  OptixResult result;
  const char* name;
  const char* text;
};

// OptiX 7.7's codes and OptiX's own descriptions where they say more than the name.
constexpr ResultText kResults[] = {
    {OPTIX_SUCCESS, "OPTIX_SUCCESS", "Success"},
    {OPTIX_ERROR_INVALID_VALUE, "OPTIX_ERROR_INVALID_VALUE", "Invalid value"},
    {OPTIX_ERROR_HOST_OUT_OF_MEMORY, "OPTIX_ERROR_HOST_OUT_OF_MEMORY", "Host is out of memory"},
    {OPTIX_ERROR_INVALID_OPERATION, "OPTIX_ERROR_INVALID_OPERATION", "Invalid operation"},
    {OPTIX_ERROR_FILE_IO_ERROR, "OPTIX_ERROR_FILE_IO_ERROR", "File I/O error"},
    {OPTIX_ERROR_INVALID_FILE_FORMAT, "OPTIX_ERROR_INVALID_FILE_FORMAT", "Invalid file format"},
    {OPTIX_ERROR_DISK_CACHE_INVALID_PATH, "OPTIX_ERROR_DISK_CACHE_INVALID_PATH",
     "Invalid path to disk cache file"},
    {OPTIX_ERROR_DISK_CACHE_PERMISSION_ERROR, "OPTIX_ERROR_DISK_CACHE_PERMISSION_ERROR",
     "Disk cache file is not writable"},
    {OPTIX_ERROR_DISK_CACHE_DATABASE_ERROR, "OPTIX_ERROR_DISK_CACHE_DATABASE_ERROR",
     "Disk cache database error"},
    {OPTIX_ERROR_DISK_CACHE_INVALID_DATA, "OPTIX_ERROR_DISK_CACHE_INVALID_DATA",
     "Invalid data in disk cache"},
    {OPTIX_ERROR_LAUNCH_FAILURE, "OPTIX_ERROR_LAUNCH_FAILURE", "Launch failure"},
    {OPTIX_ERROR_INVALID_DEVICE_CONTEXT, "OPTIX_ERROR_INVALID_DEVICE_CONTEXT",
     "Invalid device context"},
    {OPTIX_ERROR_CUDA_NOT_INITIALIZED, "OPTIX_ERROR_CUDA_NOT_INITIALIZED",
     "CUDA is not initialized"},
    {OPTIX_ERROR_VALIDATION_FAILURE, "OPTIX_ERROR_VALIDATION_FAILURE",
     "Error during validation mode run"},
    {OPTIX_ERROR_INVALID_INPUT, "OPTIX_ERROR_INVALID_INPUT",
     "Invalid module input (C++ source, module bytes or path)"},
    {OPTIX_ERROR_INVALID_LAUNCH_PARAMETER, "OPTIX_ERROR_INVALID_LAUNCH_PARAMETER",
     "Invalid launch parameter"},
    {OPTIX_ERROR_INVALID_PAYLOAD_ACCESS, "OPTIX_ERROR_INVALID_PAYLOAD_ACCESS",
     "Invalid payload access"},
    {OPTIX_ERROR_INVALID_ATTRIBUTE_ACCESS, "OPTIX_ERROR_INVALID_ATTRIBUTE_ACCESS",
     "Invalid attribute access"},
    {OPTIX_ERROR_INVALID_FUNCTION_USE, "OPTIX_ERROR_INVALID_FUNCTION_USE",
     "Invalid use of optix intrinsic function"},
    {OPTIX_ERROR_INVALID_FUNCTION_ARGUMENTS, "OPTIX_ERROR_INVALID_FUNCTION_ARGUMENTS",
     "Invalid arguments to optix intrinsic function"},
    {OPTIX_ERROR_PIPELINE_OUT_OF_CONSTANT_MEMORY, "OPTIX_ERROR_PIPELINE_OUT_OF_CONSTANT_MEMORY",
     "Pipeline out of constant memory"},
    {OPTIX_ERROR_PIPELINE_LINK_ERROR, "OPTIX_ERROR_PIPELINE_LINK_ERROR", "Pipeline link error"},
    {OPTIX_ERROR_ILLEGAL_DURING_TASK_EXECUTE, "OPTIX_ERROR_ILLEGAL_DURING_TASK_EXECUTE",
     "Illegal call during task execute"},
    {OPTIX_ERROR_INTERNAL_COMPILER_ERROR, "OPTIX_ERROR_INTERNAL_COMPILER_ERROR",
     "Internal compiler error"},
    {OPTIX_ERROR_DENOISER_MODEL_NOT_SET, "OPTIX_ERROR_DENOISER_MODEL_NOT_SET",
     "Denoiser model not set"},
    {OPTIX_ERROR_DENOISER_NOT_INITIALIZED, "OPTIX_ERROR_DENOISER_NOT_INITIALIZED",
     "Denoiser not initialized"},
    {OPTIX_ERROR_NOT_COMPATIBLE, "OPTIX_ERROR_NOT_COMPATIBLE", "Not compatible"},
    {OPTIX_ERROR_PAYLOAD_TYPE_MISMATCH, "OPTIX_ERROR_PAYLOAD_TYPE_MISMATCH",
     "Payload type mismatch"},
    {OPTIX_ERROR_PAYLOAD_TYPE_RESOLUTION_FAILED, "OPTIX_ERROR_PAYLOAD_TYPE_RESOLUTION_FAILED",
     "Payload type resolution failed"},
    {OPTIX_ERROR_PAYLOAD_TYPE_ID_INVALID, "OPTIX_ERROR_PAYLOAD_TYPE_ID_INVALID",
     "Payload type id invalid"},
    {OPTIX_ERROR_NOT_SUPPORTED, "OPTIX_ERROR_NOT_SUPPORTED", "Feature not supported"},
    {OPTIX_ERROR_UNSUPPORTED_ABI_VERSION, "OPTIX_ERROR_UNSUPPORTED_ABI_VERSION",
     "Unsupported ABI version"},
    {OPTIX_ERROR_FUNCTION_TABLE_SIZE_MISMATCH, "OPTIX_ERROR_FUNCTION_TABLE_SIZE_MISMATCH",
     "Function table size mismatch"},
    {OPTIX_ERROR_INVALID_ENTRY_FUNCTION_OPTIONS, "OPTIX_ERROR_INVALID_ENTRY_FUNCTION_OPTIONS",
     "Invalid options to entry function"},
    {OPTIX_ERROR_LIBRARY_NOT_FOUND, "OPTIX_ERROR_LIBRARY_NOT_FOUND", "Library not found"},
    {OPTIX_ERROR_ENTRY_SYMBOL_NOT_FOUND, "OPTIX_ERROR_ENTRY_SYMBOL_NOT_FOUND",
     "Entry symbol not found"},
    {OPTIX_ERROR_LIBRARY_UNLOAD_FAILURE, "OPTIX_ERROR_LIBRARY_UNLOAD_FAILURE",
     "Library could not be unloaded"},
    {OPTIX_ERROR_DEVICE_OUT_OF_MEMORY, "OPTIX_ERROR_DEVICE_OUT_OF_MEMORY", "Device out of memory"},
    {OPTIX_ERROR_CUDA_ERROR, "OPTIX_ERROR_CUDA_ERROR", "CUDA error"},
    {OPTIX_ERROR_INTERNAL_ERROR, "OPTIX_ERROR_INTERNAL_ERROR", "Internal error"},
    {OPTIX_ERROR_UNKNOWN, "OPTIX_ERROR_UNKNOWN", "Unknown error"},
};

const ResultText* Find(OptixResult result) {
  for (const ResultText& r : kResults) {
    if (r.result == result) return &r;
  }
  return nullptr;
}

}  // namespace

absl::Status OptixError(OptixResult code, absl::string_view message) {
  absl::StatusCode canonical = absl::StatusCode::kInvalidArgument;
  switch (code) {
    case OPTIX_ERROR_NOT_SUPPORTED:
      canonical = absl::StatusCode::kUnimplemented;
      break;
    case OPTIX_ERROR_HOST_OUT_OF_MEMORY:
    case OPTIX_ERROR_DEVICE_OUT_OF_MEMORY:
      canonical = absl::StatusCode::kResourceExhausted;
      break;
    case OPTIX_ERROR_INTERNAL_ERROR:
    case OPTIX_ERROR_INTERNAL_COMPILER_ERROR:
      canonical = absl::StatusCode::kInternal;
      break;
    default:
      break;
  }
  absl::Status status(canonical, message);
  status.SetPayload(kPayloadUrl, absl::Cord(absl::StrCat(static_cast<int>(code))));
  return status;
}

OptixResult ToOptixResult(const absl::Status& status, OptixResult otherwise) {
  if (status.ok()) return OPTIX_SUCCESS;
  if (auto payload = status.GetPayload(kPayloadUrl)) {
    int code = 0;
    if (absl::SimpleAtoi(std::string(*payload), &code)) return static_cast<OptixResult>(code);
  }
  switch (status.code()) {
    case absl::StatusCode::kInvalidArgument:
    case absl::StatusCode::kNotFound:
    case absl::StatusCode::kOutOfRange:
      return OPTIX_ERROR_INVALID_VALUE;
    case absl::StatusCode::kUnimplemented:
      return OPTIX_ERROR_NOT_SUPPORTED;
    case absl::StatusCode::kResourceExhausted:
      return OPTIX_ERROR_HOST_OUT_OF_MEMORY;
    case absl::StatusCode::kFailedPrecondition:
      return OPTIX_ERROR_INVALID_OPERATION;
    default:
      return otherwise;
  }
}

const char* ResultName(OptixResult result) {
  const ResultText* r = Find(result);
  return r != nullptr ? r->name : "Unknown OptixResult code";
}

const char* ResultString(OptixResult result) {
  const ResultText* r = Find(result);
  return r != nullptr ? r->text : "Unknown OptixResult code";
}

}  // namespace tessera::optix7
