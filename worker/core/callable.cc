// OptiX 3.0 callable programs: an rtCallableProgram variable's call runs the program it names as
// if it were its caller (the calls it may make, the semantic values it sees), with its own
// variables bound through its own scope and then its caller's (plan.cc, CallableBinder).
#include <cstring>
#include <exception>

#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "packet_trace.h"
#include "tessera/rt.h"
#include "thread_state.h"

namespace tessera::worker {
namespace {

const BoundProgram::SlotRef* OfSize(const std::vector<BoundProgram::SlotRef>& refs, size_t size) {
  for (const BoundProgram::SlotRef& r : refs) {
    if (r.size == size) return &r;
  }
  return nullptr;
}

const BoundProgram::Attribute* SameAttribute(const BoundProgram& p,
                                             const BoundProgram::Attribute& a) {
  for (const BoundProgram::Attribute& b : p.attributes) {
    if (b.offset == a.offset) return &b;
  }
  return nullptr;
}

bool HasPayload(ProgramKind k) {
  return k == ProgramKind::kClosestHit || k == ProgramKind::kAnyHit || k == ProgramKind::kMiss ||
         k == ProgramKind::kVisit;
}

// Where the engine keeps the running program's semantic values, for a caller that declares no
// variable of its own for one (Table 4 says which kinds have which).
const RayData* EngineRay(ThreadState& ts) {
  switch (ts.kind) {
    case ProgramKind::kClosestHit:
    case ProgramKind::kMiss:
      return &ts.top().ray;
    case ProgramKind::kIntersection:
      return &ts.is.ray;
    case ProgramKind::kVisit:
      return &ts.visits.back().ray;
    case ProgramKind::kAnyHit:
    case ProgramKind::kAttribute:
      return ts.object_ray;
    default:
      return nullptr;
  }
}
const float* EngineDistance(ThreadState& ts) {
  if (ts.kind == ProgramKind::kIntersection || ts.kind == ProgramKind::kVisit) {
    return &ts.top().hit.t;
  }
  const Hit* h = HitOf(ts);
  return h == nullptr ? nullptr : &h->t;
}

// A callable program of another module than its caller's sees the caller's ray, distance, payload
// and attributes: from the caller's variables where it declares them, else from the engine.
void ShareIn(ThreadState& ts, const BoundProgram& caller, const ModuleState& from,
             const BoundProgram& callee, const ModuleState& to) {
  if (!callee.ray.empty()) {
    const BoundProgram::SlotRef* r = OfSize(caller.ray, sizeof(RayData));
    const RayData* ray = r ? static_cast<const RayData*>(from.slots[r->var]) : EngineRay(ts);
    if (ray != nullptr) WriteRaySlots(to, callee.ray, *ray);
  }
  if (!callee.distance.empty()) {
    const BoundProgram::SlotRef* r = OfSize(caller.distance, sizeof(float));
    const float* t = r ? static_cast<const float*>(from.slots[r->var]) : EngineDistance(ts);
    if (t != nullptr) WriteSlots<sizeof(float)>(to, callee.distance, t);
  }
  if (!callee.payload.empty() && HasPayload(ts.kind)) {
    const Frame& f = ts.top();
    const BoundProgram::SlotRef* r = OfSize(caller.payload, f.payload_size);
    WriteSlots(to, callee.payload, r ? from.slots[r->var] : f.payload, f.payload_size);
  }
  const Hit* hit = HitOf(ts);
  for (const BoundProgram::Attribute& a : callee.attributes) {
    if (const BoundProgram::Attribute* c = SameAttribute(caller, a)) {
      CopyBytes(to.slots[a.var], from.slots[c->var], a.size);
    } else if (hit != nullptr) {
      CopyBytes(to.slots[a.var], hit->attributes + a.offset, a.size);
    }
  }
}

// And what it writes of them reaches the caller: the payload, and attributes where the caller
// may write them (intersection and attribute programs).
void ShareOut(ThreadState& ts, const BoundProgram& caller, const ModuleState& from,
              const BoundProgram& callee, const ModuleState& to) {
  if (HasPayload(ts.kind)) {
    Frame& f = ts.top();
    if (const BoundProgram::SlotRef* mine = OfSize(callee.payload, f.payload_size)) {
      const BoundProgram::SlotRef* r = OfSize(caller.payload, f.payload_size);
      CopyWords(r ? from.slots[r->var] : f.payload, to.slots[mine->var], f.payload_size);
    }
  }
  if (ts.kind != ProgramKind::kIntersection && ts.kind != ProgramKind::kAttribute) return;
  for (const BoundProgram::Attribute& a : callee.attributes) {
    if (const BoundProgram::Attribute* c = SameAttribute(caller, a)) {
      CopyBytes(from.slots[c->var], to.slots[a.var], a.size);
    } else if (ts.kind == ProgramKind::kAttribute) {
      CopyBytes(ts.attribute_hit->attributes + a.offset, to.slots[a.var], a.size);
    }
  }
}

// The scopes a program of kind `k` searches after its own (Table 5), for messages.
const char* OuterScopes(ProgramKind k) {
  switch (k) {
    case ProgramKind::kClosestHit:
    case ProgramKind::kAnyHit:
      return "its geometry instance, its material or the context";
    case ProgramKind::kIntersection:
    case ProgramKind::kBoundingBox:
    case ProgramKind::kAttribute:
      return "its geometry instance, its geometry or the context";
    case ProgramKind::kVisit:
      return "its selector (visit programs do not search the context)";
    default:
      return "the context";
  }
}

[[noreturn]] __attribute__((noinline, cold)) void NotSet(const ThreadState& ts,
                                                         const void* variable) {
  std::string name = "?";
  const auto& vars = ts.current->module->variables();
  for (unsigned i = 0; i < vars.size(); ++i) {
    if (ts.current_module->slots[i] == variable) name = vars[i].name;
  }
  throw FatalError{absl::FailedPreconditionError(
      absl::StrCat("rtCallableProgram '", name, "' called from ", ts.current->name,
                   ": no scope sets it (set it with rtVariableSetObject to a program made from an "
                   "RT_CALLABLE_PROGRAM, on the program or ",
                   OuterScopes(ts.kind), ")"))};
}

[[noreturn]] __attribute__((noinline, cold)) void TooDeep(const ThreadState& ts,
                                                          const BoundProgram& callee) {
  std::string what = absl::StrCat(callee.name, " called from ", ts.current->name,
                                  ": the launch index has used the ", kNativeStackBudget / 1024,
                                  " KiB of native stack it may take for nested calls (callable "
                                  "programs calling each other without end?)");
  Raise(RT_EXCEPTION_STACK_OVERFLOW, what);
  // Disabled: the call cannot be skipped, since it returns a value.
  throw FatalError{absl::ResourceExhaustedError(what)};
}

}  // namespace

void* RtCallableEnter(const void* variable, TesseraCallFrame* frame) {
  InterruptPoint();
  ThreadState& ts = TS();
  EndCollectingIfAny(ts);  // an effect: the collecting lane traces alone
  const BoundProgram* callee;
  std::memcpy(&callee, variable, sizeof(callee));
  if (__builtin_expect(callee == nullptr, 0)) NotSet(ts, variable);
  return EnterCallee(ts, *callee, frame);
}

void* EnterCallee(ThreadState& ts, const BoundProgram& callee_binding, TesseraCallFrame* frame) {
  const BoundProgram* callee = &callee_binding;
  if (__builtin_expect(static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit, 0)) {
    TooDeep(ts, *callee);
  }
  const BoundProgram& caller = *ts.current;
  ModuleState& from = *ts.current_module;
  frame->caller = &caller;
  frame->caller_module = &from;
  frame->suspended = nullptr;
  if (callee->module != caller.module) {
    // The callee may trace, and programs of the caller's module then run: they must save the
    // caller's values first, as for a caller of rtTrace. (A callee of the caller's own module
    // shares those values, and its own rtTrace suspends them.)
    const size_t level = ts.calls.size();
    while (ts.call_suspended.size() <= level) ts.call_suspended.emplace_back();
    frame->suspended = &SuspendInto(ts, ts.call_suspended[level]);
  }
  ts.calls.push_back(frame);
  Enter(ts, *callee);
  if (callee->module != caller.module) ShareIn(ts, caller, from, *callee, *ts.current_module);
  return callee->function;
}

namespace {
// Makes the caller of `frame` run again; `share`: copy back what the callee wrote of its
// caller's values (not while an exception unwinds the call: the running program may then be
// one the callee called, and the launch index ends anyway).
void Leave(ThreadState& ts, TesseraCallFrame& frame, bool share) {
  const auto& caller = *static_cast<const BoundProgram*>(frame.caller);
  auto& from = *static_cast<ModuleState*>(frame.caller_module);
  const BoundProgram& callee = *ts.current;
  ModuleState& to = *ts.current_module;
  if (!ts.calls.empty() && ts.calls.back() == &frame) ts.calls.pop_back();
  if (frame.suspended != nullptr) Resume(ts, *static_cast<SuspendedSlots*>(frame.suspended));
  if (share && callee.module != caller.module) ShareOut(ts, caller, from, callee, to);
  ReturnTo(ts, caller, from);
  if (from.loaded != &caller) Apply(from, caller);  // the callee shares the caller's module
}
}  // namespace

void RtCallableLeave(TesseraCallFrame* frame) {
  InterruptPoint();
  ThreadState& ts = TS();
  Leave(ts, *frame, std::uncaught_exceptions() == 0);
}

void EndAnyHitCalls(ThreadState& ts) {
  while (ts.calls.size() > ts.ah_calls) Leave(ts, *ts.calls.back(), true);
}

}  // namespace tessera::worker
