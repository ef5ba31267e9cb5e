#include "gltf_accessor.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "absl/strings/str_cat.h"

namespace tessera::render {
namespace {

size_t ComponentSize(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // includes DOUBLE and INT, which glTF 2.0 does not allow in accessors
  }
}

int ComponentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;  // matrices: only skins use them, and skins are not loaded
  }
}

const char* TypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "unknown type";
  }
}

constexpr size_t kMaxUnbackedCount = size_t{1} << 28;

// Where each element's bytes are: `count` elements `stride` apart from `base` (or all zeros when
// base is null: an accessor without a buffer view), then the sparse replacements.
struct Elements {
  const unsigned char* base = nullptr;
  size_t stride = 0;
  std::vector<std::pair<size_t, const unsigned char*>> replaced;  // element index, its bytes
};

// The view's bytes, checked against its buffer.
absl::StatusOr<ByteSpan> ViewBytes(const tinygltf::Model& model, int view,
                                   const std::string& what) {
  if (view < 0 || static_cast<size_t>(view) >= model.bufferViews.size()) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": buffer view ", view,
                                                   " does not exist (the file has ",
                                                   model.bufferViews.size(), ")"));
  }
  const tinygltf::BufferView& bv = model.bufferViews[view];
  if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size()) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": buffer view ", view, " names buffer ",
                                                   bv.buffer, ", which does not exist"));
  }
  const std::vector<unsigned char>& data = model.buffers[bv.buffer].data;
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": buffer view ", view, " (bytes ", bv.byteOffset, " to ",
                     bv.byteOffset + bv.byteLength, ") lies outside buffer ", bv.buffer, " of ",
                     data.size(), " bytes"));
  }
  return ByteSpan{data.data() + bv.byteOffset, bv.byteLength};
}

// `count` elements of `element_size` bytes, `stride` apart from `offset` into `view`: checked
// to end inside the view without overflowing size_t on the way.
absl::StatusOr<const unsigned char*> Span(const tinygltf::Model& model, int view, size_t offset,
                                          size_t stride, size_t element_size, size_t count,
                                          const std::string& what) {
  absl::StatusOr<ByteSpan> bytes = ViewBytes(model, view, what);
  if (!bytes.ok()) return bytes.status();
  if (count == 0) return bytes->data;
  const bool fits = offset <= bytes->size && element_size <= bytes->size - offset &&
                    count - 1 <= (bytes->size - offset - element_size) / stride;
  if (!fits) {
    return absl::InvalidArgumentError(absl::StrCat(
        what, ": ", count, " elements of ", element_size, " bytes, ", stride, " apart from byte ",
        offset, ", run past the ", bytes->size, " bytes of buffer view ", view));
  }
  return bytes->data + offset;
}

// An unsigned byte, short or int: vertex and sparse indices.
uint32_t ReadUnsigned(const unsigned char* p, int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

absl::StatusOr<Elements> Locate(const tinygltf::Model& model, const tinygltf::Accessor& a,
                                size_t element_size, const std::string& what) {
  Elements elements;
  if (a.bufferView >= 0) {
    size_t stride = element_size;
    if (static_cast<size_t>(a.bufferView) < model.bufferViews.size() &&
        model.bufferViews[a.bufferView].byteStride != 0) {
      stride = model.bufferViews[a.bufferView].byteStride;
      if (stride < element_size) {
        return absl::InvalidArgumentError(absl::StrCat(what, ": byte stride ", stride,
                                                       " is less than its elements' ", element_size,
                                                       " bytes"));
      }
    }
    absl::StatusOr<const unsigned char*> base =
        Span(model, a.bufferView, a.byteOffset, stride, element_size, a.count, what);
    if (!base.ok()) return base.status();
    elements.base = *base;
    elements.stride = stride;
  } else if (a.count > kMaxUnbackedCount) {
    // Without a buffer view, glTF says the elements are zeros (sparse values may replace some),
    // so no buffer bounds the count: this limit keeps a hostile count from exhausting memory.
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": ", a.count, " zero elements without a buffer view"));
  }

  if (!a.sparse.isSparse) return elements;
  const auto& s = a.sparse;
  if (s.count < 1 || static_cast<size_t>(s.count) > a.count) {
    return absl::InvalidArgumentError(absl::StrCat(
        what, ": sparse count ", s.count, " is not within 1 and its ", a.count, " elements"));
  }
  const size_t index_size = ComponentSize(s.indices.componentType);
  if (s.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      s.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      s.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": sparse indices of component type ",
                                                   s.indices.componentType,
                                                   " (glTF allows unsigned byte, short and int)"));
  }
  if (s.indices.byteOffset < 0 || s.values.byteOffset < 0) {
    return absl::InvalidArgumentError(absl::StrCat(what, ": negative sparse byte offset"));
  }
  const size_t count = static_cast<size_t>(s.count);
  absl::StatusOr<const unsigned char*> indices =
      Span(model, s.indices.bufferView, static_cast<size_t>(s.indices.byteOffset), index_size,
           index_size, count, absl::StrCat(what, " sparse indices"));
  if (!indices.ok()) return indices.status();
  absl::StatusOr<const unsigned char*> values =
      Span(model, s.values.bufferView, static_cast<size_t>(s.values.byteOffset), element_size,
           element_size, count, absl::StrCat(what, " sparse values"));
  if (!values.ok()) return values.status();
  elements.replaced.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const size_t index = ReadUnsigned(*indices + i * index_size, s.indices.componentType);
    if (index >= a.count) {
      return absl::InvalidArgumentError(
          absl::StrCat(what, ": sparse index ", index, " past its ", a.count, " elements"));
    }
    elements.replaced.emplace_back(index, *values + i * element_size);
  }
  return elements;
}

