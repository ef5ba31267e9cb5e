// rtBuffer*.
#include <climits>

#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "buffer.h"
#include "context.h"
#include "scope_api.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

template <typename Body>
RTresult BufferCall(const char* fn, RTbuffer buffer, Body&& body) {
  return Call<Buffer>(fn, buffer, std::forward<Body>(body));
}

// Device pointers name a device the context runs on.
absl::Status CheckDeviceNumber(const Buffer& b, unsigned number) {
  for (const DeviceSlot& slot : b.context()->device_slots()) {
    if (slot.sync.ordinal == static_cast<int>(number)) return absl::OkStatus();
  }
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("device number ", number,
                                                      " is not one of the devices the context "
                                                      "runs on (rtContextSetDevices)"));
}

}  // namespace

extern "C" {

RTresult rtBufferCreateForCUDA(RTcontext context, unsigned int bufferdesc, RTbuffer* buffer) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer, "buffer pointer"));
    TS_RETURN_IF_ERROR(Buffer::CheckDesc(bufferdesc));
    Buffer* b = c.Make<Buffer>(bufferdesc);
    b->set_for_cuda();
    *buffer = ToHandle<RTbuffer>(b);
    return absl::OkStatus();
  });
}

RTresult rtBufferGetDevicePointer(RTbuffer buffer, unsigned int optix_device_number,
                                  void** device_pointer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(device_pointer, "device pointer"));
    TS_RETURN_IF_ERROR(CheckDeviceNumber(b, optix_device_number));
    auto p = b.GetDevicePointer(static_cast<int>(optix_device_number));
    if (!p.ok()) return p.status();
    *device_pointer = *p;
    return absl::OkStatus();
  });
}

RTresult rtBufferSetDevicePointer(RTbuffer buffer, unsigned int optix_device_number,
                                  void* device_pointer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(device_pointer, "device pointer"));
    TS_RETURN_IF_ERROR(CheckDeviceNumber(b, optix_device_number));
    return b.SetDevicePointer(static_cast<int>(optix_device_number), device_pointer);
  });
}

RTresult rtBufferCreate(RTcontext context, unsigned int bufferdesc, RTbuffer* buffer) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer, "buffer pointer"));
    TS_RETURN_IF_ERROR(Buffer::CheckDesc(bufferdesc));
    *buffer = ToHandle<RTbuffer>(c.Make<Buffer>(bufferdesc));
    return absl::OkStatus();
  });
}

RTresult rtBufferDestroy(RTbuffer buffer) { return DestroyCall<Buffer>(__func__, buffer); }

RTresult rtBufferValidate(RTbuffer buffer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return ValidateObject(b); });
}

RTresult rtBufferGetContext(RTbuffer buffer, RTcontext* context) {
  return GetContextCall<Buffer>(__func__, buffer, context);
}

RTresult rtBufferSetFormat(RTbuffer buffer, RTformat format) {
  // A C caller may pass any int as an RTformat, but C++ reads a value past the enum's range as
  // RTformat with undefined behaviour (UBSan: "not a valid value for type 'RTformat'"): it
  // travels as its int until SetFormat has checked it.
  const int value = format;
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.SetFormat(value); });
}

RTresult rtBufferGetFormat(RTbuffer buffer, RTformat* format) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(format, "format pointer"));
    *format = b.format();
    return absl::OkStatus();
  });
}

RTresult rtBufferSetElementSize(RTbuffer buffer, RTsize size_of_element) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.SetElementSize(size_of_element); });
}

RTresult rtBufferGetElementSize(RTbuffer buffer, RTsize* size_of_element) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(size_of_element, "size pointer"));
    *size_of_element = b.element_size();
    return absl::OkStatus();
  });
}

RTresult rtBufferSetSize1D(RTbuffer buffer, RTsize width) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.SetSize({width}); });
}

RTresult rtBufferGetSize1D(RTbuffer buffer, RTsize* width) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(width, "width pointer"));
    *width = b.dim(0);
    return absl::OkStatus();
  });
}

RTresult rtBufferSetSize2D(RTbuffer buffer, RTsize width, RTsize height) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.SetSize({width, height}); });
}

RTresult rtBufferGetSize2D(RTbuffer buffer, RTsize* width, RTsize* height) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(width, "width pointer"));
    TS_RETURN_IF_ERROR(NotNull(height, "height pointer"));
    *width = b.dim(0);
    *height = b.dim(1);
    return absl::OkStatus();
  });
}

RTresult rtBufferSetSize3D(RTbuffer buffer, RTsize width, RTsize height, RTsize depth) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.SetSize({width, height, depth}); });
}

RTresult rtBufferGetSize3D(RTbuffer buffer, RTsize* width, RTsize* height, RTsize* depth) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(width, "width pointer"));
    TS_RETURN_IF_ERROR(NotNull(height, "height pointer"));
    TS_RETURN_IF_ERROR(NotNull(depth, "depth pointer"));
    *width = b.dim(0);
    *height = b.dim(1);
    *depth = b.dim(2);
    return absl::OkStatus();
  });
}

RTresult rtBufferSetSizev(RTbuffer buffer, unsigned int dimensionality, const RTsize* dims) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(dims, "dimension array"));
    if (dimensionality < 1 || dimensionality > 3) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("dimensionality ", dimensionality, " is not 1, 2 or 3"));
    }
    return b.SetSize(std::vector<size_t>(dims, dims + dimensionality));
  });
}

RTresult rtBufferGetSizev(RTbuffer buffer, unsigned int dimensionality, RTsize* dims) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(dims, "dimension array"));
    if (dimensionality < 1 || dimensionality > 3) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("dimensionality ", dimensionality, " is not 1, 2 or 3"));
    }
    for (unsigned i = 0; i < dimensionality; ++i) dims[i] = b.dim(i);
    return absl::OkStatus();
  });
}

RTresult rtBufferGetDimensionality(RTbuffer buffer, unsigned int* dimensionality) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(dimensionality, "dimensionality pointer"));
    *dimensionality = b.dimensionality();
    return absl::OkStatus();
  });
}

RTresult rtBufferMap(RTbuffer buffer, void** user_pointer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(user_pointer, "user pointer"));
    TS_ASSIGN_OR_RETURN(*user_pointer, b.Map());
    return absl::OkStatus();
  });
}

RTresult rtBufferUnmap(RTbuffer buffer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) { return b.Unmap(); });
}

RTresult rtBufferGetId(RTbuffer buffer, int* buffer_id) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(buffer_id, "id pointer"));
    // The buffer id is its object id, so ids in buffers and variables resolve on devices.
    if (b.id() > static_cast<uint64_t>(INT_MAX)) {
      return RtError(RT_ERROR_INVALID_VALUE, "buffer id does not fit in an int");
    }
    *buffer_id = static_cast<int>(b.id());
    b.NoteIdTaken();
    return absl::OkStatus();
  });
}

RTresult rtBufferMarkDirty(RTbuffer buffer) {
  return BufferCall(__func__, buffer, [&](Buffer& b) -> absl::Status {
    b.MarkDirty();
    return absl::OkStatus();
  });
}

}  // extern "C"
