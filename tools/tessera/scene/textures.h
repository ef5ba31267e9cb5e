// Image files into Texture (RGBA floats), decoded by OpenImageIO for both loaders: the project's
// one image library, and the same colour handling whether a texture came from a .glb or an .mtl.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_TEXTURES_H_
#define TESSERA_TOOLS_TESSERA_SCENE_TEXTURES_H_

#include <cstddef>
#include <string>

#include "absl/status/statusor.h"
#include "scene.h"

namespace tessera::render {

// kSrgb: colour data (base colour, emissive), converted to linear. kLinear: kept as stored
// (metallic-roughness, normal maps).
enum class ColorSpace { kSrgb, kLinear };

// The sRGB transfer function's inverse (IEC 61966-2-1), for values in [0, 1].
float SrgbToLinear(float encoded);

// Decodes an encoded image held in memory (PNG, JPEG, or any format OpenImageIO reads through
// memory; `extension_hint`, e.g. "png", is used when the bytes do not say). `name` is what
// messages and Texture::name call it. INVALID_ARGUMENT when the bytes are not an image.
absl::StatusOr<Texture> DecodeImage(const unsigned char* bytes, size_t size,
                                    const std::string& extension_hint, const std::string& name,
                                    ColorSpace color_space);

// Reads and decodes an image file. NOT_FOUND when `path` does not exist.
absl::StatusOr<Texture> ReadImageFile(const std::string& path, ColorSpace color_space);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_TEXTURES_H_
