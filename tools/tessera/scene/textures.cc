#include "textures.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <system_error>

#include "absl/strings/str_cat.h"

namespace tessera::render {
namespace {

// 16384 x 16384 texels: 4 GiB as RGBA floats. A larger image is far more likely a hostile or
// broken header than a texture, and would exhaust memory before it failed.
constexpr int64_t kMaxTexels = int64_t{1} << 28;

// Reads subimage 0 of an opened input into RGBA floats, expanding grey and grey-alpha images.
absl::StatusOr<Texture> ReadOpened(OIIO::ImageInput& in, const std::string& name,
                                   ColorSpace color_space) {
  const OIIO::ImageSpec& spec = in.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    return absl::InvalidArgumentError(absl::StrCat(name, ": empty image"));
  }
  if (int64_t{spec.width} * spec.height > kMaxTexels) {
    return absl::InvalidArgumentError(absl::StrCat(name, ": ", spec.width, "x", spec.height,
                                                   " texels, more than textures may have"));
  }
  const int channels = std::min(spec.nchannels, 4);
  const size_t texels = static_cast<size_t>(spec.width) * spec.height;
  std::vector<float> stored(texels * channels);
  // Volume images keep their first slice: a material samples 2D images only.
  if (!in.read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, stored.data())) {
    return absl::InvalidArgumentError(
        absl::StrCat(name, ": cannot decode the image: ", in.geterror()));
  }

  Texture texture;
  texture.name = name;
  texture.width = spec.width;
  texture.height = spec.height;
  texture.rgba.resize(texels * 4);
  for (size_t t = 0; t < texels; ++t) {
    const float* s = &stored[t * channels];
    float* d = &texture.rgba[t * 4];
    switch (channels) {
      case 1:  // grey
        d[0] = d[1] = d[2] = s[0];
        d[3] = 1.f;
        break;
      case 2:  // grey, alpha
        d[0] = d[1] = d[2] = s[0];
        d[3] = s[1];
        break;
      default:
        d[0] = s[0];
        d[1] = s[1];
        d[2] = s[2];
        d[3] = channels == 4 ? s[3] : 1.f;
    }
    // Alpha is linear coverage in every colour space.
    if (color_space == ColorSpace::kSrgb) {
      for (int c = 0; c < 3; ++c) d[c] = SrgbToLinear(d[c]);
    }
  }
  return texture;
}

// glTF's alpha is straight (not premultiplied), as is an OBJ map_Kd's; OpenImageIO would
// premultiply PNG's colours by alpha unless told not to, darkening the texels of cut-outs.
OIIO::ImageSpec OpenConfig() {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  return config;
}

}  // namespace

float SrgbToLinear(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

absl::StatusOr<Texture> DecodeImage(const unsigned char* bytes, size_t size,
                                    const std::string& extension_hint, const std::string& name,
                                    ColorSpace color_space) {
  // OpenImageIO picks its reader from a file name's extension; the magic numbers of the two
  // formats glTF allows outrank a mime type or URI that may be wrong.
  std::string extension = extension_hint;
  if (size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0) {
    extension = "png";
  } else if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) {
    extension = "jpg";
  }
  if (extension.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(name, ": not a PNG or JPEG image"));
  }
  try {
    OIIO::Filesystem::IOMemReader reader(bytes, size);
    OIIO::ImageSpec config = OpenConfig();
    // OpenImageIO 2.4 drops the ioproxy argument when a config is given too (the reader then
    // looks for a file named memory.png); the config's own ioproxy hint is honoured.
    OIIO::Filesystem::IOProxy* proxy = &reader;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    std::unique_ptr<OIIO::ImageInput> in =
        OIIO::ImageInput::open(absl::StrCat("memory.", extension), &config, &reader);
    if (!in) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, ": cannot decode the image: ", OIIO::geterror()));
    }
    return ReadOpened(*in, name, color_space);
  } catch (const std::exception& e) {  // std::bad_alloc, or a reader's own exception
    return absl::InvalidArgumentError(absl::StrCat(name, ": cannot decode the image: ", e.what()));
  }
}

absl::StatusOr<Texture> ReadImageFile(const std::string& path, ColorSpace color_space) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    return absl::NotFoundError(absl::StrCat(path, ": no such image file"));
  }
  try {
    const OIIO::ImageSpec config = OpenConfig();
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path, &config);
    if (!in) {
      return absl::InvalidArgumentError(
          absl::StrCat(path, ": cannot decode the image: ", OIIO::geterror()));
    }
    return ReadOpened(*in, path, color_space);
  } catch (const std::exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": cannot decode the image: ", e.what()));
  }
}

}  // namespace tessera::render
