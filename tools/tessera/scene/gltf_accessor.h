// Bounds-checked reads of glTF accessors. A hostile file chooses every count, offset and stride,
// so each is checked against the buffer view, and the view against its buffer, before any byte
// is read.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_GLTF_ACCESSOR_H_
#define TESSERA_TOOLS_TESSERA_SCENE_GLTF_ACCESSOR_H_

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::render {

struct FloatAccessor {
  int components = 0;         // per element: 1 (SCALAR) to 4 (VEC4)
  size_t count = 0;           // elements
  std::vector<float> values;  // count * components
};

// Accessor `index` as floats, its type one of `types` (TINYGLTF_TYPE_SCALAR, _VEC2, ...).
// Integer components become floats, normalized ones scaled to [0, 1] or [-1, 1] as glTF says.
// Sparse accessors are applied. Messages start with `what` (the file and the object reading).
absl::StatusOr<FloatAccessor> ReadFloatAccessor(const tinygltf::Model& model, int index,
                                                std::initializer_list<int> types,
                                                const std::string& what);

// Accessor `index` as vertex indices: SCALAR, unsigned byte, short or int.
absl::StatusOr<std::vector<uint32_t>> ReadIndexAccessor(const tinygltf::Model& model, int index,
                                                        const std::string& what);

struct ByteSpan {
  const unsigned char* data = nullptr;
  size_t size = 0;
};

// The bytes of buffer view `view` (e.g. an embedded image), checked to lie inside its buffer.
absl::StatusOr<ByteSpan> BufferViewBytes(const tinygltf::Model& model, int view,
                                         const std::string& what);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_GLTF_ACCESSOR_H_
