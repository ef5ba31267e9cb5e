// The five variable functions every scope object has (rt<Scope>DeclareVariable, Query, Remove,
// GetVariableCount, GetVariable), written once for all six scope kinds.
#ifndef TESSERA_API_SRC_SCOPE_API_H_
#define TESSERA_API_SRC_SCOPE_API_H_

#include "boundary.h"
#include "variable_scope.h"

namespace tessera::api {

template <typename T>
RTresult ScopeDeclare(const char* fn, const void* handle, const char* name, RTvariable* v) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(name, "variable name"));
    TS_RETURN_IF_ERROR(NotNull(v, "variable pointer"));
    TS_ASSIGN_OR_RETURN(Variable * variable, o.scope()->Declare(name));
    *v = ToHandle<RTvariable>(variable);
    return absl::OkStatus();
  });
}

// As in OptiX, an unknown name is not an error: *v becomes null.
template <typename T>
RTresult ScopeQuery(const char* fn, const void* handle, const char* name, RTvariable* v) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(name, "variable name"));
    TS_RETURN_IF_ERROR(NotNull(v, "variable pointer"));
    *v = ToHandle<RTvariable>(o.scope()->Query(name));
    return absl::OkStatus();
  });
}

template <typename T>
RTresult ScopeRemove(const char* fn, const void* handle, RTvariable v) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Variable * variable, Arg<Variable>(v, o.context(), "variable"));
    return o.scope()->Remove(variable);
  });
}

template <typename T>
RTresult ScopeCount(const char* fn, const void* handle, unsigned int* count) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = static_cast<unsigned>(o.scope()->count());
    return absl::OkStatus();
  });
}

template <typename T>
RTresult ScopeGet(const char* fn, const void* handle, unsigned int index, RTvariable* v) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(v, "variable pointer"));
    TS_ASSIGN_OR_RETURN(Variable * variable, o.scope()->At(index));
    *v = ToHandle<RTvariable>(variable);
    return absl::OkStatus();
  });
}

// Destroys an object of type T (rt<Kind>Destroy).
template <typename T>
RTresult DestroyCall(const char* fn, const void* handle) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    o.context()->DestroyObject(&o);
    return absl::OkStatus();
  });
}

// rt<Kind>GetContext.
template <typename T>
RTresult GetContextCall(const char* fn, const void* handle, RTcontext* context) {
  return Call<T>(fn, handle, [&](T& o) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(context, "context pointer"));
    *context = ToHandle<RTcontext>(o.context());
    return absl::OkStatus();
  });
}

// rt<Kind>Create: `make` builds the object on the context.
template <typename H, typename Make>
RTresult CreateCall(const char* fn, RTcontext context, H* out, Make&& make) {
  return Call<Context>(fn, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(out, "output handle pointer"));
    *out = ToHandle<H>(make(c));
    return absl::OkStatus();
  });
}

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_SCOPE_API_H_
