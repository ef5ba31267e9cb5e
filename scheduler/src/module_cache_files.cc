#include "tessera/scheduler/module_cache_files.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/string_view.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/module_hash.h"

namespace tessera::scheduler {
namespace fs = std::filesystem;
namespace {

// The module a file name holds, "" when it is no module: a worker's `<sha256>.so` or a host
// compile's `<xxh64>.so`, or the dependency list of a host compile (`<xxh64>.deps`, one per
// source version and directory: without a bound they would pile up for good), or a module's
// initial-exec build written out beside it (`<sha256>.so.ie`, worker/core/module.cc).
absl::string_view ModuleStem(absl::string_view name) {
  if (absl::EndsWith(name, ".so.ie")) name.remove_suffix(3);
  if (absl::EndsWith(name, ".deps")) {
    absl::string_view stem = name.substr(0, name.size() - 5);
    return stem.size() == 16 && IsLowerHex(stem) ? stem : absl::string_view{};
  }
  if (!absl::EndsWith(name, ".so")) return {};
  absl::string_view stem = name.substr(0, name.size() - 3);
  return (stem.size() == 64 || stem.size() == 16) && IsLowerHex(stem) ? stem : absl::string_view{};
}

// A temporary file of a write into the cache: removable once old enough that no write can still
// be going on.
bool IsTemporary(absl::string_view name) {
  if (absl::EndsWith(name, ".tmp") || absl::EndsWith(name, ".tmp.d")) return true;  // .d: -MF
  return absl::EndsWith(name, ".cpp") && name.size() > 17 && name[16] == '.' &&
         IsLowerHex(name.substr(0, 16));
}

}  // namespace

uint64_t ModuleCacheLimitBytes() {
  constexpr uint64_t kDefaultMiB = 1024;
  uint64_t mib = kDefaultMiB;
  const char* env = std::getenv("TESSERA_MODULE_CACHE_MAX_MB");
  if (env != nullptr && *env != '\0') {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(env, &end, 10);
    // Digits only (strtoull would take "-5" as 2^64 - 5), and few enough MiB that the bytes fit
    // in 64 bits: 2^44 MiB and more wrapped around to a limit of 0 that emptied the cache.
    if (end != env && *end == '\0' && v > 0 && env[0] >= '0' && env[0] <= '9' &&
        v <= (UINT64_MAX >> 20)) {
      mib = v;
    } else if (static std::atomic<bool> warned{false}; !warned.exchange(true)) {  // once
      log::Warn(log::Component::kScheduler,
                "TESSERA_MODULE_CACHE_MAX_MB='%s' is not a positive number of MiB; using %llu", env,
                static_cast<unsigned long long>(kDefaultMiB));
    }
  }
  return mib << 20;
}

void TouchCacheFile(const std::string& path) {
  std::error_code ec;
  fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
}

size_t TrimModuleCache(const std::string& dir, uint64_t max_bytes, const std::string& keep,
                       std::chrono::seconds recent) {
  struct Entry {
    fs::path path;
    uint64_t bytes;
    fs::file_time_type used;
  };
  const auto now = fs::file_time_type::clock::now();
  std::vector<Entry> modules;
  uint64_t total = 0;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    std::error_code entry_ec;
    const std::string name = e.path().filename().string();
    const fs::file_time_type used = e.last_write_time(entry_ec);
    if (entry_ec || !e.is_regular_file(entry_ec)) continue;
    if (IsTemporary(name)) {
      if (now - used > std::chrono::hours(1)) fs::remove(e.path(), entry_ec);
      continue;
    }
    const absl::string_view stem = ModuleStem(name);
    if (stem.empty()) continue;  // not ours
    const uint64_t bytes = e.file_size(entry_ec);
    if (entry_ec) continue;
    total += bytes;
    if (stem == keep || now - used < recent) continue;
    modules.push_back({e.path(), bytes, used});
  }
  std::sort(modules.begin(), modules.end(),
            [](const Entry& a, const Entry& b) { return a.used < b.used; });
  size_t removed = 0;
  for (const Entry& m : modules) {
    if (total <= max_bytes) break;
    std::error_code remove_ec;
    if (fs::remove(m.path, remove_ec)) {
      total -= m.bytes;
      ++removed;
    }
  }
  return removed;
}

}  // namespace tessera::scheduler
