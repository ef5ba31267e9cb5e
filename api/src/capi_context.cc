// rt* global functions and the context: creation, errors, global state, validation, launch.
#include <vector>

#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "device_table.h"
#include "program.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

RTresult LaunchCall(const char* fn, RTcontext context, unsigned entry, std::vector<uint64_t> dims) {
  return Call<Context>(fn, context, [&](Context& c) { return c.Launch(entry, dims); });
}

}  // namespace

extern "C" {

RTresult rtGetVersion(unsigned int* version) {
  return CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(version, "version pointer"));
    *version = OPTIX_VERSION;
    return absl::OkStatus();
  });
}

RTresult rtDeviceGetDeviceCount(unsigned int* count) {
  return CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    TS_ASSIGN_OR_RETURN(std::vector<DeviceDesc> devices, GlobalDevices());
    *count = static_cast<unsigned>(devices.size());
    return absl::OkStatus();
  });
}

RTresult rtDeviceGetAttribute(int ordinal, RTdeviceattribute attrib, RTsize size, void* p) {
  return CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(p, "attribute pointer"));
    TS_ASSIGN_OR_RETURN(DeviceDesc device, GlobalDevice(ordinal));
    return GetDeviceAttribute(device, attrib, size, p);
  });
}

RTresult rtContextCreate(RTcontext* context) {
  return CallGlobal(__func__, [&]() -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(context, "context pointer"));
    TS_ASSIGN_OR_RETURN(Context * created, Context::Create());
    *context = ToHandle<RTcontext>(created);
    return absl::OkStatus();
  });
}

RTresult rtContextDestroy(RTcontext context) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (!c.TryStartRunning()) {  // held until the context is gone: no launch starts meanwhile
      return RtError(RT_ERROR_INVALID_CONTEXT, "cannot destroy a context while it launches");
    }
    c.DestroyAll();
    return absl::OkStatus();
  });
}

void rtContextGetErrorString(RTcontext context, RTresult code, const char** return_string) {
  if (return_string == nullptr) return;
  try {
    const char* message = nullptr;
    uint64_t context_sequence = 0;
    const Context* live = nullptr;
    HandleRegistry::Lookup lookup = HandleRegistry::Get().Find(context);
    if (lookup.state == HandleRegistry::State::kLive && lookup.info.kind == Kind::kContext) {
      live = static_cast<Context*>(lookup.object);
      message = live->LastErrorFor(code, &context_sequence);
    }
    // Errors that could not be tied to a context (null or destroyed handles, rtContextCreate)
    // are kept per thread; the newer message wins.
    uint64_t thread_sequence = 0;
    const char* thread_message = ThreadErrorFor(code, live, &thread_sequence);
    if (thread_message != nullptr && (message == nullptr || thread_sequence > context_sequence)) {
      message = thread_message;
    }
    *return_string = message != nullptr ? message : ResultText(code);
  } catch (...) {
    *return_string = ResultText(code);
  }
}

RTresult rtContextValidate(RTcontext context) {
  return Call<Context>(__func__, context, [&](Context& c) { return ValidateContext(c); });
}

RTresult rtContextCompile(RTcontext context) {
  // Programs are compiled when created; compiling a context is validating it.
  return Call<Context>(__func__, context, [&](Context& c) { return ValidateContext(c); });
}

RTresult rtContextSetAttribute(RTcontext context, RTcontextattribute attrib, RTsize size, void* p) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(p, "attribute pointer"));
    return c.SetAttribute(attrib, size, p);
  });
}

RTresult rtContextGetAttribute(RTcontext context, RTcontextattribute attrib, RTsize size, void* p) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(p, "attribute pointer"));
    return c.GetAttribute(attrib, size, p);
  });
}

RTresult rtContextSetDevices(RTcontext context, unsigned int count, const int* devices) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(devices, "device list"));
    return c.SetDevices(std::vector<int>(devices, devices + count));
  });
}

RTresult rtContextGetDevices(RTcontext context, int* devices) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(devices, "device list"));
    for (size_t i = 0; i < c.selected_devices().size(); ++i) devices[i] = c.selected_devices()[i];
    return absl::OkStatus();
  });
}

