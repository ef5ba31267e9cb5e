// rtContextValidate and rt*Validate: everything a launch would use is alive and complete.
// Messages name the object and what is missing ("geometry instance #5: material 1 is not set").
#ifndef TESSERA_API_SRC_VALIDATE_H_
#define TESSERA_API_SRC_VALIDATE_H_

#include <vector>

#include "absl/status/status.h"
#include "object.h"

namespace tessera::api {

class Context;

// The context and everything reachable from it. Failures are RT_ERROR_INVALID_CONTEXT, or
// RT_ERROR_ALREADY_MAPPED for a mapped buffer.
absl::Status ValidateContext(Context& context);

// One object and everything reachable from it. Failures are RT_ERROR_INVALID_VALUE, or
// RT_ERROR_ALREADY_MAPPED for a mapped buffer.
absl::Status ValidateObject(Object& object);

// Live objects reachable from the context's programs, variables and nodes, each once, in
// depth-first order (the context itself excluded).
std::vector<Object*> CollectReachable(Context& context);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_VALIDATE_H_
