#include "tutorial/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "tutorial/rt_check.h"

namespace tessera::tutorial {
namespace {

std::string Errno() { return std::strerror(errno); }

// The image encoded in memory: OIIO's PNG writer does not report a failed write (a full disk
// left a truncated file and success), so the bytes reach the disk through checked calls below.
std::vector<unsigned char> Encode(const std::string& path, const Image& image) {
  const ImageFormat format = FormatForPath(path);
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path, &memory);
  if (!out) throw TutorialError("cannot write '" + path + "': " + OIIO::geterror());
  if (!out->supports("ioproxy")) {
    throw TutorialError("cannot write '" + path + "': this OpenImageIO cannot encode " +
                        out->format_name() + " in memory");
  }
  OIIO::ImageSpec spec(image.width, image.height, 4,
                       format == ImageFormat::kPng ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
  spec.attribute("Software", "tessera-tutorial");
  // OIIO converts the float pixels, clamping to [0, 1] for 8-bit PNG.
  if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data()) ||
      !out->close()) {
    throw TutorialError("cannot write '" + path + "': " + out->geterror());
  }
  return bytes;
}

// Holds SIGINT, SIGTERM and SIGHUP back for its lifetime; they arrive when it ends.
class DeferStopSignals {
 public:
  DeferStopSignals() {
    sigset_t stop;
    sigemptyset(&stop);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&stop, sig);
    pthread_sigmask(SIG_BLOCK, &stop, &saved_);
  }
  ~DeferStopSignals() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  DeferStopSignals(const DeferStopSignals&) = delete;
  DeferStopSignals& operator=(const DeferStopSignals&) = delete;

 private:
  sigset_t saved_;
};

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

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string OutputTarget(const std::string& path) {
  std::string target = path;
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit on links in a path
    struct stat st {};
    if (lstat(target.c_str(), &st) != 0 || !S_ISLNK(st.st_mode)) return target;
    char link[PATH_MAX];
    const ssize_t n = readlink(target.c_str(), link, sizeof(link) - 1);
    if (n < 0) throw TutorialError("cannot write '" + path + "': " + Errno());
    const std::string next(link, static_cast<size_t>(n));
    target = next.front() == '/' ? next : DirectoryOf(target) + "/" + next;
  }
  throw TutorialError("cannot write '" + path + "': too many levels of symbolic links");
}

ImageFormat FormatForPath(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const size_t name = slash == std::string::npos ? 0 : slash + 1;
  std::string ext;
  if (dot != std::string::npos && dot >= name) ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".png" && ext != ".exr") {
    throw TutorialError("cannot write '" + path + "': unsupported extension '" + ext +
                        "' (use .png or .exr)");
  }
  if (dot == name) {
    throw TutorialError("cannot write '" + path + "': the file needs a name before '" + ext + "'");
  }
  return ext == ".png" ? ImageFormat::kPng : ImageFormat::kExr;
}

void CheckImageSize(ImageFormat format, int width, int height) {
  // libpng refuses wider or taller images (PNG_USER_WIDTH_MAX / HEIGHT_MAX), after the render.
  constexpr int kPngMaxSide = 1000000;
  if (format == ImageFormat::kPng && (width > kPngMaxSide || height > kPngMaxSide)) {
    throw TutorialError("a PNG image can be at most " + std::to_string(kPngMaxSide) +
                        " pixels wide and high (use .exr for " + std::to_string(width) + "x" +
                        std::to_string(height) + ")");
  }
}

void WriteImage(const std::string& path, const Image& image) {
  const std::vector<unsigned char> bytes = Encode(path, image);
  const std::string target = OutputTarget(path);
  auto fail = [&](const std::string& reason) {
    throw TutorialError("cannot write '" + path + "': " + reason);
  };
  struct stat st {};
  const bool exists = stat(target.c_str(), &st) == 0;
  if (exists && !S_ISREG(st.st_mode)) {
    // A device or a pipe (/dev/stdout, say) is written as it is: it cannot be replaced.
    const int fd = open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) fail(Errno());
    const bool written = WriteAll(fd, bytes);
    const std::string reason = Errno();
    if (close(fd) != 0 || !written) fail(written ? Errno() : reason);
    return;
  }
  // Into a new file beside the target, renamed over it once complete: a failed or interrupted
  // write leaves the previous image (or no file), never a truncated one. Ctrl-C waits for the
  // few system calls that takes, so that no temporary file is left behind either.
  const DeferStopSignals defer;
  std::string temp = DirectoryOf(target) + "/.tessera-tutorial-XXXXXX";
  const int fd = mkstemp(temp.data());
  if (fd < 0) fail(Errno());
  // The permissions a new file would get, or those of the file it replaces.
  mode_t mode = st.st_mode & 07777;
  if (!exists) {
    const mode_t mask = umask(0);
    umask(mask);
    mode = 0666 & ~mask;
  }
  const bool written = fchmod(fd, mode) == 0 && WriteAll(fd, bytes) && fsync(fd) == 0;
  const std::string reason = Errno();
  if (close(fd) != 0 || !written || rename(temp.c_str(), target.c_str()) != 0) {
    const std::string why = written ? Errno() : reason;
    unlink(temp.c_str());
    fail(why);
  }
}

}  // namespace tessera::tutorial
