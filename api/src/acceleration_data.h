// Acceleration data caching on the host (OptiX 3 guide 3.6.5, docs/acceleration_data.md):
// reading a build's data back from a device, and deciding whether restored data ships.
#ifndef TESSERA_API_SRC_ACCELERATION_DATA_H_
#define TESSERA_API_SRC_ACCELERATION_DATA_H_

#include <string>

#include "absl/status/statusor.h"
#include "acceleration.h"
#include "context.h"
#include "tessera/v1/state.pb.h"

namespace tessera::api {

// rtAccelerationGetDataSize/GetData: the blob of `a`'s current build, made once per build epoch
// and version. RT_ERROR_INVALID_VALUE, saying to launch first, while `a` is dirty or no device
// holds its build.
absl::StatusOr<const std::string*> ExtractAccelerationData(Context& context, Acceleration& a);

// Before a launch ships its state: each acceleration whose restored data was not yet checked and
// that is on a node now is checked against that node's children (counts, programs). A mismatch
// is said once on stderr, and devices then build it as usual.
void CheckRestoredAccelerations(Context& context);

// Lowering: the restored bounds of `a` into `out`, when the check found them built over its graph.
void LowerRestoredBounds(const Acceleration& a, v1::Acceleration* out);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_ACCELERATION_DATA_H_
