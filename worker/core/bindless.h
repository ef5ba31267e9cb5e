// Buffer and program ids (OptiX 3.5+) on a device: what an rtBufferId or rtCallableProgramId of a
// program resolves to. Ids are the host's object ids, the same on every device and launch. A plan
// resolves every id once, into tables indexed by id, so a program's access costs an array lookup,
// not a search of the replica (docs/programs.md, "Buffer and program ids").
#ifndef TESSERA_WORKER_CORE_BINDLESS_H_
#define TESSERA_WORKER_CORE_BINDLESS_H_

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "binding.h"
#include "replica.h"
#include "tessera/detail/module_abi.h"

namespace tessera::worker {

// Object ids to small indices. A flat array indexed by id while ids are dense enough (an object
// id is below the count of objects the host made), else a sorted array searched by halves, so a
// context that made and destroyed millions of objects does not get a table of millions.
class IdIndex {
 public:
  // `entries`: (id, index) pairs, ids distinct and positive.
  void Build(std::vector<std::pair<uint64_t, uint32_t>> entries);
  bool dense() const { return !sparse_; }
  // The index of `id`, or -1.
  long Find(long long id) const {
    if (id <= 0) return -1;
    const auto u = static_cast<uint64_t>(id);
    if (!sparse_) return u < dense_.size() ? dense_[u] : -1;
    return FindSparse(u);
  }

 private:
  long FindSparse(uint64_t id) const;
  bool sparse_ = false;
  std::vector<int32_t> dense_;                         // by id; -1: none
  std::vector<std::pair<uint64_t, uint32_t>> sorted_;  // by id
};

inline constexpr size_t kProgramKinds = static_cast<size_t>(ProgramKind::kAttribute) + 1;

struct BindlessBuffer {
  TesseraBufferView view;
  unsigned ndims = 0;  // 0: unsized, fits any rtBufferId
};

// A program called by id: its binding with its own scope and the context's, one per kind of
// caller (a callee takes its caller's kind: the calls it may make, the values it sees).
struct BindlessProgram {
  uint64_t id = 0;
  std::array<const BoundProgram*, kProgramKinds> by_kind{};
  // Why it could not be bound; reported when a program calls it, not when the plan is made:
  // an id no program uses must not fail launches.
  absl::Status problem;
};

struct BindlessTable {
  IdIndex buffer_index, program_index;
  std::vector<BindlessBuffer> buffers;
  std::vector<BindlessProgram> programs;
  // The buffers again, as programs read them without a call (TesseraBufferIdTable): entries by
  // id while buffer_index is dense, else none.
  std::vector<TesseraBufferIdEntry> fast_entries;
  TesseraBufferIdTable fast{0, nullptr};
};

// The calling thread's table of buffers by id, read by modules at a fixed offset from the thread
// pointer (TesseraRuntime::buffer_id_table_offset): the plan's once UsePlan ran, else an empty one.
extern __thread const TesseraBufferIdTable* t_buffer_ids __attribute__((tls_model("initial-exec")));

// Fills plan.bindless: a view of every buffer of the replica, and bindings of every program the
// host gave an id (v1::Program.has_id). `add` puts a binding in the plan and binds the callable
// programs it names (plan.cc); it returns the binding's address in the plan.
using AddBinding = std::function<absl::StatusOr<const BoundProgram*>(BoundProgram)>;
void PlanBindless(const Replica& replica, const Scope* context_scope, AttributeLayout& attributes,
                  const AddBinding& add, BindlessTable& table);

// The runtime table's entries (TesseraRuntime::buffer_by_id, buffer_id_index_error,
// callable_id_enter).
const TesseraBufferView* RtBufferById(int id, size_t element_size, unsigned dimensionality);
void* RtBufferIdIndexError(int id, size_t element_size, unsigned long long x, unsigned long long y,
                           unsigned long long z);
void* RtCallableIdEnter(int id, int skippable, TesseraCallFrame* frame);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_BINDLESS_H_
