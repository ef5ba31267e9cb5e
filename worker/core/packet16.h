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

// Groups lanes [0, count) (at most 16) by the scene they trace, one packet's worth each, scenes in
// the order of their first lane: scene_of(k) is lane k's scene, null for a lane that traces
// nothing; group(scene, first, valid, members) gets each scene, its first lane, valid[k] = -1 for
// its lanes (0 for the others, IntersectPacket16's mask) and how many there are.
template <typename SceneOf, typename Group>
void ForEachSceneGroup(int count, SceneOf&& scene_of, Group&& group) {
  constexpr int kLanes = 16;
  bool grouped[kLanes] = {};
  for (int first = 0; first < count; ++first) {
    const auto* scene = scene_of(first);
    if (scene == nullptr || grouped[first]) continue;
    int valid[kLanes] = {};
    int members = 0;
    for (int k = first; k < count; ++k) {
      if (grouped[k] || scene_of(k) != scene) continue;
      valid[k] = -1;
      grouped[k] = true;
      ++members;
    }
    group(scene, first, valid, members);
  }
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_PACKET16_H_
