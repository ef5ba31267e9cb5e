// The bound on a program module cache directory, shared by what writes into one: a worker's module
// cache (`<sha256>.so`, modules received by hash) and the host's compile cache (`<xxh64>.so`,
// modules compiled from source). By default both live in ~/.cache/tessera/modules, so one bound
// and one trimming policy cover the directory whoever writes it.
#ifndef TESSERA_SCHEDULER_MODULE_CACHE_FILES_H_
#define TESSERA_SCHEDULER_MODULE_CACHE_FILES_H_

#include <chrono>
#include <cstdint>
#include <string>

namespace tessera::scheduler {

// How many bytes of modules a cache directory may hold: TESSERA_MODULE_CACHE_MAX_MB (default
// 1024). A farm's workers receive every new build of every program and a host compiles every
// edit of a source; without a bound, a long-lived cache would grow until the disk is full.
uint64_t ModuleCacheLimitBytes();

// Marks a cached file as just used (its modification time), so that trimming keeps it longest.
void TouchCacheFile(const std::string& path);

// Removes the least recently used modules of `dir` until its modules take at most `max_bytes`,
// sparing the module named `keep` (file name without ".so") and every module used within
// `recent` (another process may be about to load it). Modules are `<64 hex>.so` and
// `<16 hex>.so`; other files are left alone, except temporary files older than an hour
// (`*.tmp`, and the sources of host compiles, `<16 hex>.*.cpp`): writes cut short by a crash.
// Returns how many modules it removed.
size_t TrimModuleCache(const std::string& dir, uint64_t max_bytes, const std::string& keep,
                       std::chrono::seconds recent = std::chrono::hours(1));

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_MODULE_CACHE_FILES_H_
