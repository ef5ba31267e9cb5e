// rtAcceleration*.
#include <cstring>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "acceleration.h"
#include "acceleration_data.h"
#include "boundary.h"
#include "scope_api.h"
#include "status.h"
#include "tessera/scheduler/device.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {
// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
// Property names and values travel to devices in a protobuf map<string, string>, which a
// worker refuses to parse unless both are UTF-8.
bool IsUtf8(const unsigned char* s) {
  while (*s != 0) {
    const unsigned char c = *s;
    int n = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the first continuation byte
    if (c < 0x80) {
      ++s;
      continue;
    } else if (c >= 0xC2 && c <= 0xDF) {
      n = 1;
    } else if (c >= 0xE0 && c <= 0xEF) {
      n = 2;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      n = 3;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return false;
    }
    ++s;
    for (int i = 0; i < n; ++i, ++s) {
      if (*s < (i == 0 ? lo : 0x80) || *s > (i == 0 ? hi : 0xBF)) return false;
    }
  }
  return true;
}

absl::Status CheckUtf8(const char* text, const char* what) {
  if (IsUtf8(reinterpret_cast<const unsigned char*>(text))) return absl::OkStatus();
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(what, " is not valid UTF-8"));
}
}  // namespace

extern "C" {

RTresult rtAccelerationCreate(RTcontext context, RTacceleration* acceleration) {
  return CreateCall(__func__, context, acceleration,
                    [](Context& c) { return c.Make<Acceleration>(); });
}
RTresult rtAccelerationDestroy(RTacceleration acceleration) {
  return DestroyCall<Acceleration>(__func__, acceleration);
}
RTresult rtAccelerationValidate(RTacceleration acceleration) {
  return Call<Acceleration>(__func__, acceleration,
                            [](Acceleration& a) { return ValidateObject(a); });
}
RTresult rtAccelerationGetContext(RTacceleration acceleration, RTcontext* context) {
  return GetContextCall<Acceleration>(__func__, acceleration, context);
}

RTresult rtAccelerationSetBuilder(RTacceleration acceleration, const char* builder) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(builder, "builder name"));
    return a.SetBuilder(builder);
  });
}

RTresult rtAccelerationGetBuilder(RTacceleration acceleration, const char** return_string) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(return_string, "string pointer"));
    *return_string = a.builder().c_str();
    return absl::OkStatus();
  });
}

RTresult rtAccelerationSetTraverser(RTacceleration acceleration, const char* traverser) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(traverser, "traverser name"));
    return a.SetTraverser(traverser);
  });
}

RTresult rtAccelerationGetTraverser(RTacceleration acceleration, const char** return_string) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(return_string, "string pointer"));
    *return_string = a.traverser().c_str();
    return absl::OkStatus();
  });
}

RTresult rtAccelerationSetProperty(RTacceleration acceleration, const char* name,
                                   const char* value) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(name, "property name"));
    TS_RETURN_IF_ERROR(NotNull(value, "property value"));
    TS_RETURN_IF_ERROR(CheckUtf8(name, "property name"));
    TS_RETURN_IF_ERROR(CheckUtf8(value, "property value"));
    a.SetProperty(name, value);
    return absl::OkStatus();
  });
}

RTresult rtAccelerationGetProperty(RTacceleration acceleration, const char* name,
                                   const char** return_string) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(name, "property name"));
    TS_RETURN_IF_ERROR(NotNull(return_string, "string pointer"));
    *return_string = a.Property(name).c_str();
    return absl::OkStatus();
  });
}

// Acceleration data caching (OptiX 3 guide 3.6.5, docs/acceleration_data.md): the blob carries
// the builder, traverser, properties, what the structure was built over, and the bounds the
// bounding-box programs gave, which devices reuse instead of running the programs again.
RTresult rtAccelerationGetDataSize(RTacceleration acceleration, RTsize* size) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(size, "size pointer"));
    absl::StatusOr<const std::string*> blob = ExtractAccelerationData(*a.context(), a);
    if (!blob.ok()) return blob.status();
    *size = (*blob)->size();
    return absl::OkStatus();
  });
}

// Writes rtAccelerationGetDataSize's count of bytes (the same blob, made once per build).
RTresult rtAccelerationGetData(RTacceleration acceleration, void* data) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(data, "data pointer"));
    absl::StatusOr<const std::string*> blob = ExtractAccelerationData(*a.context(), a);
    if (!blob.ok()) return blob.status();
    std::memcpy(data, (*blob)->data(), (*blob)->size());
    return absl::OkStatus();
  });
}

// A blob that is not one this Tessera wrote leaves the acceleration as it was, so that the
// guide's "if SetData fails, MarkDirty" works.
RTresult rtAccelerationSetData(RTacceleration acceleration, const void* data, RTsize size) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    if (size > 0) TS_RETURN_IF_ERROR(NotNull(data, "data pointer"));
    absl::StatusOr<AccelerationBlob> blob = DecodeAccelerationBlob(data, size);
    if (!blob.ok()) return blob.status();
    uint64_t bounds_bytes = 0;
    for (const std::vector<float>& b : blob->bounds) bounds_bytes += b.size() * sizeof(float);
    if (bounds_bytes > tessera::kMaxCarriedBoundsBytes) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat("acceleration data refused: it carries ", bounds_bytes,
                                  " bytes of bounds, more than the ",
                                  tessera::kMaxCarriedBoundsBytes, " Tessera writes"));
    }
    for (const auto& [name, value] : blob->properties) {  // they travel to devices as strings
      TS_RETURN_IF_ERROR(CheckUtf8(name.c_str(), "a restored property name"));
      TS_RETURN_IF_ERROR(CheckUtf8(value.c_str(), "a restored property value"));
    }
    return a.Restore(*std::move(blob));
  });
}

RTresult rtAccelerationMarkDirty(RTacceleration acceleration) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    a.MarkDirty();
    return absl::OkStatus();
  });
}

RTresult rtAccelerationIsDirty(RTacceleration acceleration, int* dirty) {
  return Call<Acceleration>(__func__, acceleration, [&](Acceleration& a) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(dirty, "dirty pointer"));
    *dirty = a.dirty() ? 1 : 0;
    return absl::OkStatus();
  });
}

}  // extern "C"
