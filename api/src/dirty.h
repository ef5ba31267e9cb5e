// Carries "the structure below changed" up the node graph to acceleration structures.
// OptiX 3 leaves this to the application (rtAccelerationMarkDirty); Tessera does it as well, so
// an application that forgets still renders correctly. Documented in docs/COMPATIBILITY.md.
#ifndef TESSERA_API_SRC_DIRTY_H_
#define TESSERA_API_SRC_DIRTY_H_

#include "object.h"

namespace tessera::api {

// `changed` is a buffer a geometry refers to, a geometry, an instance or a node whose children,
// programs, primitive count or matrix changed. Every acceleration on a GeometryGroup or Group at
// or above it is marked dirty, but `keep_restored` while it holds rtAccelerationSetData's data.
void NotifyStructureChanged(Object* changed, const Object* keep_restored = nullptr);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_DIRTY_H_
