// Embree callbacks implemented by the runtime (runtime.cc); scenes (scene.cc) install them.
#ifndef TESSERA_WORKER_CORE_CALLBACKS_H_
#define TESSERA_WORKER_CORE_CALLBACKS_H_

#include <embree3/rtcore.h>

namespace tessera::worker {

// A primitive of user geometry: runs the intersection program.
void IntersectUserGeometry(const RTCIntersectFunctionNArguments* args);
// A triangle of the watertight test's user geometry (watertight.h): a native triangle's hit.
void IntersectWatertight(const RTCIntersectFunctionNArguments* args);
// A child of a Group (Transform, Group or GeometryGroup): traverses it.
void IntersectChild(const RTCIntersectFunctionNArguments* args);
// A candidate hit on native triangles whose material has an any-hit program.
void FilterTriangles(const RTCFilterFunctionNArguments* args);
// The context filter of a ray traced again because an intersection program rejected the native
// triangle Embree found: puts every triangle candidate to the program (trace.cc).
void VerifyTriangles(const RTCFilterFunctionNArguments* args);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_CALLBACKS_H_
