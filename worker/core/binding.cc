#include "binding.h"

#include <algorithm>
#include <cstring>
#include <string_view>
#include <utility>

#include "absl/strings/str_cat.h"
#include "tessera/rt.h"
#include "texture_views.h"

namespace tessera::worker {
namespace {

bool IsNodeType(uint32_t type) {
  return type == RT_OBJECTTYPE_GROUP || type == RT_OBJECTTYPE_GEOMETRY_GROUP ||
         type == RT_OBJECTTYPE_TRANSFORM || type == RT_OBJECTTYPE_SELECTOR ||
         type == RT_OBJECTTYPE_OBJECT;
}

const Value* Lookup(const std::vector<const Scope*>& scopes, const std::string& name) {
  for (const Scope* s : scopes) {
    if (s == nullptr) continue;
    auto it = s->find(name);
    if (it != s->end()) return &it->second;
  }
  return nullptr;
}

// Bytes of a semantic value a variable receives: the value's size, or less for a smaller
// declaration (a uint2 launch index of a 3D index).
unsigned CopySize(size_t declared, size_t value) {
  return static_cast<unsigned>(std::min(declared, value));
}

constexpr size_t kRayBytes = 36;  // optix::Ray

// The value types of rtVariableSet* by name, as programs declare them (optix:: optional).
constexpr std::pair<const char*, uint32_t> kValueTypes[] = {
    {"float", RT_OBJECTTYPE_FLOAT},
    {"float2", RT_OBJECTTYPE_FLOAT2},
    {"float3", RT_OBJECTTYPE_FLOAT3},
    {"float4", RT_OBJECTTYPE_FLOAT4},
    {"int", RT_OBJECTTYPE_INT},
    {"int2", RT_OBJECTTYPE_INT2},
    {"int3", RT_OBJECTTYPE_INT3},
    {"int4", RT_OBJECTTYPE_INT4},
    {"unsigned int", RT_OBJECTTYPE_UNSIGNED_INT},
    {"unsigned", RT_OBJECTTYPE_UNSIGNED_INT},
    {"uint", RT_OBJECTTYPE_UNSIGNED_INT},
    {"uint2", RT_OBJECTTYPE_UNSIGNED_INT2},
    {"uint3", RT_OBJECTTYPE_UNSIGNED_INT3},
    {"uint4", RT_OBJECTTYPE_UNSIGNED_INT4},
    {"Matrix2x2", RT_OBJECTTYPE_MATRIX_FLOAT2x2},
    {"Matrix2x3", RT_OBJECTTYPE_MATRIX_FLOAT2x3},
    {"Matrix2x4", RT_OBJECTTYPE_MATRIX_FLOAT2x4},
    {"Matrix3x2", RT_OBJECTTYPE_MATRIX_FLOAT3x2},
    {"Matrix3x3", RT_OBJECTTYPE_MATRIX_FLOAT3x3},
    {"Matrix3x4", RT_OBJECTTYPE_MATRIX_FLOAT3x4},
    {"Matrix4x2", RT_OBJECTTYPE_MATRIX_FLOAT4x2},
    {"Matrix4x3", RT_OBJECTTYPE_MATRIX_FLOAT4x3},
    {"Matrix4x4", RT_OBJECTTYPE_MATRIX_FLOAT4x4},
};

// The value type a declaration names, or 0 for any other type (a struct, a typedef of the
// program's own, char or double …), whose values are checked by size only.
uint32_t DeclaredValueType(std::string_view name) {
  for (std::string_view prefix : {"::", "optix::"}) {
    if (name.substr(0, prefix.size()) == prefix) name.remove_prefix(prefix.size());
  }
  for (const auto& [type_name, type] : kValueTypes) {
    if (name == type_name) return type;
  }
  return 0;
}

// Whether a declaration names rtObject (optix:: or :: optional): only graph nodes bind to it.
bool DeclaredAsObject(std::string_view name) {
  for (std::string_view prefix : {"::", "optix::"}) {
    if (name.substr(0, prefix.size()) == prefix) name.remove_prefix(prefix.size());
  }
  return name == "rtObject";
}

const char* ValueTypeName(uint32_t type) {
  for (const auto& [type_name, t] : kValueTypes) {
    if (t == type) return type_name;
  }
  switch (type) {
    case RT_OBJECTTYPE_USER:
      return "user data";
    case RT_OBJECTTYPE_BUFFER:
      return "a buffer";
    case RT_OBJECTTYPE_PROGRAM:
      return "a program";
    case RT_OBJECTTYPE_TEXTURE_SAMPLER:
      return "a texture sampler";
    default:
      return "another type";
  }
}

// A view per rtTextureSampler declaration of the module, from the sampler its name resolves to.
absl::Status BindTextures(const Replica& replica, const std::vector<const Scope*>& scopes,
                          BoundProgram& b) {
  for (const ModuleTexture& mt : b.module->textures()) {
    TesseraTextureView view{};
    const Value* value = Lookup(scopes, mt.name);
    if (value != nullptr) {
      if (value->type != RT_OBJECTTYPE_TEXTURE_SAMPLER) {
        return absl::InvalidArgumentError(absl::StrCat(
            b.name, ": rtTextureSampler '", mt.name, "' is bound to ", ValueTypeName(value->type),
            "; set it with rtVariableSetObject to a texture sampler"));
      }
      absl::StatusOr<TesseraTextureView> made = MakeTextureView(replica, value->object_id);
      if (!made.ok()) {
        return absl::Status(
            made.status().code(),
            absl::StrCat(b.name, ": rtTextureSampler '", mt.name, "': ", made.status().message()));
      }
      if (const char* wanted = TextureShapeMismatch(mt.dimensionality, *made)) {
        return absl::InvalidArgumentError(
            absl::StrCat(b.name, ": rtTextureSampler '", mt.name, "' (Dim 0x",
                         absl::Hex(mt.dimensionality), ") needs ", wanted, " but texture sampler #",
                         value->object_id, " reads a ", made->dimensionality, "D buffer",
                         made->cubemap != 0   ? " (cube map)"
                         : made->layered != 0 ? " (layered)"
                                              : ""));
      }
      view = *made;
    }
    b.textures.push_back(view);
  }
  return absl::OkStatus();
}

}  // namespace

const char* KindName(ProgramKind kind) {
  switch (kind) {
    case ProgramKind::kRayGeneration:
      return "ray generation";
    case ProgramKind::kException:
      return "exception";
    case ProgramKind::kClosestHit:
      return "closest hit";
    case ProgramKind::kAnyHit:
      return "any hit";
    case ProgramKind::kMiss:
      return "miss";
    case ProgramKind::kIntersection:
      return "intersection";
    case ProgramKind::kBoundingBox:
      return "bounding box";
    case ProgramKind::kVisit:
      return "visit";
    case ProgramKind::kAttribute:
      return "attribute";
  }
  return "unknown";
}

absl::StatusOr<size_t> AttributeLayout::Offset(const std::string& name, size_t size,
                                               const std::string& where) {
  if (name == kTriangleBarycentrics && size != 2 * sizeof(float)) {
    return absl::InvalidArgumentError(
        absl::StrCat("attribute '", name, "' is ", size, " bytes in ", where, "; it is a float2"));
  }
  auto it = entries_.find(name);
  if (it != entries_.end()) {
    if (it->second.second != size) {
      return absl::InvalidArgumentError(absl::StrCat("attribute '", name, "' is ", size,
                                                     " bytes in ", where, " but ",
                                                     it->second.second, " bytes elsewhere"));
    }
    return it->second.first;
  }
  // Packed, without alignment padding: attributes move bytewise between a hit's block and
  // programs' variables, and padding must not count against the 512 bytes a hit carries.
  const size_t offset = used_;
  if (offset + size > kMaxBytes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "attributes take more than the ", kMaxBytes, " bytes a hit carries: attribute '", name,
        "' (", size, " bytes, declared in the module of ", where, ") comes after ", used_,
        " bytes of other attributes (all modules' attributes share one block)"));
  }
  used_ = offset + size;
  entries_[name] = {offset, size};
  return offset;
}

