#include "optix7_atomics.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>

#include "tessera/detail/atomic_ops.h"

namespace tessera::worker {
namespace {

namespace ops = atomic_ops;

// Folds (op, operand, limit) into `into`, which already holds the address's notes.
inline void Fold(CombinedAtomic& into, uint32_t op, uint64_t operand, uint32_t limit) {
  if (into.op == ops::kNone) return;
  if (op != into.op || limit != into.limit) {
    into.op = ops::kNone;  // mixed kinds or limits: the order matters, the bytes travel
    return;
  }
  into.operand = ops::Combine(op, into.operand, operand);
}

// Open addressing by address (0 is never device memory, so it marks an empty slot), at most half
// full. A thread's table outlives the call and keeps its slots, so a launch's later calls and
// launches do not allocate.
class NoteTable {
 public:
  void Note(uintptr_t address, uint32_t op, uint64_t operand, uint32_t limit) {
    if ((used_ + 1) * 2 > slots_.size()) Grow();
    CombinedAtomic& slot = Find(address);
    if (slot.address == 0) {
      slot = CombinedAtomic{address, op, limit, operand};
      ++used_;
      return;
    }
    Fold(slot, op, operand, limit);
  }

  // Empties the table for call `call`; a table grown far past the usual (one launch touched
  // millions of addresses) gives its memory back.
  void Reset(uint64_t call) {
    call_ = call;
    if (used_ == 0) return;
    if (slots_.size() > kKeptSlots) {
      std::vector<CombinedAtomic>().swap(slots_);
    } else {
      std::fill(slots_.begin(), slots_.end(), CombinedAtomic{});
    }
    used_ = 0;
  }

  uint64_t call() const { return call_; }
  const std::vector<CombinedAtomic>& slots() const { return slots_; }

 private:
  static constexpr size_t kKeptSlots = size_t{1} << 16;

  CombinedAtomic& Find(uintptr_t address) {
    const size_t mask = slots_.size() - 1;
    // Fibonacci hashing of the 4-byte-aligned address: neighbouring counters spread out.
    size_t i = static_cast<size_t>(((address >> 2) * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (slots_[i].address != 0 && slots_[i].address != address) i = (i + 1) & mask;
    return slots_[i];
  }

  void Grow() {
    std::vector<CombinedAtomic> old;
    old.swap(slots_);
    slots_.assign(std::max<size_t>(64, old.size() * 2), CombinedAtomic{});
    for (const CombinedAtomic& a : old) {
      if (a.address != 0) Find(a.address) = a;
    }
  }

  std::vector<CombinedAtomic> slots_;
  size_t used_ = 0;
  uint64_t call_ = 0;
};

unsigned int noting = 0;  // AtomicsNotedFlag
std::atomic<uint64_t> current_call{0};

// Every thread's table, kept after its thread ends (tables are few: one per device thread).
std::mutex& TablesMutex() {
  static auto* const mu = new std::mutex;
  return *mu;
}
std::vector<std::unique_ptr<NoteTable>>& Tables() {
  static auto* const tables = new std::vector<std::unique_ptr<NoteTable>>;
  return *tables;
}

NoteTable* ThreadTable() {
  thread_local NoteTable* table = [] {
    std::lock_guard<std::mutex> lock(TablesMutex());
    Tables().push_back(std::make_unique<NoteTable>());
    return Tables().back().get();
  }();
  return table;
}

}  // namespace

const unsigned int* AtomicsNotedFlag() { return &noting; }

void NoteAtomic(void* address, unsigned int op, unsigned long long operand, unsigned int limit) {
  NoteTable* table = ThreadTable();
  const uint64_t call = current_call.load(std::memory_order_relaxed);
  if (table->call() != call) table->Reset(call);
  table->Note(reinterpret_cast<uintptr_t>(address), op, operand, limit);
}

void BeginAtomicNotes() {
  current_call.fetch_add(1, std::memory_order_relaxed);
  // Threads that run the call's tiles start after this (the task arena's hand-off orders it).
  noting = 1;
}

std::vector<CombinedAtomic> EndAtomicNotes() {
  noting = 0;
  const uint64_t call = current_call.load(std::memory_order_relaxed);
  NoteTable all;
  std::lock_guard<std::mutex> lock(TablesMutex());
  for (const std::unique_ptr<NoteTable>& table : Tables()) {
    if (table->call() != call) continue;  // took no notes in this call
    for (const CombinedAtomic& a : table->slots()) {
      if (a.address != 0) all.Note(a.address, a.op, a.operand, a.limit);
    }
    table->Reset(call);
  }
  std::vector<CombinedAtomic> out;
  for (const CombinedAtomic& a : all.slots()) {
    if (a.address != 0) out.push_back(a);
  }
  std::sort(out.begin(), out.end(),
            [](const CombinedAtomic& a, const CombinedAtomic& b) { return a.address < b.address; });
  return out;
}

std::vector<CombinedAtomic> AtomicsToSend(const std::vector<CombinedAtomic>& notes,
                                          const std::map<uint64_t, uint64_t>& allocations) {
  std::vector<CombinedAtomic> out;
  for (const CombinedAtomic& a : notes) {
    const uint32_t size = ops::SizeOf(a.op);
    if (size == 0) continue;
    auto it = allocations.upper_bound(a.address);
    if (it == allocations.begin()) continue;
    --it;
    if (a.address - it->first >= it->second || it->second - (a.address - it->first) < size) {
      continue;
    }
    out.push_back(a);
  }
  return out;
}

std::vector<std::pair<uintptr_t, size_t>> RunsWithoutAtomics(
    const std::vector<std::pair<uintptr_t, size_t>>& runs,
    const std::vector<CombinedAtomic>& atomics) {
  if (atomics.empty()) return runs;
  std::vector<std::pair<uintptr_t, size_t>> out;
  size_t next = 0;  // the first atomic that may overlap the current run
  for (const auto& [address, size] : runs) {
    uintptr_t at = address;
    const uintptr_t end = address + size;
    while (next < atomics.size() && atomics[next].address + ops::SizeOf(atomics[next].op) <= at) {
      ++next;
    }
    for (size_t i = next; i < atomics.size() && atomics[i].address < end; ++i) {
      const uintptr_t a = atomics[i].address;
      const uintptr_t a_end = a + ops::SizeOf(atomics[i].op);
      if (a > at) out.emplace_back(at, a - at);
      at = std::max(at, a_end);
    }
    if (at < end) out.emplace_back(at, end - at);
  }
  return out;
}

}  // namespace tessera::worker
