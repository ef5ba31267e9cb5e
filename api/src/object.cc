#include "object.h"

#include <atomic>
#include <cstdint>

#include "absl/strings/str_cat.h"
#include "context.h"
#include "handle_registry.h"

namespace tessera::api {

const char* KindName(Kind kind) {
  switch (kind) {
    case Kind::kContext:
      return "context";
    case Kind::kVariable:
      return "variable";
    case Kind::kProgram:
      return "program";
    case Kind::kBuffer:
      return "buffer";
    case Kind::kGeometry:
      return "geometry";
    case Kind::kMaterial:
      return "material";
    case Kind::kGeometryInstance:
      return "geometry instance";
    case Kind::kGeometryGroup:
      return "geometry group";
    case Kind::kGroup:
      return "group";
    case Kind::kSelector:
      return "selector";
    case Kind::kTransform:
      return "transform";
    case Kind::kAcceleration:
      return "acceleration";
    case Kind::kGeometryTriangles:
      return "geometry triangles";
    case Kind::kTextureSampler:
      return "texture sampler";
  }
  return "object";
}

bool IsNodeKind(Kind kind) {
  return kind == Kind::kGroup || kind == Kind::kGeometryGroup || kind == Kind::kTransform ||
         kind == Kind::kSelector;
}

RTobjecttype ObjectTypeOf(Kind kind) {
  switch (kind) {
    case Kind::kGroup:
      return RT_OBJECTTYPE_GROUP;
    case Kind::kGeometryGroup:
      return RT_OBJECTTYPE_GEOMETRY_GROUP;
    case Kind::kTransform:
      return RT_OBJECTTYPE_TRANSFORM;
    case Kind::kSelector:
      return RT_OBJECTTYPE_SELECTOR;
    case Kind::kGeometryInstance:
      return RT_OBJECTTYPE_GEOMETRY_INSTANCE;
    case Kind::kBuffer:
      return RT_OBJECTTYPE_BUFFER;
    case Kind::kProgram:
      return RT_OBJECTTYPE_PROGRAM;
    case Kind::kTextureSampler:
      return RT_OBJECTTYPE_TEXTURE_SAMPLER;
    default:
      return RT_OBJECTTYPE_UNKNOWN;
  }
}

std::string EdgeRole::Format() const {
  std::string out = label;
  if (index >= 0) absl::StrAppend(&out, " ", index);
  if (name != nullptr) absl::StrAppend(&out, " '", *name, "'");
  return out;
}

namespace {

// Handles count up from 16 in steps of 16 (aligned like pointers, so C code that stores them
// with pointer tags keeps working); 2^60 of them before they would wrap.
const void* NextHandle() {
  static std::atomic<uintptr_t> next{1};
  return reinterpret_cast<const void*>(next.fetch_add(1, std::memory_order_relaxed) << 4);
}

}  // namespace

Object::Object(Kind kind, Context* context, uint64_t id)
    : kind_(kind), context_(context), id_(id), handle_(NextHandle()) {}

Object::~Object() = default;

std::string Object::Describe() const {
  if (id_ == 0) return KindName(kind_);
  return absl::StrCat(KindName(kind_), " #", id_);
}

void Object::Touch() {
  if (context_ == nullptr) return;
  version_ = context_->NextVersion();
  context_->StructureChanged();
}

void Object::TouchValue() {
  if (context_ != nullptr) version_ = context_->NextVersion();
}

void Object::RemoveParent(Object* parent) {
  auto it = parents_.find(parent);
  if (it == parents_.end()) return;
  if (--it->second == 0) parents_.erase(it);
}

void Object::Destroy() {
  if (!alive_) return;
  alive_ = false;
  if (context_ != nullptr) context_->StructureChanged();
  HandleRegistry::Get().Remove(this);
  DropLinks();
}

void Links::Resize(size_t size) {
  // Release in reverse so that nothing below observes a half-shrunk vector.
  while (targets_.size() > size) {
    Set(targets_.size() - 1, nullptr);
    targets_.pop_back();
  }
  targets_.resize(size, nullptr);
}

void Links::Set(size_t index, Object* target) {
  Object* old = targets_[index];
  if (old == target) return;
  if (target != nullptr) {
    target->Retain();
    target->AddParent(owner_);
  }
  targets_[index] = target;
  if (old != nullptr) {
    old->RemoveParent(owner_);
    old->Release();
  }
}

}  // namespace tessera::api
