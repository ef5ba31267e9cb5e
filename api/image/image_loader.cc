// tesseraBufferCreateFromImage (tessera/image.h): OpenImageIO reads the file as 8-bit or float
// pixels, which are expanded to four channels and copied into a new buffer, bottom row first
// unless asked otherwise.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "tessera/image.h"

namespace {

thread_local std::string g_error;

RTresult Fail(RTresult code, std::string message) {
  g_error = std::move(message);
  return code;
}

// Expands one pixel of `channels` channels to RGBA (grey, grey + alpha, RGB, or RGBA and more).
template <typename T>
void ToRgba(const T* in, int channels, T opaque, T* out) {
  if (channels <= 2) {
    out[0] = out[1] = out[2] = in[0];
    out[3] = channels == 2 ? in[1] : opaque;
  } else {
    out[0] = in[0];
    out[1] = in[1];
    out[2] = in[2];
    out[3] = channels >= 4 ? in[3] : opaque;
  }
}

// Reads the whole first subimage as `T` and returns it as RGBA rows in buffer order.
template <typename T>
bool ReadRgba(OIIO::ImageInput& input, OIIO::TypeDesc type, T opaque, bool top_row_first,
              std::vector<T>& rgba, std::string& why) {
  const OIIO::ImageSpec& spec = input.spec();
  const size_t width = static_cast<size_t>(spec.width);
  const size_t height = static_cast<size_t>(spec.height);
  const int channels = spec.nchannels;
  std::vector<T> pixels(width * height * static_cast<size_t>(channels));
  if (!input.read_image(0, 0, 0, channels, type, pixels.data())) {
    why = input.geterror();
    return false;
  }
  rgba.resize(width * height * 4);
  for (size_t row = 0; row < height; ++row) {
    const size_t to = top_row_first ? row : height - 1 - row;
    for (size_t x = 0; x < width; ++x) {
      ToRgba(&pixels[(row * width + x) * static_cast<size_t>(channels)], channels, opaque,
             &rgba[(to * width + x) * 4]);
    }
  }
  return true;
}

// Makes the buffer and fills it; destroys it again if any step fails.
RTresult MakeBuffer(RTcontext context, RTformat format, size_t width, size_t height,
                    const void* texels, size_t bytes, const std::string& path, RTbuffer* buffer) {
  RTbuffer made = nullptr;
  RTresult r = rtBufferCreate(context, RT_BUFFER_INPUT, &made);
  if (r != RT_SUCCESS) return Fail(r, "rtBufferCreate failed for the image " + path);
  void* data = nullptr;
  if ((r = rtBufferSetFormat(made, format)) != RT_SUCCESS ||
      (r = rtBufferSetSize2D(made, width, height)) != RT_SUCCESS ||
      (r = rtBufferMap(made, &data)) != RT_SUCCESS) {
    rtBufferDestroy(made);
    return Fail(r, "could not make a " + std::to_string(width) + "x" + std::to_string(height) +
                       " buffer for the image " + path + " (see rtContextGetErrorString)");
  }
  std::memcpy(data, texels, bytes);
  if ((r = rtBufferUnmap(made)) != RT_SUCCESS) {
    rtBufferDestroy(made);
    return Fail(r, "rtBufferUnmap failed for the image " + path);
  }
  *buffer = made;
  g_error.clear();
  return RT_SUCCESS;
}

}  // namespace

extern "C" RTresult tesseraBufferCreateFromImage(RTcontext context, const char* path,
                                                 unsigned flags, RTbuffer* buffer) {
  if (context == nullptr || path == nullptr || buffer == nullptr) {
    return Fail(RT_ERROR_INVALID_VALUE,
                "tesseraBufferCreateFromImage: context, path and buffer must not be null");
  }
  constexpr unsigned kKnown = TESSERA_IMAGE_TOP_ROW_FIRST | TESSERA_IMAGE_FLOAT;
  if ((flags & ~kKnown) != 0) {
    return Fail(RT_ERROR_INVALID_VALUE, "tesseraBufferCreateFromImage: unknown flags " +
                                            std::to_string(flags & ~kKnown) + " for " + path);
  }
  // Alpha as the file stores it: OpenImageIO would otherwise premultiply PNG's straight alpha,
  // and the OptiX SDK's loaders hand programs the stored values.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input) {
    return Fail(RT_ERROR_FILE_NOT_FOUND,
                std::string("cannot read the image ") + path + ": " + OIIO::geterror());
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    return Fail(RT_ERROR_FILE_NOT_FOUND,
                std::string("the image ") + path + " is not a 2D image with channels");
  }
  const size_t width = static_cast<size_t>(spec.width);
  const size_t height = static_cast<size_t>(spec.height);
  const bool top_row_first = (flags & TESSERA_IMAGE_TOP_ROW_FIRST) != 0;
  std::string why;
  if (spec.format == OIIO::TypeDesc::UINT8 && (flags & TESSERA_IMAGE_FLOAT) == 0) {
    std::vector<uint8_t> rgba;
    if (!ReadRgba<uint8_t>(*input, OIIO::TypeDesc::UINT8, 255, top_row_first, rgba, why)) {
      return Fail(RT_ERROR_FILE_NOT_FOUND,
                  std::string("cannot read the image ") + path + ": " + why);
    }
    return MakeBuffer(context, RT_FORMAT_UNSIGNED_BYTE4, width, height, rgba.data(), rgba.size(),
                      path, buffer);
  }
  std::vector<float> rgba;
  if (!ReadRgba<float>(*input, OIIO::TypeDesc::FLOAT, 1.0f, top_row_first, rgba, why)) {
    return Fail(RT_ERROR_FILE_NOT_FOUND, std::string("cannot read the image ") + path + ": " + why);
  }
  return MakeBuffer(context, RT_FORMAT_FLOAT4, width, height, rgba.data(),
                    rgba.size() * sizeof(float), path, buffer);
}

extern "C" const char* tesseraImageGetErrorString(void) { return g_error.c_str(); }
