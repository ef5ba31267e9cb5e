// A host-declared variable: a name in one scope and a typed value. The first Set fixes the type;
// later Sets and Gets of another type fail with RT_ERROR_TYPE_MISMATCH. Plain values are stored
// as the little-endian bytes a program reads (matrices row-major); object values are links.
#ifndef TESSERA_API_SRC_VARIABLE_H_
#define TESSERA_API_SRC_VARIABLE_H_

#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "object.h"

namespace tessera::api {

// "float3", "matrix 3x4", "user data", "buffer" …
const char* TypeName(RTobjecttype type);
// The RTobjecttype of `count` floats/ints/unsigned ints (count 1..4).
RTobjecttype FloatType(int count);
RTobjecttype IntType(int count);
RTobjecttype UintType(int count);
RTobjecttype MatrixType(int rows, int cols);

class Variable : public Object {
 public:
  static constexpr Kind kKind = Kind::kVariable;

  Variable(Context* context, Object* scope_owner, std::string name);

  const std::string& name() const { return name_; }
  Object* scope_owner() const { return scope_owner_; }
  RTobjecttype type() const { return type_; }
  bool has_value() const { return type_ != RT_OBJECTTYPE_UNKNOWN; }
  bool holds_object() const;
  // Raw value bytes (plain values and user data).
  const std::vector<unsigned char>& data() const { return data_; }
  // The referenced object for object values; null otherwise.
  Object* object() const { return object_.Get(0); }
  // Bytes a program sees: the value's size, 4 for object references (an id), 0 when unset.
  size_t ValueSize() const;

  absl::Status SetPlain(RTobjecttype type, const void* bytes, size_t size);
  absl::Status GetPlain(RTobjecttype type, void* out, size_t size) const;
  absl::Status SetUserData(const void* bytes, size_t size);
  absl::Status GetUserData(void* out, size_t size) const;
  // `target` must be a live buffer, program or node of this context (checked by the caller).
  absl::Status SetObject(Object* target);
  absl::StatusOr<Object*> GetObject() const;

  std::string Describe() const override;
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override { object_.Resize(0); }
  absl::Status CheckType(RTobjecttype wanted, const char* action) const;
  void Changed();

  Object* const scope_owner_;
  const std::string name_;
  RTobjecttype type_ = RT_OBJECTTYPE_UNKNOWN;
  std::vector<unsigned char> data_;
  // Owned by the variable but recorded with the scope as parent, so that a buffer knows which
  // geometry refers to it (acceleration dirty tracking).
  Links object_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_VARIABLE_H_
