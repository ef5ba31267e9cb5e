// Writing rendered images with OpenImageIO.
#ifndef TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_
#define TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_

#include <string>

#include "tutorial/image.h"

namespace tessera::tutorial {

enum class ImageFormat { kPng, kExr };

// The format for `path` by its extension (case-insensitive); throws TutorialError for others.
ImageFormat FormatForPath(const std::string& path);

// Writes PNG as 8-bit RGBA (clamped) or EXR as float RGBA, by the extension of `path`.
// Throws TutorialError on failure.
void WriteImage(const std::string& path, const Image& image);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_
