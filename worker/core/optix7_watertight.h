// Watertight triangles of OptiX 7 scenes (TESSERA_ACCURACY_WATERTIGHT, or the acceleration's
// TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT): a triangle build input becomes an Embree user geometry
// whose intersection function runs the watertight test of watertight.h over the same vertices and
// indices, then hands the hit on exactly as Embree hands on a native triangle's (barycentrics,
// unnormalized Ng, the context's filter), so the engine cannot tell the two apart
// (docs/optix7_engine.md, "Speed and accuracy"). Motion triangles stay native.
#ifndef TESSERA_WORKER_CORE_OPTIX7_WATERTIGHT_H_
#define TESSERA_WORKER_CORE_OPTIX7_WATERTIGHT_H_

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "accel_format.h"

namespace tessera::worker {

// The triangles of one build input, copied out of the descriptor (scenes outlive the device
// memory they were built from, and may serve another buffer of the same content).
struct Optix7WatertightMesh {
  std::vector<float> vertices;    // 3 a vertex
  std::vector<uint32_t> indices;  // 3 a triangle
};

// A new user geometry for build input `in` of the descriptor at `descriptor` (no motion), its
// triangles copied into `mesh`, which must outlive the geometry. Null when Embree refuses.
RTCGeometry NewWatertightGeometry(RTCDevice device, const unsigned char* descriptor,
                                  const memory::AccelInput& in, Optix7WatertightMesh* mesh);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_WATERTIGHT_H_
