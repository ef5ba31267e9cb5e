// The host object model. Every rt* handle points at an Object: a kind tag, the owning context, a
// host-allocated 64-bit id (unique per context, never reused), a version that grows with every
// change, and a reference count. Graph edges (Links) hold references, so destroying an object
// that is still attached is memory-safe; rtContextValidate then reports the dangling use.
#ifndef TESSERA_API_SRC_OBJECT_H_
#define TESSERA_API_SRC_OBJECT_H_

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/functional/function_ref.h"
#include "tessera/rt.h"

namespace tessera::api {

class Context;
class VariableScope;

enum class Kind : uint8_t {
  kContext,
  kVariable,
  kProgram,
  kBuffer,
  kGeometry,
  kMaterial,
  kGeometryInstance,
  kGeometryGroup,
  kGroup,
  kSelector,
  kTransform,
  kAcceleration,
  kGeometryTriangles,
  kTextureSampler,
};

// "geometry instance", as used in error messages.
const char* KindName(Kind kind);
// Group, GeometryGroup, Transform or Selector: what rtTrace and node children accept.
bool IsNodeKind(Kind kind);
// The RTobjecttype of a node, buffer or program; RT_OBJECTTYPE_UNKNOWN for other kinds.
RTobjecttype ObjectTypeOf(Kind kind);

// How an edge is described in validation messages, formatted only when an error is reported.
struct EdgeRole {
  const char* label;                  // "child", "acceleration", "variable"
  int64_t index = -1;                 // child or ray type index, -1 = none
  const std::string* name = nullptr;  // variable name
  std::string Format() const;
};

class Object {
 public:
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;

  Kind kind() const { return kind_; }
  Context* context() const { return context_; }
  uint64_t id() const { return id_; }
  // What the application holds as its RTcontext, RTbuffer …: a token unique for the process's
  // life, not the object's address, so that a destroyed object's handle can never come to name a
  // later object that happens to get the same memory.
  const void* handle() const { return handle_; }
  uint64_t version() const { return version_; }
  bool alive() const { return alive_; }

  // "buffer #7"; variables name themselves and their scope.
  virtual std::string Describe() const;

  void Retain() { refs_.fetch_add(1, std::memory_order_relaxed); }
  void Release() {
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }

  // Records a change: the object travels again with the next state delta. TouchValue records one
  // that changes only a variable's bytes (not its type, size or object), which no validation or
  // graph walk of the context can see (Context::structure_clock).
  void Touch();
  void TouchValue();

  // Objects whose links point here, with multiplicity. Used to carry "structure changed" upward
  // to acceleration structures.
  const absl::flat_hash_map<Object*, int>& parents() const { return parents_; }
  void AddParent(Object* parent) { ++parents_[parent]; }
  void RemoveParent(Object* parent);

  // The application destroyed the object (or its context): it leaves the handle registry and
  // drops its outgoing links; its memory lives on while other objects still link to it.
  void Destroy();

  // The variables of scope objects (context, program, geometry, instance, material, selector).
  virtual VariableScope* scope() { return nullptr; }

  // Calls `visit` for every outgoing edge (children, programs, variables' objects).
  using EdgeVisitor = absl::FunctionRef<void(Object* target, const EdgeRole& role)>;
  virtual void VisitEdges(EdgeVisitor visit) const {}

 protected:
  Object(Kind kind, Context* context, uint64_t id);
  virtual ~Object();
  // Releases outgoing links; called once by Destroy().
  virtual void DropLinks() {}
  void set_context(Context* context) { context_ = context; }

 private:
  const Kind kind_;
  Context* context_;
  const uint64_t id_;
  const void* const handle_;
  uint64_t version_ = 0;
  bool alive_ = true;
  std::atomic<int> refs_{1};  // the creator's reference
  absl::flat_hash_map<Object*, int> parents_;
};

// Owning graph edges from `owner` to other objects. Each target is retained and records `owner`
// as a parent. Slots may be empty (null).
class Links {
 public:
  explicit Links(Object* owner, size_t size = 0) : owner_(owner) { Resize(size); }
  ~Links() { Resize(0); }
  Links(const Links&) = delete;
  Links& operator=(const Links&) = delete;

  size_t size() const { return targets_.size(); }
  void Resize(size_t size);
  void Set(size_t index, Object* target);
  Object* Get(size_t index) const { return index < targets_.size() ? targets_[index] : nullptr; }
  const std::vector<Object*>& targets() const { return targets_; }

 private:
  Object* owner_;
  std::vector<Object*> targets_;
};

template <typename H>
H ToHandle(const Object* object) {
  return object != nullptr ? reinterpret_cast<H>(const_cast<void*>(object->handle())) : nullptr;
}

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_OBJECT_H_
