// Writing rendered images with OpenImageIO.
#ifndef TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_
#define TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_

#include <string>

#include "tutorial/image.h"

namespace tessera::tutorial {

enum class ImageFormat { kPng, kExr };

// The format for `path` by its extension (case-insensitive); throws TutorialError for others.
ImageFormat FormatForPath(const std::string& path);

// The directory part of `path` ("." for a bare name).
std::string DirectoryOf(const std::string& path);

// The file a write to `path` lands in: `path` with its symlinks followed, to a file that may not
// exist yet (the link stays a link).
std::string OutputTarget(const std::string& path);

// Throws TutorialError when `format` cannot hold a width x height image (PNG: 1,000,000 pixels
// a side, libpng's limit), so that the render is not done for nothing.
void CheckImageSize(ImageFormat format, int width, int height);

// Writes PNG as 8-bit RGBA (clamped) or EXR as float RGBA, by the extension of `path`: encoded in
// memory, written to a new file beside `path` (or beside the file a symlink `path` names) and
// renamed over it, so that a failure leaves the previous file as it was. Throws TutorialError
// naming the reason on failure (a full disk, say).
void WriteImage(const std::string& path, const Image& image);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_IMAGE_IO_H_
