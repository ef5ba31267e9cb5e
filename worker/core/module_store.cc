#include "module_store.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <vector>

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "tessera/scheduler/log.h"

namespace tessera::worker {
namespace fs = std::filesystem;
namespace {

const char* Env(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : nullptr;
}

// The fallback directories of this process, removed when it ends.
struct TemporaryCacheList {
  std::mutex mu;
  std::vector<std::string> dirs;
};
TemporaryCacheList& TemporaryCaches() {
  static auto* list = new TemporaryCacheList;  // never destroyed: used by an exit handler
  return *list;
}

// Fallback directories are named tessera-modules-<pid>-XXXXXX. A process killed by a signal (a
// worker whose host crashed dies of SIGKILL) runs no exit handler, so its directory and the
// modules in it would stay for good: the next process that falls back removes those of
// processes that are gone.
constexpr char kTemporaryPrefix[] = "tessera-modules-";

void RemoveStaleTemporaryCaches(const fs::path& root) {
  DIR* dir = opendir(root.c_str());
  if (dir == nullptr) return;
  while (dirent* entry = readdir(dir)) {
    const std::string name = entry->d_name;
    if (name.rfind(kTemporaryPrefix, 0) != 0) continue;
    const std::string rest = name.substr(sizeof(kTemporaryPrefix) - 1);
    const size_t dash = rest.find('-');
    if (dash == std::string::npos || dash == 0) continue;  // an older name: no owner to check
    long pid = 0;
    if (std::sscanf(rest.substr(0, dash).c_str(), "%ld", &pid) != 1 || pid <= 0) continue;
    const fs::path path = root / name;
    struct stat st {};
    if (lstat(path.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != geteuid()) continue;
    if (kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  }
  closedir(dir);
}

}  // namespace

// Only a regular file counts: something else under a module's name (a directory, a FIFO) reads
// as not stored, so that the module is sent and the write reports it, instead of the read throwing
// (a directory) or the open blocking for good with the cache's lock held (a FIFO).
bool ReadWholeFile(const std::string& path, std::string* out) {
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st {};
  bool ok = fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  out->clear();
  if (ok) out->reserve(static_cast<size_t>(st.st_size));
  char buffer[1 << 16];
  while (ok) {
    const ssize_t n = read(fd, buffer, sizeof(buffer));
    if (n == 0) break;
    if (n < 0) {
      ok = errno == EINTR;
      continue;
    }
    out->append(buffer, static_cast<size_t>(n));
  }
  close(fd);
  return ok;
}

std::string DefaultModuleCacheDir() {
  if (const char* dir = Env("TESSERA_MODULE_CACHE")) return dir;
  if (const char* dir = Env("TESSERA_CACHE_DIR")) return dir;
  if (const char* xdg = Env("XDG_CACHE_HOME")) return absl::StrCat(xdg, "/tessera/modules");
  const char* home = Env("HOME");
  return absl::StrCat(home != nullptr ? home : "/tmp", "/.cache/tessera/modules");
}

std::string PrepareModuleCacheDir(const std::string& dir) {
  std::error_code ec;
  std::string why;
  if (dir.empty()) {
    why = "no directory given";
  } else if (fs::create_directories(dir, ec); ec) {
    why = ec.message();
  } else if (access(dir.c_str(), W_OK | X_OK) != 0) {
    why = std::strerror(errno);
  } else {
    return dir;
  }
  fs::path temp_root = fs::temp_directory_path(ec);
  if (ec) temp_root = "/tmp";
  RemoveStaleTemporaryCaches(temp_root);
  std::string temp =
      (temp_root / absl::StrCat(kTemporaryPrefix, static_cast<long>(getpid()), "-XXXXXX")).string();
  if (mkdtemp(temp.data()) == nullptr) {
    log::Error(log::Component::kWorker,
               "module cache %s is not usable (%s), nor is a temporary one", dir, why);
    return dir;  // storing a module then fails with a message naming the directory
  }
  log::Warn(log::Component::kWorker, "module cache %s is not usable (%s); using %s instead", dir,
            why, temp);
  static const bool kRemovedAtExit = std::atexit(RemoveTemporaryModuleCaches) == 0;
  (void)kRemovedAtExit;
  std::lock_guard<std::mutex> lock(TemporaryCaches().mu);
  TemporaryCaches().dirs.push_back(temp);
  return temp;
}

void RemoveTemporaryModuleCaches() {
  std::lock_guard<std::mutex> lock(TemporaryCaches().mu);
  for (const std::string& dir : TemporaryCaches().dirs) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  TemporaryCaches().dirs.clear();
}

std::string ModuleFilePath(const std::string& dir, const std::string& hash) {
  return absl::StrCat(dir, "/", hash, ".so");
}

bool HasModuleFile(const std::string& dir, const std::string& hash) {
  std::string bytes;
  return ReadWholeFile(ModuleFilePath(dir, hash), &bytes) && ModuleHash(bytes) == hash;
}

absl::Status WriteModuleFile(const std::string& dir, const std::string& hash,
                             absl::string_view bytes) {
  // A file that does not match its name (a write cut short by a crash) is replaced below.
  if (HasModuleFile(dir, hash)) return absl::OkStatus();
  std::error_code ec;
  // Again here: a cache directory may be cleaned away while a process runs.
  fs::create_directories(dir, ec);
  const std::string path = ModuleFilePath(dir, hash);
  const std::string temp = absl::StrCat(path, ".", getpid(), "-", std::random_device()(), ".tmp");
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      const int error = errno;
      fs::remove(temp, ec);
      return absl::InternalError(absl::StrCat("cannot store program module ", hash, " in ", dir,
                                              ": ", std::strerror(error)));
    }
  }
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    return absl::InternalError(
        absl::StrCat("cannot store program module ", path, ": ", ec.message()));
  }
  return absl::OkStatus();
}

