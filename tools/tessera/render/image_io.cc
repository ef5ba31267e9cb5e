#include "tools/tessera/render/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "absl/strings/str_cat.h"

#ifndef TESSERA_VERSION_STRING
#error "TESSERA_VERSION_STRING must be the project's version"
#endif

namespace tessera::render {
namespace {

std::string Errno() { return std::strerror(errno); }

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Linear to sRGB's transfer function, for 8-bit files.
float EncodeSrgb(float v) {
  if (!(v > 0.f)) return 0.f;  // NaN too
  if (v >= 1.f) return 1.f;
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

// The image's pixels interleaved as the file's channels list them, and that list.
struct Pixels {
  OIIO::ImageSpec spec;
  std::vector<float> data;
};

Pixels Layout(ImageFormat format, const RenderedImage& image, bool exr_float) {
  const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  Pixels p;
  if (format == ImageFormat::kExr) {
    const OIIO::TypeDesc colour = exr_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::HALF;
    p.spec = OIIO::ImageSpec(image.width, image.height, 11, colour);
    p.spec.channelnames = {"R",        "G",        "B",        "A",        "albedo.R", "albedo.G",
                           "albedo.B", "normal.X", "normal.Y", "normal.Z", "depth.Z"};
    p.spec.channelformats.assign(11, colour);
    p.spec.channelformats[10] = OIIO::TypeDesc::FLOAT;  // half overflows past 65504
    p.spec.alpha_channel = 3;
    p.spec.attribute("compression", "zip");
    p.data.resize(count * 11);
    for (size_t i = 0; i < count; ++i) {
      float* d = &p.data[i * 11];
      std::copy_n(&image.rgba[i * 4], 4, d);
      std::copy_n(&image.albedo[i * 3], 3, d + 4);
      std::copy_n(&image.normal[i * 3], 3, d + 7);
      d[10] = image.depth[i];
    }
    return p;
  }
  const bool png = format == ImageFormat::kPng;
  p.spec = OIIO::ImageSpec(image.width, image.height, 3,
                           png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
  p.data.resize(count * 3);
  for (size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const float v = image.rgba[i * 4 + c];
      p.data[i * 3 + c] = png ? EncodeSrgb(v) : (std::isfinite(v) ? std::max(v, 0.f) : 0.f);
    }
  }
  if (png) p.spec.attribute("oiio:ColorSpace", "sRGB");
  return p;
}

// PNG text chunks hold strings only (OIIO drops other attributes there), so PNG gets every
// value as a string; OpenEXR keeps numbers as numbers.
void AddMetadata(OIIO::ImageSpec& spec, const ImageMetadata& m, bool strings_only) {
  spec.attribute("Software", SoftwareName());
  spec.attribute("tessera:version", TESSERA_VERSION_STRING);
  spec.attribute("tessera:scene", m.scene);
  spec.attribute("tessera:camera", m.camera);
  auto number = [&](const char* name, auto value) {
    if (strings_only) {
      spec.attribute(name, absl::StrCat(value));
    } else {
      spec.attribute(name, value);
    }
  };
  number("tessera:samples", static_cast<int>(m.samples));
  number("tessera:spp", static_cast<int>(m.spp));
  number("tessera:seed", static_cast<unsigned>(m.seed));
  number("tessera:max_depth", m.max_depth);
  number("tessera:frame", m.frame);
  number("tessera:time", static_cast<float>(m.time));
}

// Writes all of `bytes` to `fd`; false with errno set when it could not.
bool WriteAll(int fd, const std::vector<unsigned char>& bytes) {
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

}  // namespace

std::string SoftwareName() { return absl::StrCat("tessera ", TESSERA_VERSION_STRING); }

absl::StatusOr<ImageFormat> FormatForPath(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  std::string ext;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    ext = path.substr(dot + 1);
  }
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "png") return ImageFormat::kPng;
  if (ext == "exr") return ImageFormat::kExr;
  if (ext == "hdr") return ImageFormat::kHdr;
  return absl::InvalidArgumentError("cannot write '" + path +
                                    "': the extension must be .png, .exr or .hdr");
}

absl::Status CheckWritable(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    return absl::InvalidArgumentError("cannot write '" + path + "': it is a directory");
  }
  const std::string dir = DirectoryOf(path);
  if (stat(dir.c_str(), &st) != 0) {
    return absl::NotFoundError("cannot write '" + path + "': directory '" + dir + "': " + Errno());
  }
  if (!S_ISDIR(st.st_mode) || access(dir.c_str(), W_OK | X_OK) != 0) {
    return absl::PermissionDeniedError("cannot write '" + path + "': directory '" + dir +
                                       "' is not writable");
  }
  return absl::OkStatus();
}

absl::Status WriteImage(const std::string& path, const RenderedImage& image,
                        const ImageMetadata& metadata, bool exr_float) {
  const absl::StatusOr<ImageFormat> format = FormatForPath(path);
  if (!format.ok()) return format.status();
  Pixels pixels = Layout(*format, image, exr_float);
  if (*format != ImageFormat::kHdr) {
    AddMetadata(pixels.spec, metadata, *format == ImageFormat::kPng);
  }

  // Encoded in memory first: OIIO's PNG writer does not report a failed write, so the bytes
  // reach the disk through checked calls.
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path, &memory);
  if (!out) return absl::InternalError("cannot write '" + path + "': " + OIIO::geterror());
  if (!out->supports("ioproxy")) {
    return absl::InternalError("cannot write '" + path + "': this OpenImageIO cannot encode " +
                               out->format_name() + " in memory");
  }
  if (!out->open(path, pixels.spec) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data.data()) || !out->close()) {
    return absl::InternalError("cannot write '" + path + "': " + out->geterror());
  }

  const std::string temp = absl::StrCat(DirectoryOf(path), "/.", path.substr(path.rfind('/') + 1),
                                        ".", getpid(), ".tmp");
  const int fd = open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) return absl::InternalError("cannot write '" + temp + "': " + Errno());
  const bool written = WriteAll(fd, bytes);
  const std::string why = written ? "" : Errno();
  if (close(fd) != 0 && written) {
    unlink(temp.c_str());
    return absl::InternalError("cannot write '" + path + "': " + Errno());
  }
  if (!written) {
    unlink(temp.c_str());
    return absl::InternalError("cannot write '" + path + "': " + why);
  }
  if (rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = Errno();
    unlink(temp.c_str());
    return absl::InternalError("cannot write '" + path + "': " + reason);
  }
  return absl::OkStatus();
}

}  // namespace tessera::render