float DecodeComponent(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto v = static_cast<int8_t>(*p);
      return normalized ? std::max(v / 127.f, -1.f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? *p / 255.f : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.f, -1.f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? static_cast<float>(v / 4294967295.0) : static_cast<float>(v);
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// The accessor, once its index, type and component type are checked.
absl::StatusOr<const tinygltf::Accessor*> Find(const tinygltf::Model& model, int index,
                                               const std::string& what) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    return absl::InvalidArgumentError(absl::StrCat(
        what, ": accessor ", index, " does not exist (the file has ", model.accessors.size(), ")"));
  }
  const tinygltf::Accessor& a = model.accessors[index];
  if (ComponentSize(a.componentType) == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": accessor ", index, " has invalid component type ", a.componentType));
  }
  return &a;
}

}  // namespace

absl::StatusOr<FloatAccessor> ReadFloatAccessor(const tinygltf::Model& model, int index,
                                                std::initializer_list<int> types,
                                                const std::string& what) {
  absl::StatusOr<const tinygltf::Accessor*> found = Find(model, index, what);
  if (!found.ok()) return found.status();
  const tinygltf::Accessor& a = **found;
  const std::string where = absl::StrCat(what, " (accessor ", index, ")");
  if (std::find(types.begin(), types.end(), a.type) == types.end() || ComponentCount(a.type) == 0) {
    std::string allowed;
    for (int type : types) absl::StrAppend(&allowed, allowed.empty() ? "" : " or ", TypeName(type));
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": type ", TypeName(a.type), " where ", allowed, " belongs"));
  }
  const int components = ComponentCount(a.type);
  const size_t component_size = ComponentSize(a.componentType);
  absl::StatusOr<Elements> elements = Locate(model, a, component_size * components, where);
  if (!elements.ok()) return elements.status();

  FloatAccessor out;
  out.components = components;
  out.count = a.count;
  out.values.assign(a.count * components, 0.f);
  auto decode = [&](size_t element, const unsigned char* p) {
    for (int c = 0; c < components; ++c) {
      out.values[element * components + c] =
          DecodeComponent(p + c * component_size, a.componentType, a.normalized);
    }
  };
  if (elements->base != nullptr) {
    for (size_t e = 0; e < a.count; ++e) decode(e, elements->base + e * elements->stride);
  }
  for (const auto& [element, p] : elements->replaced) decode(element, p);
  return out;
}

absl::StatusOr<std::vector<uint32_t>> ReadIndexAccessor(const tinygltf::Model& model, int index,
                                                        const std::string& what) {
  absl::StatusOr<const tinygltf::Accessor*> found = Find(model, index, what);
  if (!found.ok()) return found.status();
  const tinygltf::Accessor& a = **found;
  const std::string where = absl::StrCat(what, " indices (accessor ", index, ")");
  if (a.type != TINYGLTF_TYPE_SCALAR ||
      (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
       a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": indices must be unsigned byte, short or int scalars"));
  }
  const size_t size = ComponentSize(a.componentType);
  absl::StatusOr<Elements> elements = Locate(model, a, size, where);
  if (!elements.ok()) return elements.status();
  std::vector<uint32_t> out(a.count, 0);
  auto decode = [&](size_t element, const unsigned char* p) {
    out[element] = ReadUnsigned(p, a.componentType);
  };
  if (elements->base != nullptr) {
    for (size_t e = 0; e < a.count; ++e) decode(e, elements->base + e * elements->stride);
  }
  for (const auto& [element, p] : elements->replaced) decode(element, p);
  return out;
}

absl::StatusOr<ByteSpan> BufferViewBytes(const tinygltf::Model& model, int view,
                                         const std::string& what) {
  return ViewBytes(model, view, what);
}

}  // namespace tessera::render
