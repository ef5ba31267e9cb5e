// Batched tracing of OptiX 3 launches (docs/programs.md, "Batched tracing"): the launch indices
// of a block of the launch grid (batch_block.h) each run their ray generation program up to its
// first rtTrace, where the ray is kept and the run abandoned; the kept rays are traced as one
// Embree packet; then each index runs as usual, and its first rtTrace takes the packet's hit for
// its ray instead of tracing it. Nothing is suspended, so no lane needs a stack of its own: the
// ray generation program's code before its first trace runs twice instead.
//
// What that first run may not do is anything with an effect: an access to a buffer programs may
// write (its views carry TESSERA_COLLECTING_EPOCH), rtPrintf, a callable program, a buffer by id,
// an exception, or a trace the packet cannot answer (a nested ray, ray flags, a scene where
// Embree calls back into the engine: SceneEntry::packets). Each ends the first run at once, and
// that index traces alone. Which indices share a packet thus depends on the launch alone.
#ifndef TESSERA_WORKER_CORE_PACKET_TRACE_H_
#define TESSERA_WORKER_CORE_PACKET_TRACE_H_

#include "thread_state.h"

namespace tessera::worker {

// Runs `rg` at ts.index until its first rtTrace; lane.scene is that ray's scene when the ray was
// kept, null when the index must trace alone.
void CollectLane(ThreadState& ts, const BoundProgram& rg, PacketLane& lane);

// Traces the kept rays of lanes[0, count) as one packet per scene (fewer than two: none); a lane
// whose ray was not traced in a packet has its scene cleared.
void TracePackets(PacketLane* lanes, int count);

// Called by the engine's entry points that have an effect: while a lane collects, ends its run
// (the index traces alone).
inline void EndCollectingIfAny(ThreadState& ts);
[[noreturn]] void EndCollecting(ThreadState& ts);

inline void EndCollectingIfAny(ThreadState& ts) {
  if (__builtin_expect(ts.packet.collecting != nullptr, 0)) EndCollecting(ts);
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_PACKET_TRACE_H_
