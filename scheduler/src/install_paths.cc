#include "tessera/scheduler/install_paths.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "tessera/scheduler/log.h"

// Set by scheduler/CMakeLists.txt from GNUInstallDirs: the installed <bindir> and <includedir>
// relative to <libdir>, which `cmake --install --prefix` keeps whatever the prefix.
#ifndef TESSERA_BINDIR_FROM_LIBDIR
#define TESSERA_BINDIR_FROM_LIBDIR "../bin"
#endif
#ifndef TESSERA_INCLUDEDIR_FROM_LIBDIR
#define TESSERA_INCLUDEDIR_FROM_LIBDIR "../include"
#endif

namespace tessera::scheduler {
namespace {

// dladdr names the library as the loader found it: possibly through a symlink (whose directory
// holds no installed layout) or relative to a working directory the application may change
// later. Resolved once, at load time, while that directory is still the one it was found from.
std::string ResolveThisBinary() {
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&ResolveThisBinary), &info) != 0 &&
      info.dli_fname != nullptr && std::strchr(info.dli_fname, '/') != nullptr) {
    char resolved[PATH_MAX];
    if (realpath(info.dli_fname, resolved) != nullptr) return resolved;
    return info.dli_fname;
  }
  char buf[PATH_MAX];
  ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  return n > 0 ? std::string(buf, static_cast<size_t>(n)) : std::string();
}

const std::string& ThisBinaryPathOnce() {
  static const std::string* path = new std::string(ResolveThisBinary());
  return *path;
}

[[maybe_unused]] const bool kResolvedAtLoad = (ThisBinaryPathOnce(), true);

std::string FromThisBinary(const char* relative) {
  const std::string& self = ThisBinaryPathOnce();
  if (self.empty()) return std::string();
  return DirName(self) + "/" + relative;
}

}  // namespace

std::string ThisBinaryPath() { return ThisBinaryPathOnce(); }

std::string DirName(const std::string& path) {
  size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string InstalledWorkerPath() {
  return FromThisBinary(TESSERA_BINDIR_FROM_LIBDIR "/tessera-worker");
}

std::string InstalledIncludeDir() {
  return FromThisBinary(TESSERA_INCLUDEDIR_FROM_LIBDIR "/tessera");
}

bool RunningFromBuildTree() {
#ifdef TESSERA_BUILD_DIR
  const std::string& self = ThisBinaryPathOnce();
  const std::string build = std::string(TESSERA_BUILD_DIR) + "/";
  return self.compare(0, build.size(), build) == 0;
#else
  return false;
#endif
}

void NoteBuildTreeFallback(InstalledPart part, const std::string& missing,
                           const std::string& used) {
  if (RunningFromBuildTree()) return;
  static std::once_flag said[2];
  const bool worker = part == InstalledPart::kWorker;
  std::call_once(said[worker ? 0 : 1], [&] {
    log::Warn(log::Component::kScheduler,
              "no usable %s at %s (beside %s); using the build tree's, %s, which may be another "
              "version: reinstall, or set %s",
              worker ? "tessera-worker" : "program headers", missing, ThisBinaryPathOnce(), used,
              worker ? "TESSERA_WORKER" : "TESSERA_INCLUDE_DIR");
  });
}

}  // namespace tessera::scheduler
