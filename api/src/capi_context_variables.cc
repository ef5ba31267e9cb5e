// Context variables and rt*Validate for single objects.
#include "boundary.h"
#include "scope_api.h"

using namespace tessera::api;  // NOLINT: C entry points only

extern "C" {

RTresult rtContextDeclareVariable(RTcontext context, const char* name, RTvariable* v) {
  return ScopeDeclare<Context>(__func__, context, name, v);
}
RTresult rtContextQueryVariable(RTcontext context, const char* name, RTvariable* v) {
  return ScopeQuery<Context>(__func__, context, name, v);
}
RTresult rtContextRemoveVariable(RTcontext context, RTvariable v) {
  return ScopeRemove<Context>(__func__, context, v);
}
RTresult rtContextGetVariableCount(RTcontext context, unsigned int* count) {
  return ScopeCount<Context>(__func__, context, count);
}
RTresult rtContextGetVariable(RTcontext context, unsigned int index, RTvariable* v) {
  return ScopeGet<Context>(__func__, context, index, v);
}

}  // extern "C"
