#include "bindless.h"

#include <algorithm>
#include <string>

#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "packet_trace.h"
#include "tessera/rt.h"
#include "thread_state.h"

namespace tessera::worker {

void IdIndex::Build(std::vector<std::pair<uint64_t, uint32_t>> entries) {
  uint64_t max_id = 0;
  for (const auto& [id, index] : entries) max_id = std::max(max_id, id);
  // Dense while the array is at most 16 slots per entry (plus room for a small context): object
  // ids count every object the host made, buffers and programs are a share of them.
  sparse_ = max_id > 16 * entries.size() + 4096;
  dense_.clear();
  sorted_.clear();
  if (sparse_) {
    std::sort(entries.begin(), entries.end());
    sorted_ = std::move(entries);
    return;
  }
  dense_.assign(entries.empty() ? 0 : max_id + 1, -1);
  for (const auto& [id, index] : entries) dense_[id] = static_cast<int32_t>(index);
}

long IdIndex::FindSparse(uint64_t id) const {
  auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(id, uint32_t{0}));
  return it != sorted_.end() && it->first == id ? static_cast<long>(it->second) : -1;
}

void PlanBindless(const Replica& replica, const Scope* context_scope, AttributeLayout& attributes,
                  const AddBinding& add, BindlessTable& table) {
  // Every buffer: the device cannot tell which ids the host gave out, and a buffer reached by id
  // is any buffer of the context, as in OptiX.
  std::vector<std::pair<uint64_t, uint32_t>> ids;
  for (const auto& [id, b] : replica.buffers) {
    BindlessBuffer e;
    e.view = {const_cast<unsigned char*>(b.data.data()),
              {b.dims[0], b.dims[1], b.dims[2]},
              b.element_size,
              id,
              nullptr,
              nullptr,
              nullptr};
    if (!b.written.empty()) {  // gathered: the same marks as an rtBuffer's view (binding.cc)
      e.view.written = const_cast<unsigned char*>(b.written.data());
      e.view.written_blocks = const_cast<unsigned char*>(b.written_blocks.data());
      e.view.write_epoch = replica.write_epoch();
    }
    e.ndims = b.ndims;
    ids.emplace_back(id, static_cast<uint32_t>(table.buffers.size()));
    table.buffers.push_back(e);
  }
  table.buffer_index.Build(ids);
  if (table.buffer_index.dense()) {
    for (const auto& [id, index] : ids) {
      if (table.fast_entries.size() <= id) table.fast_entries.resize(id + 1, {nullptr, 0});
      table.fast_entries[id] = {&table.buffers[index].view, table.buffers[index].ndims};
    }
    table.fast = {table.fast_entries.size(), table.fast_entries.data()};
  }

  ids.clear();
  for (const auto& [id, p] : replica.programs) {
    if (!p.has_id) continue;
    BindlessProgram bp;
    bp.id = id;
    for (size_t k = 0; k < kProgramKinds; ++k) {
      // OptiX 6: a bindless callable program looks its variables up in its own scope, then the
      // context's, whoever calls it.
      absl::StatusOr<BoundProgram> b = Bind(replica, static_cast<ProgramKind>(k), id,
                                            {context_scope}, attributes, /*callable=*/true);
      absl::StatusOr<const BoundProgram*> added =
          b.ok() ? add(std::move(*b)) : absl::StatusOr<const BoundProgram*>(b.status());
      if (!added.ok()) {
        bp.problem = added.status();
        bp.by_kind.fill(nullptr);
        break;
      }
      bp.by_kind[k] = *added;
    }
    ids.emplace_back(id, static_cast<uint32_t>(table.programs.size()));
    table.programs.push_back(std::move(bp));
  }
  table.program_index.Build(std::move(ids));
}

namespace {
const TesseraBufferIdTable kNoBufferIds = {0, nullptr};
}  // namespace

__thread const TesseraBufferIdTable* t_buffer_ids __attribute__((tls_model("initial-exec"))) =
    &kNoBufferIds;

