// Embree callbacks implemented by the runtime (runtime.cc); scenes (scene.cc) install them.
#ifndef TESSERA_WORKER_CORE_CALLBACKS_H_
#define TESSERA_WORKER_CORE_CALLBACKS_H_

#include <embree3/rtcore.h>

namespace tessera::worker {

// A primitive of user geometry: runs the intersection program.
void IntersectUserGeometry(const RTCIntersectFunctionNArguments* args);
// A child of a Group (Transform, Group or GeometryGroup): traverses it.
void IntersectChild(const RTCIntersectFunctionNArguments* args);
// A candidate hit on native triangles whose material has an any-hit program.
void FilterTriangles(const RTCFilterFunctionNArguments* args);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_CALLBACKS_H_
