// Writing rendered images through OpenImageIO, by the file's extension: PNG (sRGB, 8 bits,
// clamped), OpenEXR (linear, half or float, with albedo, normal and depth layers), Radiance HDR
// (linear RGBE).
#ifndef TESSERA_TOOLS_TESSERA_RENDER_IMAGE_IO_H_
#define TESSERA_TOOLS_TESSERA_RENDER_IMAGE_IO_H_

#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace tessera::render {

enum class ImageFormat { kPng, kExr, kHdr };

// The format `path`'s extension names (case-insensitive), or INVALID_ARGUMENT naming the path.
absl::StatusOr<ImageFormat> FormatForPath(const std::string& path);

// A finished image, row 0 at the top. `rgba` is linear radiance; the layers are per pixel:
// albedo rgb, world-space normal xyz, depth along the camera's view axis (+inf where nothing
// was hit).
struct RenderedImage {
  int width = 0, height = 0;
  std::vector<float> rgba;
  std::vector<float> albedo;
  std::vector<float> normal;
  std::vector<float> depth;
};

// What the image carries besides pixels: OpenEXR attributes and PNG text chunks named
// "tessera:samples" and so on (HDR files carry none).
struct ImageMetadata {
  uint32_t samples = 0;  // samples per pixel done
  uint32_t spp = 0;      // samples per pixel asked for
  uint32_t seed = 0;
  int max_depth = 0;
  std::string scene;
  std::string camera;
  int frame = 0;
  double time = 0.0;  // seconds
};

// Writes `image` to `path` (through a temporary file in the same directory, renamed when whole,
// so that a file at `path` is always complete). `exr_float`: 32-bit EXR channels instead of half
// (depth is always 32-bit). Errors name the path.
absl::Status WriteImage(const std::string& path, const RenderedImage& image,
                        const ImageMetadata& metadata, bool exr_float);

// Whether `path` can be written: the directory exists and is writable, and `path` is not a
// directory. Checked before rendering, so a long render does not end in "cannot open".
absl::Status CheckWritable(const std::string& path);

// "tessera <version>", the image's Software attribute.
std::string SoftwareName();

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_IMAGE_IO_H_
