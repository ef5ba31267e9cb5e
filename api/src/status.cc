#include "status.h"

#include <cstdlib>
#include <string>

#include "absl/strings/cord.h"
#include "absl/strings/numbers.h"

namespace tessera::api {
namespace {

constexpr char kPayloadUrl[] = "type.tessera.dev/rtresult";

// The one table. `from_status` marks the row used when a status without payload (from a device,
// Abseil or gRPC) is turned into an RTresult; every RTresult maps to its row's status code.
struct Row {
  RTresult result;
  absl::StatusCode code;
  bool from_status;
  const char* text;
};

constexpr Row kTable[] = {
    {RT_SUCCESS, absl::StatusCode::kOk, true, "RT_SUCCESS: success"},
    {RT_TIMEOUT_CALLBACK, absl::StatusCode::kCancelled, true,
     "RT_TIMEOUT_CALLBACK: cancelled by the timeout callback"},
    {RT_ERROR_INVALID_CONTEXT, absl::StatusCode::kFailedPrecondition, true,
     "RT_ERROR_INVALID_CONTEXT: invalid context"},
    {RT_ERROR_INVALID_VALUE, absl::StatusCode::kInvalidArgument, true,
     "RT_ERROR_INVALID_VALUE: invalid value"},
    {RT_ERROR_INVALID_VALUE, absl::StatusCode::kNotFound, true, nullptr},
    {RT_ERROR_INVALID_VALUE, absl::StatusCode::kAlreadyExists, true, nullptr},
    {RT_ERROR_INVALID_VALUE, absl::StatusCode::kOutOfRange, true, nullptr},
    {RT_ERROR_MEMORY_ALLOCATION_FAILED, absl::StatusCode::kResourceExhausted, true,
     "RT_ERROR_MEMORY_ALLOCATION_FAILED: memory allocation failed"},
    {RT_ERROR_TYPE_MISMATCH, absl::StatusCode::kInvalidArgument, false,
     "RT_ERROR_TYPE_MISMATCH: type mismatch"},
    {RT_ERROR_VARIABLE_NOT_FOUND, absl::StatusCode::kNotFound, false,
     "RT_ERROR_VARIABLE_NOT_FOUND: variable not found"},
    {RT_ERROR_VARIABLE_REDECLARED, absl::StatusCode::kAlreadyExists, false,
     "RT_ERROR_VARIABLE_REDECLARED: variable redeclared"},
    {RT_ERROR_ILLEGAL_SYMBOL, absl::StatusCode::kInvalidArgument, false,
     "RT_ERROR_ILLEGAL_SYMBOL: illegal symbol"},
    {RT_ERROR_INVALID_SOURCE, absl::StatusCode::kInvalidArgument, false,
     "RT_ERROR_INVALID_SOURCE: invalid program source"},
    {RT_ERROR_VERSION_MISMATCH, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_VERSION_MISMATCH: version mismatch"},
    {RT_ERROR_OBJECT_CREATION_FAILED, absl::StatusCode::kInternal, false,
     "RT_ERROR_OBJECT_CREATION_FAILED: object creation failed"},
    {RT_ERROR_NO_DEVICE, absl::StatusCode::kUnavailable, false, "RT_ERROR_NO_DEVICE: no device"},
    {RT_ERROR_INVALID_DEVICE, absl::StatusCode::kInvalidArgument, false,
     "RT_ERROR_INVALID_DEVICE: invalid device"},
    {RT_ERROR_INVALID_IMAGE, absl::StatusCode::kInvalidArgument, false,
     "RT_ERROR_INVALID_IMAGE: invalid image"},
    {RT_ERROR_FILE_NOT_FOUND, absl::StatusCode::kNotFound, false,
     "RT_ERROR_FILE_NOT_FOUND: file not found"},
    {RT_ERROR_ALREADY_MAPPED, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_ALREADY_MAPPED: buffer already mapped"},
    {RT_ERROR_INVALID_DRIVER_VERSION, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_INVALID_DRIVER_VERSION: invalid driver version"},
    {RT_ERROR_CONTEXT_CREATION_FAILED, absl::StatusCode::kInternal, false,
     "RT_ERROR_CONTEXT_CREATION_FAILED: context creation failed"},
    {RT_ERROR_RESOURCE_NOT_REGISTERED, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_RESOURCE_NOT_REGISTERED: resource not registered"},
    {RT_ERROR_RESOURCE_ALREADY_REGISTERED, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_RESOURCE_ALREADY_REGISTERED: resource already registered"},
    {RT_ERROR_LAUNCH_FAILED, absl::StatusCode::kInternal, true,
     "RT_ERROR_LAUNCH_FAILED: launch failed"},
    {RT_ERROR_LAUNCH_FAILED, absl::StatusCode::kAborted, true, nullptr},
    {RT_ERROR_LAUNCH_FAILED, absl::StatusCode::kDataLoss, true, nullptr},
    {RT_ERROR_LAUNCH_FAILED, absl::StatusCode::kDeadlineExceeded, true, nullptr},
    {RT_ERROR_NOT_SUPPORTED, absl::StatusCode::kUnimplemented, true,
     "RT_ERROR_NOT_SUPPORTED: not supported"},
    {RT_ERROR_CONNECTION_FAILED, absl::StatusCode::kUnavailable, true,
     "RT_ERROR_CONNECTION_FAILED: connection failed"},
    {RT_ERROR_AUTHENTICATION_FAILED, absl::StatusCode::kUnauthenticated, true,
     "RT_ERROR_AUTHENTICATION_FAILED: authentication failed"},
    {RT_ERROR_AUTHENTICATION_FAILED, absl::StatusCode::kPermissionDenied, true, nullptr},
    {RT_ERROR_CONNECTION_ALREADY_EXISTS, absl::StatusCode::kAlreadyExists, false,
     "RT_ERROR_CONNECTION_ALREADY_EXISTS: connection already exists"},
    {RT_ERROR_NETWORK_LOAD_FAILED, absl::StatusCode::kUnavailable, false,
     "RT_ERROR_NETWORK_LOAD_FAILED: network load failed"},
    {RT_ERROR_NETWORK_INIT_FAILED, absl::StatusCode::kUnavailable, false,
     "RT_ERROR_NETWORK_INIT_FAILED: network init failed"},
    {RT_ERROR_CLUSTER_NOT_RUNNING, absl::StatusCode::kUnavailable, false,
     "RT_ERROR_CLUSTER_NOT_RUNNING: cluster not running"},
    {RT_ERROR_CLUSTER_ALREADY_RUNNING, absl::StatusCode::kFailedPrecondition, false,
     "RT_ERROR_CLUSTER_ALREADY_RUNNING: cluster already running"},
    {RT_ERROR_INSUFFICIENT_FREE_NODES, absl::StatusCode::kResourceExhausted, false,
     "RT_ERROR_INSUFFICIENT_FREE_NODES: insufficient free nodes"},
    {RT_ERROR_UNKNOWN, absl::StatusCode::kUnknown, true, "RT_ERROR_UNKNOWN: unknown error"},
};

const Row* RowFor(RTresult code) {
  for (const Row& row : kTable) {
    if (row.result == code && row.text != nullptr) return &row;
  }
  return nullptr;
}

}  // namespace

absl::Status RtError(RTresult code, absl::string_view message) {
  absl::Status status(StatusCodeFor(code), message);
  status.SetPayload(kPayloadUrl, absl::Cord(std::to_string(static_cast<unsigned>(code))));
  return status;
}

absl::StatusCode StatusCodeFor(RTresult code) {
  const Row* row = RowFor(code);
  return row != nullptr ? row->code : absl::StatusCode::kUnknown;
}

RTresult ToRtResult(const absl::Status& status) {
  if (status.ok()) return RT_SUCCESS;
  if (auto payload = status.GetPayload(kPayloadUrl)) {
    unsigned value = 0;
    if (absl::SimpleAtoi(std::string(*payload), &value)) return static_cast<RTresult>(value);
  }
  for (const Row& row : kTable) {
    if (row.from_status && row.code == status.code()) return row.result;
  }
  return RT_ERROR_UNKNOWN;
}

const char* ResultText(RTresult code) {
  const Row* row = RowFor(code);
  return row != nullptr ? row->text : "unknown RTresult code";
}

}  // namespace tessera::api
