#include "boundary.h"

#include <atomic>
#include <new>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace tessera::api {
namespace {

struct ThreadError {
  RTresult code = RT_SUCCESS;
  uint64_t sequence = 0;
  const Context* context = nullptr;  // where it was also recorded; compared, never dereferenced
  std::string message;
};

std::atomic<uint64_t> g_error_sequence{0};

ThreadError& ThisThreadError() {
  thread_local ThreadError error;
  return error;
}

const char* Article(Kind kind) { return kind == Kind::kAcceleration ? "an" : "a"; }

}  // namespace

RTresult Fail(const char* fn, Context* context, const std::string& who,
              const absl::Status& status) {
  RTresult code = ToRtResult(status);
  if (code == RT_SUCCESS) code = RT_ERROR_UNKNOWN;
  std::string message = who.empty() ? absl::StrCat(fn, ": ", status.message())
                                    : absl::StrCat(fn, "(", who, "): ", status.message());
  const uint64_t sequence = ++g_error_sequence;
  if (context != nullptr) context->RecordError(code, message, sequence);
  ThreadError& te = ThisThreadError();
  te.code = code;
  te.sequence = sequence;
  te.context = context;
  te.message = std::move(message);
  return code;
}

RTresult FailException(const char* fn, Context* context, const std::string& who) {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return Fail(fn, context, who, RtError(RT_ERROR_MEMORY_ALLOCATION_FAILED, "out of memory"));
  } catch (const std::exception& e) {
    return Fail(fn, context, who,
                RtError(RT_ERROR_UNKNOWN, absl::StrCat("internal error: ", e.what())));
  } catch (...) {
    return Fail(fn, context, who, RtError(RT_ERROR_UNKNOWN, "internal error"));
  }
}

const char* ThreadErrorFor(RTresult code, const Context* context, uint64_t* sequence) {
  const ThreadError& te = ThisThreadError();
  if (te.code != code || te.message.empty()) return nullptr;
  if (te.context != nullptr && te.context != context) return nullptr;
  *sequence = te.sequence;
  return te.message.c_str();
}

absl::Status HandleError(const HandleRegistry::Lookup& lookup, const void* handle, Kind expected,
                         const char* role, Context** error_context) {
  const RTresult code =
      expected == Kind::kContext ? RT_ERROR_INVALID_CONTEXT : RT_ERROR_INVALID_VALUE;
  const std::string what =
      role != nullptr ? std::string(role) : absl::StrCat(KindName(expected), " handle");
  switch (lookup.state) {
    case HandleRegistry::State::kUnknown:
      if (handle == nullptr) return RtError(code, absl::StrCat(what, " is null"));
      return RtError(code, absl::StrFormat("%s %p is not a live Tessera %s", what, handle,
                                           KindName(expected)));
    case HandleRegistry::State::kDestroyed: {
      *error_context = lookup.info.context;
      std::string dead = lookup.info.id != 0
                             ? absl::StrCat(KindName(lookup.info.kind), " #", lookup.info.id)
                             : std::string(KindName(lookup.info.kind));
      if (lookup.info.kind != expected) {
        return RtError(code, absl::StrCat(what, " refers to destroyed ", dead, ", not ",
                                          Article(expected), " ", KindName(expected)));
      }
      return RtError(code, absl::StrCat(what, " refers to destroyed ", dead));
    }
    case HandleRegistry::State::kLive:
      *error_context = lookup.info.context;
      return RtError(code, absl::StrCat(what, " is ", Article(lookup.info.kind), " ",
                                        lookup.object->Describe(), ", not ", Article(expected), " ",
                                        KindName(expected)));
  }
  return RtError(code, what);
}

absl::StatusOr<Object*> AnyArg(const void* handle, Context* context, const char* role,
                               std::initializer_list<Kind> allowed, const char* expected) {
  HandleRegistry::Lookup lookup = HandleRegistry::Get().Find(handle);
  switch (lookup.state) {
    case HandleRegistry::State::kUnknown:
      if (handle == nullptr) return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(role, " is null"));
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrFormat("%s %p is not a live Tessera object", role, handle));
    case HandleRegistry::State::kDestroyed:
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(role, " refers to destroyed ", KindName(lookup.info.kind), " #",
                                  lookup.info.id));
    case HandleRegistry::State::kLive:
      break;
  }
  Object* object = lookup.object;
  bool ok = false;
  for (Kind k : allowed) ok = ok || object->kind() == k;
  if (!ok) {
    return RtError(RT_ERROR_TYPE_MISMATCH,
                   absl::StrCat(role, " is ", Article(object->kind()), " ", object->Describe(),
                                ", expected ", expected));
  }
  if (object->context() != context) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(role, " (", object->Describe(), ") belongs to another context"));
  }
  return object;
}

absl::Status NotNull(const void* pointer, const char* what) {
  if (pointer != nullptr) return absl::OkStatus();
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(what, " is null"));
}

absl::Status CheckIndex(unsigned index, unsigned count, const char* what, const char* counted) {
  if (index < count) return absl::OkStatus();
  return RtError(RT_ERROR_INVALID_VALUE,
                 absl::StrCat(what, " ", index, " is out of range (", count, " ", counted, ")"));
}

}  // namespace tessera::api
