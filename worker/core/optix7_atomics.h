// Atomics of OptiX 7 programs on a device that holds a copy of device memory
// (docs/device_memory.md, "Atomics across devices"): while a device call notes atomics, each atomic
// function of a program tells NoteAtomic its address, kind and operand
// (tessera/detail/atomic_ops.h), and each thread combines what it is told per address in a table of
// its own (no lock, no log that grows with the number of calls: one entry per address a thread
// reached). At the call's end the threads' tables are combined into one operation per address, for
// the host to apply to its copy.
#ifndef TESSERA_WORKER_CORE_OPTIX7_ATOMICS_H_
#define TESSERA_WORKER_CORE_OPTIX7_ATOMICS_H_

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace tessera::worker {

// One address's atomics combined: `op` (an atomic_ops::Op; kNone when they do not combine),
// `operand` its combined operand, `limit` atomicInc's or atomicDec's.
struct CombinedAtomic {
  uintptr_t address = 0;
  uint32_t op = 0;
  uint32_t limit = 0;
  uint64_t operand = 0;
};

// What the runtime table's atomics_noted points at: not 0 between BeginAtomicNotes and
// EndAtomicNotes.
const unsigned int* AtomicsNotedFlag();
// The runtime table's note_atomic (any thread, while noting).
void NoteAtomic(void* address, unsigned int op, unsigned long long operand, unsigned int limit);

// Starts noting for one device call (calls hold Optix7CallMutex: one at a time per process).
void BeginAtomicNotes();
// Stops noting and returns every thread's notes combined, by address.
std::vector<CombinedAtomic> EndAtomicNotes();

// Splits `notes` (by address) for sending: those inside an allocation of `allocations` (address
// -> size) that combine are returned; the others are dropped (kNone: their bytes travel as
// written; outside device memory: a program's own globals or stack, which no other device sees).
std::vector<CombinedAtomic> AtomicsToSend(const std::vector<CombinedAtomic>& notes,
                                          const std::map<uint64_t, uint64_t>& allocations);

// `runs` (written byte ranges, by address, disjoint) without the bytes of `atomics` (by
// address): the host gets those as operations, and their bytes would undo other devices'.
std::vector<std::pair<uintptr_t, size_t>> RunsWithoutAtomics(
    const std::vector<std::pair<uintptr_t, size_t>>& runs,
    const std::vector<CombinedAtomic>& atomics);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_ATOMICS_H_
