// The exception and callable entries of the TesseraOptix7Runtime table: optixThrowException and
// the exception program's getters, optixDirectCall and optixContinuationCall.
#include <cstring>

#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "optix7_thread.h"
#include "optix_types.h"

namespace tessera::worker {
namespace {

// User exceptions are raised whatever OPTIX_EXCEPTION_FLAG_USER says: a program's explicit throw
// dropped silently would hide the error it reports.
void ThrowException(int code, unsigned int num_details, const unsigned int* details) {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  CheckKind(ts, ~KindBit(Optix7Kind::kException), "optixThrowException");
  if (code < 0 || code >= (1 << 30)) {
    Fail(ts, "optixThrowException",
         absl::StrCat("code ", code, ": user exception codes run from 0 to 2^30 - 1"));
  }
  Optix7Exception e;
  e.code = code;
  std::string what = absl::StrCat("user exception ", code);
  for (unsigned i = 0; i < num_details && i < 8; ++i) {
    e.details[i] = details[i];
    absl::StrAppend(&what, i == 0 ? " with details " : ", ", "0x", absl::Hex(details[i]));
  }
  Raise(ts, e, what);
}

const Optix7Exception& ExceptionOf(Optix7Thread& ts, const char* call) {
  CheckKind(ts, KindBit(Optix7Kind::kException), call);
  return ts.exception;
}

int ExceptionCode() { return ExceptionOf(Optix7TS(), "optixGetExceptionCode").code; }

unsigned int ExceptionDetail(unsigned int index) {
  Optix7Thread& ts = Optix7TS();
  const Optix7Exception& e = ExceptionOf(ts, "optixGetExceptionDetail");
  return index < 8 ? e.details[index] : 0;
}

OptixTraversableHandle ExceptionInvalidTraversable() {
  return ExceptionOf(Optix7TS(), "optixGetExceptionInvalidTraversable").invalid_traversable;
}

int ExceptionInvalidSbtOffset() {
  return ExceptionOf(Optix7TS(), "optixGetExceptionInvalidSbtOffset").invalid_sbt_offset;
}

void ExceptionInvalidRay(float out[9]) {
  std::memcpy(out, ExceptionOf(Optix7TS(), "optixGetExceptionInvalidRay").invalid_ray,
              9 * sizeof(float));
}

// Callables are called with the types the caller names (the module's own call), so a mismatch
// is not detected: nothing of a callable's signature is known at run time.
void ExceptionParameterMismatch(TesseraOptix7ParameterMismatch* out) {
  ExceptionOf(Optix7TS(), "optixGetExceptionParameterMismatch");
  *out = TesseraOptix7ParameterMismatch{0, 0, 0, nullptr};
}

char* ExceptionLineInfo() {
  ExceptionOf(Optix7TS(), "optixGetExceptionLineInfo");
  static char none[] = "";
  return none;
}

void* CallableEnter(unsigned int kind, unsigned int sbt_index, TesseraOptix7CallFrame* frame) {
  InterruptPoint();
  Optix7Thread& ts = Optix7TS();
  const bool direct = kind == TESSERA_OPTIX7_DIRECT_CALLABLE;
  if (!direct) {
    CheckKind(ts,
              KindBit(Optix7Kind::kRaygen) | KindBit(Optix7Kind::kClosestHit) |
                  KindBit(Optix7Kind::kMiss) | KindBit(Optix7Kind::kContinuationCallable),
              "optixContinuationCall");
  }
  const char* call = direct ? "optixDirectCall" : "optixContinuationCall";
  Optix7Exception e;
  e.invalid_sbt_offset = static_cast<int>(sbt_index);
  const std::vector<Optix7Record>& records = ts.launch->callables;
  if (sbt_index >= records.size()) {
    e.code = OPTIX_EXCEPTION_CODE_CALLABLE_INVALID_SBT;
    Raise(ts, e,
          absl::StrCat(call, "(", sbt_index, ") past the ", records.size(), " callable records"));
  }
  const Optix7Record& record = records[sbt_index];
  const Optix7Entry& entry = direct ? record.group->entry : record.group->continuation;
  if (entry.function == nullptr) {
    e.code = direct ? OPTIX_EXCEPTION_CODE_CALLABLE_NO_DC_SBT_RECORD
                    : OPTIX_EXCEPTION_CODE_CALLABLE_NO_CC_SBT_RECORD;
    Raise(ts, e,
          absl::StrCat(call, "(", sbt_index, "): callable record ", sbt_index, " (program group ",
                       record.group->id, ") has no ", direct ? "direct" : "continuation",
                       " callable"));
  }
  if (static_cast<const char*>(__builtin_frame_address(0)) < ts.stack_limit) {
    e.code = OPTIX_EXCEPTION_CODE_STACK_OVERFLOW;
    Raise(ts, e, absl::StrCat(call, ": the launch index has used the native stack it may take"));
  }
  frame->caller = reinterpret_cast<void*>(ts.callers.size());
  ts.callers.push_back(ts.ctx);
  // A callable sees its caller's ray and hit (the getters its caller may use), its own record.
  ts.ctx.kind = direct ? Optix7Kind::kDirectCallable : Optix7Kind::kContinuationCallable;
  ts.ctx.record = &record;
  return reinterpret_cast<void*>(entry.function);
}

void CallableLeave(TesseraOptix7CallFrame* frame) {
  Optix7Thread& ts = Optix7TS();
  const auto depth = reinterpret_cast<size_t>(frame->caller);
  // An exception or an any-hit program's end may have dropped the callers already.
  if (depth < ts.callers.size()) {
    ts.ctx = ts.callers[depth];
    ts.callers.resize(depth);
  }
}

}  // namespace

void FillCallsTable(TesseraOptix7Runtime& r) {
  r.throw_exception = &ThrowException;
  r.exception_code = &ExceptionCode;
  r.exception_detail = &ExceptionDetail;
  r.exception_invalid_traversable = &ExceptionInvalidTraversable;
  r.exception_invalid_sbt_offset = &ExceptionInvalidSbtOffset;
  r.exception_invalid_ray = &ExceptionInvalidRay;
  r.exception_parameter_mismatch = &ExceptionParameterMismatch;
  r.exception_line_info = &ExceptionLineInfo;
  r.callable_enter = &CallableEnter;
  r.callable_leave = &CallableLeave;
}

}  // namespace tessera::worker
