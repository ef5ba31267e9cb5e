// OptixResult inside the OptiX 7 layer: errors are absl::Status, and one that must surface as a
// particular OptixResult carries it as a payload (as api/src/status.h does for RTresult).
#ifndef TESSERA_API_OPTIX7_RESULT_H_
#define TESSERA_API_OPTIX7_RESULT_H_

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "optix_types.h"

namespace tessera::optix7 {

// A failed status whose OptixResult is exactly `code`.
absl::Status OptixError(OptixResult code, absl::string_view message);

// The payload's OptixResult, else by canonical code: INVALID_ARGUMENT and NOT_FOUND are
// OPTIX_ERROR_INVALID_VALUE, UNIMPLEMENTED OPTIX_ERROR_NOT_SUPPORTED, RESOURCE_EXHAUSTED
// OPTIX_ERROR_HOST_OUT_OF_MEMORY, FAILED_PRECONDITION OPTIX_ERROR_INVALID_OPERATION, anything
// else `otherwise` (OPTIX_ERROR_INTERNAL_ERROR unless a caller knows better, e.g. a launch).
OptixResult ToOptixResult(const absl::Status& status,
                          OptixResult otherwise = OPTIX_ERROR_INTERNAL_ERROR);

// "OPTIX_ERROR_INVALID_VALUE"; "Unknown OptixResult code" for a value that is none.
const char* ResultName(OptixResult result);
// A sentence saying what `result` means; never null.
const char* ResultString(OptixResult result);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_RESULT_H_