absl::StatusOr<BoundProgram> Bind(const Replica& replica, ProgramKind kind, uint64_t program_id,
                                  const std::vector<const Scope*>& outer,
                                  AttributeLayout& attributes, bool callable) {
  const ProgramRec* program = replica.Find(replica.programs, program_id);
  if (program == nullptr) {
    return absl::NotFoundError(
        absl::StrCat(KindName(kind), " program #", program_id, " is unknown to the device"));
  }
  absl::StatusOr<const Module*> module =
      ModuleCache::Get().Load(program->module_hash, program->module_path);
  if (!module.ok()) return module.status();
  BoundProgram b;
  b.kind = kind;
  b.id = program_id;
  b.module = *module;
  b.module_index = static_cast<unsigned>(b.module->index());
  b.name = absl::StrCat(callable ? "callable" : KindName(kind), " program '", program->function,
                        "' in ", program->module_path);
  b.outer = outer;
  b.function = b.module->Function(program->function);
  if (b.function == nullptr) {
    return absl::NotFoundError(absl::StrCat(b.name, ": no such function in the module"));
  }
  std::vector<const Scope*> scopes;
  scopes.push_back(&program->vars);
  scopes.insert(scopes.end(), outer.begin(), outer.end());

  const auto& vars = b.module->variables();
  std::vector<size_t> callable_copies;  // indices in b.copies of rtCallableProgram slots
  for (unsigned i = 0; i < vars.size(); ++i) {
    const ModuleVariable& v = vars[i];
    switch (v.semantic) {
      case Semantic::kLaunchIndex:
        b.launch_index.push_back({i, CopySize(v.size, 3 * sizeof(uint32_t))});
        continue;
      case Semantic::kLaunchDim:
        b.launch_dim.push_back({i, CopySize(v.size, 3 * sizeof(uint32_t))});
        continue;
      case Semantic::kCurrentRay:
        b.ray.push_back({i, CopySize(v.size, kRayBytes)});
        continue;
      case Semantic::kPayload:
        b.payload.push_back({i, static_cast<unsigned>(v.size)});
        continue;
      case Semantic::kDistance:
        b.distance.push_back({i, CopySize(v.size, sizeof(float))});
        continue;
      case Semantic::kCurrentTime:
        b.time.push_back({i, CopySize(v.size, sizeof(float))});
        continue;
      case Semantic::kAttribute: {
        absl::StatusOr<size_t> offset = attributes.Offset(v.attribute, v.size, b.name);
        if (!offset.ok()) return offset.status();
        b.attributes.push_back({i, *offset, v.size});
        continue;
      }
      case Semantic::kCallable: {
        const Value* value = Lookup(scopes, v.name);
        if (value != nullptr && value->type != RT_OBJECTTYPE_PROGRAM) {
          return absl::InvalidArgumentError(absl::StrCat(
              b.name, ": rtCallableProgram '", v.name, "' is set to ", ValueTypeName(value->type),
              "; set it with rtVariableSetObject to a program made from an RT_CALLABLE_PROGRAM"));
        }
        // The slot's value comes from `callables` once the plan has bound the target; every
        // binding of the module copies it, null when no scope names a program.
        b.callables.push_back({i, value == nullptr ? 0 : value->object_id, nullptr});
        callable_copies.push_back(b.copies.size());
        b.copies.push_back({i, nullptr, sizeof(const BoundProgram*)});
        continue;
      }
      case Semantic::kUser:
        break;
    }
    const Value* value = Lookup(scopes, v.name);
    if (value == nullptr) {
      b.copies.push_back({i, v.initial.data(), v.size});
      continue;
    }
    if (value->type == RT_OBJECTTYPE_BUFFER || value->type == RT_OBJECTTYPE_PROGRAM ||
        value->type == RT_OBJECTTYPE_TEXTURE_SAMPLER) {
      return absl::InvalidArgumentError(absl::StrCat(
          b.name, ": variable '", v.name, "' is declared with rtDeclareVariable but bound to ",
          ValueTypeName(value->type),
          " (use rtBuffer for buffers, rtTextureSampler for texture samplers, rtCallableProgram "
          "for programs; an rtBufferId or rtCallableProgramId takes the object's id, set with "
          "rtVariableSet1i)"));
    }
    if (IsNodeType(value->type)) {
      // Only an rtObject receives a node: a float2 or uint2 has the same 8 bytes but would read
      // the node's id as its value.
      if (!DeclaredAsObject(v.type_name) || v.size != sizeof(uint64_t)) {
        return absl::InvalidArgumentError(absl::StrCat(b.name, ": variable '", v.name,
                                                       "' is declared as ", v.type_name,
                                                       " but is bound to a graph node; declare "
                                                       "it as rtObject"));
      }
      b.copies.push_back({i, &value->object_id, sizeof(uint64_t)});
      continue;
    }
    if (DeclaredAsObject(v.type_name)) {
      return absl::InvalidArgumentError(
          absl::StrCat(b.name, ": variable '", v.name, "' is declared as rtObject but was set as ",
                       ValueTypeName(value->type),
                       "; set it with rtVariableSetObject to a group, "
                       "geometry group, transform or selector"));
    }
    // As OptiX: a value set with rtVariableSet3i does not bind to a float3, though the bytes
    // fit. User data (rtVariableSetUserData) binds to anything of its size.
    if (const uint32_t declared = DeclaredValueType(v.type_name);
        declared != 0 && value->type != RT_OBJECTTYPE_USER && value->type != declared) {
      return absl::InvalidArgumentError(
          absl::StrCat(b.name, ": variable '", v.name, "' is declared as ", v.type_name,
                       " but was set as ", ValueTypeName(value->type), " (type mismatch)"));
    }
    if (value->data.size() != v.size) {
      return absl::InvalidArgumentError(
          absl::StrCat(b.name, ": variable '", v.name, "' is declared as ", v.type_name, " (",
                       v.size, " bytes) but its value is ", value->data.size(), " bytes"));
    }
    b.copies.push_back({i, value->data.data(), v.size});
  }

  const auto& buffers = b.module->buffers();
  for (unsigned slot = 0; slot < buffers.size(); ++slot) {
    const ModuleBuffer& mb = buffers[slot];
    TesseraBufferView view{nullptr, {0, 1, 1}, mb.element_size, 0, nullptr, nullptr, nullptr};
    const Value* value = Lookup(scopes, mb.name);
    if (value != nullptr) {
      if (value->type != RT_OBJECTTYPE_BUFFER) {
        return absl::InvalidArgumentError(absl::StrCat(b.name, ": rtBuffer '", mb.name,
                                                       "' is bound to a variable that is not a "
                                                       "buffer"));
      }
      const BufferRec* buf = replica.Find(replica.buffers, value->object_id);
      if (buf == nullptr && value->object_id != 0) {
        return absl::NotFoundError(absl::StrCat(
            b.name, ": rtBuffer '", mb.name, "' is bound to unknown buffer #", value->object_id));
      }
      if (buf != nullptr) {
        if (buf->element_size != mb.element_size) {
          return absl::InvalidArgumentError(
              absl::StrCat(b.name, ": rtBuffer '", mb.name, "' has elements of ", mb.element_size,
                           " bytes but buffer #", value->object_id, " has elements of ",
                           buf->element_size, " bytes"));
        }
        if (buf->ndims != 0 && buf->ndims != mb.dimensionality) {
          return absl::InvalidArgumentError(
              absl::StrCat(b.name, ": rtBuffer '", mb.name, "' is ", mb.dimensionality,
                           "D but buffer #", value->object_id, " is ", buf->ndims, "D"));
        }
        view.data = const_cast<unsigned char*>(buf->data.data());
        view.size[0] = buf->dims[0];
        view.size[1] = buf->dims[1];
        view.size[2] = buf->dims[2];
        view.id = value->object_id;
        if ((buf->desc & RT_BUFFER_OUTPUT) != 0) b.writable_slots.push_back(slot);
        if (!buf->written.empty()) {
          view.written = const_cast<unsigned char*>(buf->written.data());
          view.written_blocks = const_cast<unsigned char*>(buf->written_blocks.data());
          view.write_epoch = replica.write_epoch();
        }
      }
    }
    b.table.push_back(view);
  }
  if (absl::Status s = BindTextures(replica, scopes, b); !s.ok()) return s;
  for (size_t i = 0; i < b.attributes.size() && !b.attributes_alias; ++i) {
    for (size_t j = i + 1; j < b.attributes.size(); ++j) {
      const BoundProgram::Attribute &x = b.attributes[i], &y = b.attributes[j];
      if (x.offset < y.offset + y.size && y.offset < x.offset + x.size) b.attributes_alias = true;
    }
  }
  // `callables` is complete: its elements keep their addresses from here on (also when `b`
  // moves into the plan).
  for (size_t k = 0; k < callable_copies.size(); ++k) {
    b.copies[callable_copies[k]].src = &b.callables[k].target;
  }
  return b;
}

}  // namespace tessera::worker
