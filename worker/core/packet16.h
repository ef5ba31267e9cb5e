// One 16-wide Embree packet of rays from neighbouring launch indices (batched tracing of both
// layers: optix7_batch.h, packet_trace.h).
#ifndef TESSERA_WORKER_CORE_PACKET16_H_
#define TESSERA_WORKER_CORE_PACKET16_H_

#include <embree3/rtcore.h>

namespace tessera::worker {

// Traces rays[k] for every k with valid[k] set (-1) as one rtcIntersect16 in `scene`, with
// Embree's coherent packet traversal (a block's rays leave neighbouring launch indices; the
// default context takes rays as incoherent and traces a packet ray by ray). Each traced ray gets
// its tfar and hit back in place, as rtcIntersect1 would give them.
void IntersectPacket16(RTCScene scene, const int* valid, RTCRayHit* const* rays);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_PACKET16_H_
