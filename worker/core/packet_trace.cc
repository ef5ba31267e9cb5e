#include "packet_trace.h"

#include "bindless.h"
#include "packet16.h"

namespace tessera::worker {
namespace {

// The views `rg` runs with while its lane collects: those of buffers it may write carry
// TESSERA_COLLECTING_EPOCH (their marks are never reached: the access stops at the epoch).
const TesseraBufferView* CollectingTable(ThreadState& ts, const BoundProgram& rg) {
  PacketState& p = ts.packet;
  if (p.table_program != &rg || p.table_plan != ts.plan_serial) {
    static unsigned char unreached = 0;
    static const unsigned char collecting = TESSERA_COLLECTING_EPOCH;
    p.table = rg.table;
    for (unsigned slot : rg.writable_slots) {
      p.table[slot].written = &unreached;
      p.table[slot].written_blocks = &unreached;
      p.table[slot].write_epoch = &collecting;
    }
    p.table_program = &rg;
    p.table_plan = ts.plan_serial;
  }
  return p.table.data();
}

// Out of CollectLane, whose __builtin_setjmp keeps every register on the stack: runs `rg` until
// it returns or CollectTrace jumps out of it. An exception ends the run as an effect would (the
// index raises it again when it runs).
__attribute__((noinline)) void RunUntilTrace(ThreadState& ts, const BoundProgram& rg) {
  try {
    ++ts.index_serial;  // a new launch index for Enter: its index and attributes are written
    Enter(ts, rg);
    t_buffer_table = CollectingTable(ts, rg);
    CallProgram(ts, rg);
  } catch (const ExceptionSignal&) {
  } catch (const FatalError&) {
  }
}

}  // namespace

void CollectLane(ThreadState& ts, const BoundProgram& rg, PacketLane& lane) {
  // Buffers by id are read from a table without a call: an empty one sends every such access
  // through RtBufferById, which ends the run (the header cannot tell a read from a write).
  static const TesseraBufferIdTable kNoIds{0, nullptr};
  lane.scene = nullptr;
  ts.packet.collecting = &lane;
  t_buffer_ids = &kNoIds;
  if (__builtin_setjmp(ts.packet.jump) == 0) RunUntilTrace(ts, rg);
  t_buffer_ids = &ts.plan->bindless.fast;  // as UsePlan set it
  ts.packet.collecting = nullptr;
}

void EndCollecting(ThreadState& ts) {
  ts.packet.collecting->scene = nullptr;
  __builtin_longjmp(ts.packet.jump, 1);
}

void TracePackets(PacketLane* lanes, int count) {
  RTCRayHit* rays[16] = {};  // IntersectPacket16 reads a group's own lanes only
  for (int k = 0; k < count; ++k) rays[k] = &lanes[k].hit;
  ForEachSceneGroup(
      count, [&](int k) { return lanes[k].scene; },
      [&](const SceneEntry* scene, int first, const int* valid, int members) {
        if (members < 2) {  // a packet of one costs more than the ray alone
          lanes[first].scene = nullptr;
          return;
        }
        IntersectPacket16(scene->scene, valid, rays);
      });
}

}  // namespace tessera::worker