RTresult rtContextGetDeviceCount(RTcontext context, unsigned int* count) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = static_cast<unsigned>(c.selected_devices().size());
    return absl::OkStatus();
  });
}

RTresult rtContextSetStackSize(RTcontext context, RTsize stack_size_bytes) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.SetStackSize(stack_size_bytes);
    return absl::OkStatus();
  });
}

RTresult rtContextGetStackSize(RTcontext context, RTsize* stack_size_bytes) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(stack_size_bytes, "stack size pointer"));
    *stack_size_bytes = c.stack_size();
    return absl::OkStatus();
  });
}

RTresult rtContextSetTimeoutCallback(RTcontext context, RTtimeoutcallback callback,
                                     double min_polling_seconds) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (!(min_polling_seconds >= 0.0)) {
      return RtError(RT_ERROR_INVALID_VALUE, "polling interval must be a non-negative number");
    }
    c.SetTimeoutCallback(callback, min_polling_seconds);
    return absl::OkStatus();
  });
}

RTresult rtContextSetEntryPointCount(RTcontext context, unsigned int num_entry_points) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.SetEntryPointCount(num_entry_points);
    return absl::OkStatus();
  });
}

RTresult rtContextGetEntryPointCount(RTcontext context, unsigned int* num_entry_points) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(num_entry_points, "count pointer"));
    *num_entry_points = c.entry_point_count();
    return absl::OkStatus();
  });
}

RTresult rtContextSetRayGenerationProgram(RTcontext context, unsigned int entry_point_index,
                                          RTprogram program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, &c, "program"));
    TS_RETURN_IF_ERROR(
        CheckIndex(entry_point_index, c.entry_point_count(), "entry point", "entry points"));
    c.SetRayGeneration(entry_point_index, p);
    return absl::OkStatus();
  });
}

RTresult rtContextGetRayGenerationProgram(RTcontext context, unsigned int entry_point_index,
                                          RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_RETURN_IF_ERROR(
        CheckIndex(entry_point_index, c.entry_point_count(), "entry point", "entry points"));
    *program = ToHandle<RTprogram>(c.ray_generation(entry_point_index));
    return absl::OkStatus();
  });
}

RTresult rtContextSetExceptionProgram(RTcontext context, unsigned int entry_point_index,
                                      RTprogram program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, &c, "program"));
    TS_RETURN_IF_ERROR(
        CheckIndex(entry_point_index, c.entry_point_count(), "entry point", "entry points"));
    c.SetExceptionProgram(entry_point_index, p);
    return absl::OkStatus();
  });
}

RTresult rtContextGetExceptionProgram(RTcontext context, unsigned int entry_point_index,
                                      RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_RETURN_IF_ERROR(
        CheckIndex(entry_point_index, c.entry_point_count(), "entry point", "entry points"));
    *program = ToHandle<RTprogram>(c.exception_program(entry_point_index));
    return absl::OkStatus();
  });
}

RTresult rtContextSetExceptionEnabled(RTcontext context, RTexception exception, int enabled) {
  return Call<Context>(__func__, context,
                       [&](Context& c) { return c.SetExceptionEnabled(exception, enabled != 0); });
}

RTresult rtContextGetExceptionEnabled(RTcontext context, RTexception exception, int* enabled) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(enabled, "enabled pointer"));
    TS_ASSIGN_OR_RETURN(bool on, c.ExceptionEnabled(exception));
    *enabled = on ? 1 : 0;
    return absl::OkStatus();
  });
}

RTresult rtContextSetRayTypeCount(RTcontext context, unsigned int num_ray_types) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.SetRayTypeCount(num_ray_types);
    return absl::OkStatus();
  });
}

RTresult rtContextGetRayTypeCount(RTcontext context, unsigned int* num_ray_types) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(num_ray_types, "count pointer"));
    *num_ray_types = c.ray_type_count();
    return absl::OkStatus();
  });
}