namespace {

// What a buffer or program of an id reads as when the id is invalid and the exception is off.
const TesseraBufferView kNoBuffer = {nullptr, {0, 1, 1}, 0, 0, nullptr, nullptr, nullptr};

const char* Caller(const ThreadState& ts) {
  return ts.current != nullptr ? ts.current->name.c_str() : "a program";
}

std::string WhyInvalid(const ThreadState& ts, int id, bool program) {
  if (id == 0) return program ? "RT_PROGRAM_ID_NULL" : "RT_BUFFER_ID_NULL";
  if (program && id > 0 && ts.plan->replica->programs.count(static_cast<uint64_t>(id)) != 0) {
    return absl::StrCat("program #", id, " was never given an id with rtProgramGetId");
  }
  return absl::StrCat("no ", program ? "program" : "buffer", " of the context has that id");
}

__attribute__((noinline, cold)) const TesseraBufferView* InvalidBufferId(ThreadState& ts, int id) {
  Raise(RT_EXCEPTION_BUFFER_ID_INVALID,
        absl::StrCat("buffer id ", id, " in ", Caller(ts), " (", WhyInvalid(ts, id, false), ")"));
  return &kNoBuffer;  // disabled: an empty buffer (bindless.h)
}

[[noreturn]] __attribute__((noinline, cold)) void BufferMismatch(const ThreadState& ts, int id,
                                                                 const BindlessBuffer& b,
                                                                 size_t element_size,
                                                                 unsigned dimensionality) {
  throw FatalError{absl::InvalidArgumentError(
      absl::StrCat(Caller(ts), ": an rtBufferId of ", dimensionality, "D elements of ",
                   element_size, " bytes reaches buffer #", id, ", which is ", b.ndims,
                   "D with elements of ", b.view.element_size, " bytes"))};
}

}  // namespace

const TesseraBufferView* RtBufferById(int id, size_t element_size, unsigned dimensionality) {
  InterruptPoint();
  ThreadState& ts = TS();
  EndCollectingIfAny(ts);  // an effect: the collecting lane traces alone
  const BindlessTable& t = ts.plan->bindless;
  const long k = t.buffer_index.Find(id);
  if (__builtin_expect(k < 0, 0)) return InvalidBufferId(ts, id);
  const BindlessBuffer& b = t.buffers[static_cast<size_t>(k)];
  if (__builtin_expect(
          b.view.element_size != element_size || (b.ndims != 0 && b.ndims != dimensionality), 0)) {
    BufferMismatch(ts, id, b, element_size, dimensionality);
  }
  return &b.view;
}

void* RtBufferIdIndexError(int id, size_t element_size, unsigned long long x, unsigned long long y,
                           unsigned long long z) {
  InterruptPoint();
  ThreadState& ts = TS();
  const BindlessTable& t = ts.plan->bindless;
  // An invalid id's empty view was raised (or let through) when the id was resolved.
  if (const long k = t.buffer_index.Find(id); k >= 0) {
    const TesseraBufferView& v = t.buffers[static_cast<size_t>(k)].view;
    Raise(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS,
          absl::StrCat("buffer #", id, " (by id) index (", x, ", ", y, ", ", z, ") outside size (",
                       v.size[0], ", ", v.size[1], ", ", v.size[2], ") in ", Caller(ts)));
  }
  // Disabled: reads see zeros and writes land in scratch memory.
  ts.scratch.assign(std::max<size_t>(element_size, 64), 0);
  return ts.scratch.data();
}

void* RtCallableIdEnter(int id, int skippable, TesseraCallFrame* frame) {
  InterruptPoint();
  ThreadState& ts = TS();
  EndCollectingIfAny(ts);  // an effect: the collecting lane traces alone
  const BindlessTable& t = ts.plan->bindless;
  const long k = t.program_index.Find(id);
  if (__builtin_expect(k < 0, 0)) {
    const std::string what = absl::StrCat("rtCallableProgramId ", id, " called from ", Caller(ts),
                                          " (", WhyInvalid(ts, id, true), ")");
    Raise(RT_EXCEPTION_PROGRAM_ID_INVALID, what);
    if (skippable) return nullptr;  // disabled: the call returns R() (bindless.h)
    throw FatalError{absl::InvalidArgumentError(absl::StrCat(
        what,
        ": RT_EXCEPTION_PROGRAM_ID_INVALID is disabled, and the call cannot be skipped "
        "since its return type has no default value"))};
  }
  const BindlessProgram& p = t.programs[static_cast<size_t>(k)];
  const BoundProgram* callee = p.by_kind[static_cast<size_t>(ts.kind)];
  if (__builtin_expect(callee == nullptr, 0)) {
    throw FatalError{
        absl::Status(p.problem.code(), absl::StrCat("rtCallableProgramId ", id, " called from ",
                                                    Caller(ts), ": ", p.problem.message()))};
  }
  return EnterCallee(ts, *callee, frame);
}

}  // namespace tessera::worker
