#include "variable.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "status.h"

namespace tessera::api {
namespace {

// Object references of these classes may replace each other; anything else fixes its type.
enum class ValueClass { kPlain, kBuffer, kProgram, kNode, kTextureSampler };

ValueClass ClassOf(RTobjecttype type) {
  switch (type) {
    case RT_OBJECTTYPE_BUFFER:
      return ValueClass::kBuffer;
    case RT_OBJECTTYPE_PROGRAM:
      return ValueClass::kProgram;
    case RT_OBJECTTYPE_TEXTURE_SAMPLER:
      return ValueClass::kTextureSampler;
    case RT_OBJECTTYPE_GROUP:
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
    case RT_OBJECTTYPE_TRANSFORM:
    case RT_OBJECTTYPE_SELECTOR:
      return ValueClass::kNode;
    default:
      return ValueClass::kPlain;
  }
}

}  // namespace

const char* TypeName(RTobjecttype type) {
  switch (type) {
    case RT_OBJECTTYPE_UNKNOWN:
      return "no value";
    case RT_OBJECTTYPE_GROUP:
      return "group";
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
      return "geometry group";
    case RT_OBJECTTYPE_TRANSFORM:
      return "transform";
    case RT_OBJECTTYPE_SELECTOR:
      return "selector";
    case RT_OBJECTTYPE_GEOMETRY_INSTANCE:
      return "geometry instance";
    case RT_OBJECTTYPE_BUFFER:
      return "buffer";
    case RT_OBJECTTYPE_TEXTURE_SAMPLER:
      return "texture sampler";
    case RT_OBJECTTYPE_OBJECT:
      return "object";
    case RT_OBJECTTYPE_MATRIX_FLOAT2x2:
      return "matrix 2x2";
    case RT_OBJECTTYPE_MATRIX_FLOAT2x3:
      return "matrix 2x3";
    case RT_OBJECTTYPE_MATRIX_FLOAT2x4:
      return "matrix 2x4";
    case RT_OBJECTTYPE_MATRIX_FLOAT3x2:
      return "matrix 3x2";
    case RT_OBJECTTYPE_MATRIX_FLOAT3x3:
      return "matrix 3x3";
    case RT_OBJECTTYPE_MATRIX_FLOAT3x4:
      return "matrix 3x4";
    case RT_OBJECTTYPE_MATRIX_FLOAT4x2:
      return "matrix 4x2";
    case RT_OBJECTTYPE_MATRIX_FLOAT4x3:
      return "matrix 4x3";
    case RT_OBJECTTYPE_MATRIX_FLOAT4x4:
      return "matrix 4x4";
    case RT_OBJECTTYPE_FLOAT:
      return "float";
    case RT_OBJECTTYPE_FLOAT2:
      return "float2";
    case RT_OBJECTTYPE_FLOAT3:
      return "float3";
    case RT_OBJECTTYPE_FLOAT4:
      return "float4";
    case RT_OBJECTTYPE_INT:
      return "int";
    case RT_OBJECTTYPE_INT2:
      return "int2";
    case RT_OBJECTTYPE_INT3:
      return "int3";
    case RT_OBJECTTYPE_INT4:
      return "int4";
    case RT_OBJECTTYPE_UNSIGNED_INT:
      return "unsigned int";
    case RT_OBJECTTYPE_UNSIGNED_INT2:
      return "uint2";
    case RT_OBJECTTYPE_UNSIGNED_INT3:
      return "uint3";
    case RT_OBJECTTYPE_UNSIGNED_INT4:
      return "uint4";
    case RT_OBJECTTYPE_USER:
      return "user data";
    case RT_OBJECTTYPE_PROGRAM:
      return "program";
  }
  return "unknown type";
}

RTobjecttype FloatType(int count) {
  return static_cast<RTobjecttype>(RT_OBJECTTYPE_FLOAT + count - 1);
}
RTobjecttype IntType(int count) { return static_cast<RTobjecttype>(RT_OBJECTTYPE_INT + count - 1); }
RTobjecttype UintType(int count) {
  return static_cast<RTobjecttype>(RT_OBJECTTYPE_UNSIGNED_INT + count - 1);
}
RTobjecttype MatrixType(int rows, int cols) {
  return static_cast<RTobjecttype>(RT_OBJECTTYPE_MATRIX_FLOAT2x2 + (rows - 2) * 3 + (cols - 2));
}

Variable::Variable(Context* context, Object* scope_owner, std::string name)
    : Object(Kind::kVariable, context, 0),
      scope_owner_(scope_owner),
      name_(std::move(name)),
      object_(scope_owner, 1) {}

bool Variable::holds_object() const { return ClassOf(type_) != ValueClass::kPlain; }

size_t Variable::ValueSize() const {
  if (type_ == RT_OBJECTTYPE_UNKNOWN) return 0;
  if (holds_object()) return 4;
  return data_.size();
}

std::string Variable::Describe() const {
  return absl::StrCat("variable '", name_, "' of ", scope_owner_->Describe());
}

void Variable::VisitEdges(EdgeVisitor visit) const {
  if (object() != nullptr) visit(object(), EdgeRole{"variable", -1, &name_});
}

absl::Status Variable::CheckType(RTobjecttype wanted, const char* action) const {
  if (type_ == RT_OBJECTTYPE_UNKNOWN || type_ == wanted) return absl::OkStatus();
  if (ClassOf(type_) != ValueClass::kPlain && ClassOf(type_) == ClassOf(wanted)) {
    return absl::OkStatus();
  }
  return RtError(RT_ERROR_TYPE_MISMATCH,
                 absl::StrCat("variable '", name_, "' holds ", TypeName(type_), ", cannot ", action,
                              " ", TypeName(wanted)));
}

void Variable::Changed() { scope_owner_->Touch(); }

absl::Status Variable::SetPlain(RTobjecttype type, const void* bytes, size_t size) {
  TS_RETURN_IF_ERROR(CheckType(type, "set it as"));
  const bool same_shape = type_ == type && data_.size() == size;
  type_ = type;
  const auto* first = static_cast<const unsigned char*>(bytes);
  if (size > 0) {
    data_.assign(first, first + size);
  } else {
    data_.clear();
  }
  if (same_shape) {
    scope_owner_->TouchValue();
  } else {
    Changed();
  }
  return absl::OkStatus();
}

absl::Status Variable::GetPlain(RTobjecttype type, void* out, size_t size) const {
  if (type_ == RT_OBJECTTYPE_UNKNOWN) {
    return RtError(RT_ERROR_TYPE_MISMATCH,
                   absl::StrCat("variable '", name_, "' has no value yet, cannot read it as ",
                                TypeName(type)));
  }
  if (type_ != type) {
    return RtError(RT_ERROR_TYPE_MISMATCH,
                   absl::StrCat("variable '", name_, "' holds ", TypeName(type_),
                                ", cannot read it as ", TypeName(type)));
  }
  if (size > 0) std::memcpy(out, data_.data(), size);
  return absl::OkStatus();
}

absl::Status Variable::SetUserData(const void* bytes, size_t size) {
  return SetPlain(RT_OBJECTTYPE_USER, bytes, size);
}

absl::Status Variable::GetUserData(void* out, size_t size) const {
  if (type_ == RT_OBJECTTYPE_USER && size != data_.size()) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("variable '", name_, "' holds ", data_.size(),
                                " bytes of user data, not ", size));
  }
  return GetPlain(RT_OBJECTTYPE_USER, out, size);
}

absl::Status Variable::SetObject(Object* target) {
  RTobjecttype type = ObjectTypeOf(target->kind());
  TS_RETURN_IF_ERROR(CheckType(type, "set it to a"));
  type_ = type;
  data_.clear();
  object_.Set(0, target);
  Changed();
  return absl::OkStatus();
}

absl::StatusOr<Object*> Variable::GetObject() const {
  if (!holds_object()) {
    return RtError(RT_ERROR_TYPE_MISMATCH, absl::StrCat("variable '", name_, "' holds ",
                                                        TypeName(type_), ", not an object"));
  }
  return object();
}

}  // namespace tessera::api