RTresult rtContextSetMissProgram(RTcontext context, unsigned int ray_type_index,
                                 RTprogram program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, &c, "program"));
    TS_RETURN_IF_ERROR(CheckIndex(ray_type_index, c.ray_type_count(), "ray type", "ray types"));
    c.SetMiss(ray_type_index, p);
    return absl::OkStatus();
  });
}

RTresult rtContextGetMissProgram(RTcontext context, unsigned int ray_type_index,
                                 RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_RETURN_IF_ERROR(CheckIndex(ray_type_index, c.ray_type_count(), "ray type", "ray types"));
    *program = ToHandle<RTprogram>(c.miss(ray_type_index));
    return absl::OkStatus();
  });
}

RTresult rtContextLaunch1D(RTcontext context, unsigned int entry_point_index, RTsize image_width) {
  return LaunchCall(__func__, context, entry_point_index, {image_width});
}

RTresult rtContextLaunch2D(RTcontext context, unsigned int entry_point_index, RTsize image_width,
                           RTsize image_height) {
  return LaunchCall(__func__, context, entry_point_index, {image_width, image_height});
}

RTresult rtContextLaunch3D(RTcontext context, unsigned int entry_point_index, RTsize image_width,
                           RTsize image_height, RTsize image_depth) {
  return LaunchCall(__func__, context, entry_point_index, {image_width, image_height, image_depth});
}

RTresult rtContextGetRunningState(RTcontext context, int* running) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(running, "running pointer"));
    *running = c.running() ? 1 : 0;
    return absl::OkStatus();
  });
}

RTresult rtContextSetPrintEnabled(RTcontext context, int enabled) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.SetPrintEnabled(enabled != 0);
    return absl::OkStatus();
  });
}

RTresult rtContextGetPrintEnabled(RTcontext context, int* enabled) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(enabled, "enabled pointer"));
    *enabled = c.print_enabled() ? 1 : 0;
    return absl::OkStatus();
  });
}

RTresult rtContextSetPrintBufferSize(RTcontext context, RTsize buffer_size_bytes) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.SetPrintBufferSize(buffer_size_bytes);
    return absl::OkStatus();
  });
}

RTresult rtContextGetPrintBufferSize(RTcontext context, RTsize* buffer_size_bytes) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer_size_bytes, "size pointer"));
    *buffer_size_bytes = c.print_buffer_size();
    return absl::OkStatus();
  });
}

RTresult rtContextSetPrintLaunchIndex(RTcontext context, int x, int y, int z) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    if (x < -1 || y < -1 || z < -1) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     "print launch index components must be >= 0, or -1 for all");
    }
    c.SetPrintLaunchIndex(x, y, z);
    return absl::OkStatus();
  });
}

RTresult rtContextGetPrintLaunchIndex(RTcontext context, int* x, int* y, int* z) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    // OptiX lets callers ask for some components only.
    if (x == nullptr && y == nullptr && z == nullptr) {
      return RtError(RT_ERROR_INVALID_VALUE, "all index pointers are null");
    }
    if (x != nullptr) *x = c.print_launch_index()[0];
    if (y != nullptr) *y = c.print_launch_index()[1];
    if (z != nullptr) *z = c.print_launch_index()[2];
    return absl::OkStatus();
  });
}

RTresult rtContextGetBufferFromId(RTcontext context, int buffer_id, RTbuffer* buffer) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer, "buffer pointer"));
    Object* object = buffer_id > 0 ? c.FindById(static_cast<uint64_t>(buffer_id)) : nullptr;
    if (object == nullptr || object->kind() != Kind::kBuffer) {
      return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("no live buffer has id ", buffer_id));
    }
    *buffer = ToHandle<RTbuffer>(object);
    return absl::OkStatus();
  });
}

RTresult rtContextGetProgramFromId(RTcontext context, int program_id, RTprogram* program) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    Object* object = program_id > 0 ? c.FindById(static_cast<uint64_t>(program_id)) : nullptr;
    if (object == nullptr || object->kind() != Kind::kProgram) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("no live program has id ", program_id,
                                  " (ids come from rtProgramGetId; RT_PROGRAM_ID_NULL is 0)"));
    }
    *program = ToHandle<RTprogram>(object);
    return absl::OkStatus();
  });
}

}  // extern "C"
