// rtProgram*: programs from modules or C++ source.
#include <climits>

#include "boundary.h"
#include "context.h"
#include "program.h"
#include "program_loader.h"
#include "scope_api.h"
#include "tessera/accuracy.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {
// Source the context compiles gets fast math with TESSERA_ACCURACY_FAST_MATH (docs/fast_math.md).
bool FastMath(const Context& c) { return (c.accuracy_flags() & TESSERA_ACCURACY_FAST_MATH) != 0; }
}  // namespace

extern "C" {

RTresult rtProgramCreateFromPTXFile(RTcontext context, const char* filename,
                                    const char* program_name, RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(filename, "file name"));
    TS_RETURN_IF_ERROR(NotNull(program_name, "program name"));
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_ASSIGN_OR_RETURN(ModuleRef module, LoadProgramFile(filename, program_name, FastMath(c)));
    *program = ToHandle<RTprogram>(c.Make<Program>(std::move(module.path), std::move(module.hash),
                                                   std::move(module.bytes), program_name));
    return absl::OkStatus();
  });
}

RTresult rtProgramCreateFromPTXString(RTcontext context, const char* ptx, const char* program_name,
                                      RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(ptx, "source string"));
    TS_RETURN_IF_ERROR(NotNull(program_name, "program name"));
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_ASSIGN_OR_RETURN(ModuleRef module, LoadProgramSource(ptx, program_name, FastMath(c)));
    *program = ToHandle<RTprogram>(c.Make<Program>(std::move(module.path), std::move(module.hash),
                                                   std::move(module.bytes), program_name));
    return absl::OkStatus();
  });
}

RTresult rtProgramDestroy(RTprogram program) { return DestroyCall<Program>(__func__, program); }

RTresult rtProgramValidate(RTprogram program) {
  return Call<Program>(__func__, program, [&](Program& p) { return ValidateObject(p); });
}

RTresult rtProgramGetContext(RTprogram program, RTcontext* context) {
  return GetContextCall<Program>(__func__, program, context);
}

RTresult rtProgramDeclareVariable(RTprogram program, const char* name, RTvariable* v) {
  return ScopeDeclare<Program>(__func__, program, name, v);
}
RTresult rtProgramQueryVariable(RTprogram program, const char* name, RTvariable* v) {
  return ScopeQuery<Program>(__func__, program, name, v);
}
RTresult rtProgramRemoveVariable(RTprogram program, RTvariable v) {
  return ScopeRemove<Program>(__func__, program, v);
}
RTresult rtProgramGetVariableCount(RTprogram program, unsigned int* count) {
  return ScopeCount<Program>(__func__, program, count);
}
RTresult rtProgramGetVariable(RTprogram program, unsigned int index, RTvariable* v) {
  return ScopeGet<Program>(__func__, program, index, v);
}

RTresult rtProgramGetId(RTprogram program, int* program_id) {
  return Call<Program>(__func__, program, [&](Program& p) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program_id, "id pointer"));
    // The program id is its object id, so ids in buffers and variables resolve on devices.
    if (p.id() > static_cast<uint64_t>(INT_MAX)) {
      return RtError(RT_ERROR_INVALID_VALUE, "program id does not fit in an int");
    }
    *program_id = static_cast<int>(p.id());
    if (!p.id_taken()) {
      p.NoteIdTaken();
      p.Touch();                                // travels again, marked as called by id
      p.context()->NoteProgramIdTaken(p.id());  // reaches devices with no variable naming it
    }
    return absl::OkStatus();
  });
}

}  // extern "C"