void TouchModuleFile(const std::string& dir, const std::string& hash) {
  scheduler::TouchCacheFile(ModuleFilePath(dir, hash));
}

absl::StatusOr<std::map<std::string, std::string>> AssembleModules(
    const google::protobuf::RepeatedPtrField<v1::ModuleChunk>& chunks) {
  std::map<std::string, std::string> modules;
  std::map<std::string, uint64_t> totals;
  for (const v1::ModuleChunk& c : chunks) {
    const std::string& hash = c.module_hash();
    if (!IsModuleHash(hash)) {
      return absl::InvalidArgumentError(absl::StrCat(
          "program module slice names no module hash ('", absl::CEscape(hash.substr(0, 80)),
          "'; expected 64 lowercase hex digits of SHA-256)"));
    }
    auto [total, first] = totals.emplace(hash, c.total_size());
    std::string& bytes = modules[hash];
    if (first) {
      if (c.total_size() == 0 || c.total_size() > kMaxModuleBytes) {
        return absl::InvalidArgumentError(absl::StrCat("program module ", hash, " is ",
                                                       c.total_size(), " bytes (1 byte to ",
                                                       kMaxModuleBytes, " bytes)"));
      }
      // Only what this slice brings: a size is a claim until its bytes arrive, and reserving
      // every claimed size up front let a delta naming many modules exhaust the address space.
      bytes.reserve(c.data().size());
    }
    if (c.total_size() != total->second) {
      return absl::InvalidArgumentError(absl::StrCat("slices of program module ", hash,
                                                     " disagree on its size (", total->second,
                                                     " and ", c.total_size(), " bytes)"));
    }
    if (c.offset() != bytes.size() || c.data().size() > total->second - bytes.size()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "program module ", hash, ": slice [", c.offset(), ", +", c.data().size(),
          ") does not continue the ", bytes.size(), " of ", total->second, " bytes received"));
    }
    bytes.append(c.data());
  }
  for (const auto& [hash, bytes] : modules) {
    if (bytes.size() != totals[hash]) {
      return absl::InvalidArgumentError(absl::StrCat("program module ", hash, ": only ",
                                                     bytes.size(), " of ", totals[hash],
                                                     " bytes arrived"));
    }
  }
  return modules;
}

}  // namespace tessera::worker
