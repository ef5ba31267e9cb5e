// The one boundary every extern "C" function goes through: look up and type-check handles, run
// the body, catch everything, record "rtFn(object): what went wrong" on the context (and the
// calling thread), and return the RTresult. Nothing throws across the boundary and nothing
// aborts on user error.
#ifndef TESSERA_API_SRC_BOUNDARY_H_
#define TESSERA_API_SRC_BOUNDARY_H_

#include <initializer_list>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "context.h"
#include "handle_registry.h"
#include "object.h"
#include "status.h"
#include "tessera/rt.h"

namespace tessera::api {

// Records a failure and returns its RTresult. `context` may be null; `who` names the object.
RTresult Fail(const char* fn, Context* context, const std::string& who, const absl::Status& status);
// The same for an exception caught at the boundary.
RTresult FailException(const char* fn, Context* context, const std::string& who);

// The last message this thread recorded, if it was recorded with `code` and on no context or on
// `context` (else null), and its sequence number: rtContextGetErrorString returns the newer of
// the context's and the thread's.
const char* ThreadErrorFor(RTresult code, const Context* context, uint64_t* sequence);

// Why `handle` is not a usable `expected`; sets `*error_context` to the context the handle
// belongs (or belonged) to, when known.
absl::Status HandleError(const HandleRegistry::Lookup& lookup, const void* handle, Kind expected,
                         const char* role, Context** error_context);

// Resolves the handle a call is about.
template <typename T>
absl::StatusOr<T*> ResolveHandle(const void* handle, Context** error_context) {
  HandleRegistry::Lookup lookup = HandleRegistry::Get().Find(handle);
  if (lookup.state != HandleRegistry::State::kLive || lookup.info.kind != T::kKind) {
    return HandleError(lookup, handle, T::kKind, nullptr, error_context);
  }
  return static_cast<T*>(lookup.object);
}

// Resolves another handle argument of a call on `context` (`role` names it in messages).
template <typename T>
absl::StatusOr<T*> Arg(const void* handle, Context* context, const char* role) {
  HandleRegistry::Lookup lookup = HandleRegistry::Get().Find(handle);
  Context* ignored = nullptr;
  if (lookup.state != HandleRegistry::State::kLive || lookup.info.kind != T::kKind) {
    return HandleError(lookup, handle, T::kKind, role, &ignored);
  }
  if (lookup.object->context() != context) {
    return RtError(RT_ERROR_INVALID_VALUE, std::string(role) + " (" + lookup.object->Describe() +
                                               ") belongs to another context");
  }
  return static_cast<T*>(lookup.object);
}

// Resolves an RTobject argument whose kind must be one of `allowed`; another live kind is
// RT_ERROR_TYPE_MISMATCH ("child is a geometry instance, expected a group, geometry group,
// transform or selector").
absl::StatusOr<Object*> AnyArg(const void* handle, Context* context, const char* role,
                               std::initializer_list<Kind> allowed, const char* expected);

// RT_ERROR_INVALID_VALUE "<what> is null".
absl::Status NotNull(const void* pointer, const char* what);
// RT_ERROR_INVALID_VALUE "<what> <index> is out of range (<count> ...)".
absl::Status CheckIndex(unsigned index, unsigned count, const char* what, const char* counted);

// A call about one object of type T.
template <typename T, typename Body>
RTresult Call(const char* fn, const void* handle, Body&& body) {
  Context* context = nullptr;
  std::string who;
  try {
    absl::StatusOr<T*> resolved = ResolveHandle<T>(handle, &context);
    if (!resolved.ok()) return Fail(fn, context, who, resolved.status());
    T* object = *resolved;
    if (object->context()->InForkedChild()) {
      // gRPC channels and worker processes do not survive fork(): touching them hangs the child
      // (grpc_channel_destroy) or stops the parent's workers.
      return Fail(fn, nullptr, object->Describe(),
                  RtError(RT_ERROR_INVALID_CONTEXT,
                          absl::StrCat("the context was created by process ",
                                       object->context()->creator_pid(),
                                       "; a process forked from it must create its own context")));
    }
    context = object->context();
    // Named before the body runs: rt*Destroy frees the object.
    who = object->Describe();
    absl::Status status = body(*object);
    if (status.ok()) return RT_SUCCESS;
    return Fail(fn, context, who, status);
  } catch (...) {
    return FailException(fn, context, who);
  }
}

// A call that is about no object (rtContextCreate, rtDeviceGetAttribute …).
template <typename Body>
RTresult CallGlobal(const char* fn, Body&& body) {
  try {
    absl::Status status = body();
    if (status.ok()) return RT_SUCCESS;
    return Fail(fn, nullptr, "", status);
  } catch (...) {
    return FailException(fn, nullptr, "");
  }
}

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_BOUNDARY_H_
