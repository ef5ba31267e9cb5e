// The on-disk side of the module cache: program modules stored by content hash, so that a device
// never needs the host's path (docs/programs.md "How modules reach devices": remote workers receive
// modules by content hash and cache them). A module is the file `<directory>/<hash>.so`, written
// once through a temporary file and a rename: a reader never sees a partial file, and workers that
// share a directory (local:N) only race to store identical bytes.
#ifndef TESSERA_WORKER_CORE_MODULE_STORE_H_
#define TESSERA_WORKER_CORE_MODULE_STORE_H_

#include <cstdint>
#include <map>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "google/protobuf/repeated_ptr_field.h"
#include "tessera/scheduler/module_cache_files.h"
#include "tessera/scheduler/module_hash.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

using scheduler::IsModuleHash;  // 64 lowercase hex digits: also a safe file name
using scheduler::ModuleHash;    // the wire's module hash, as the host computes it

// $TESSERA_MODULE_CACHE, else $TESSERA_CACHE_DIR (where the host compiles modules, so that a host
// that moved its cache keeps its in-process device's copies there too), else
// $XDG_CACHE_HOME/tessera/modules, else ~/.cache/tessera/modules.
std::string DefaultModuleCacheDir();

// `dir`, created if missing; if it cannot be created or written, a private temporary directory
// instead, announced by one line on stderr. A device must not fail for want of a cache.
std::string PrepareModuleCacheDir(const std::string& dir);

// Removes the temporary directories PrepareModuleCacheDir fell back to in this process (also run
// at exit; a worker's shutdown, which skips exit handlers, calls it itself): they hold copies
// that nothing else will use.
void RemoveTemporaryModuleCaches();

std::string ModuleFilePath(const std::string& dir, const std::string& hash);

// The whole of the regular file at `path` in `out`; false for anything else, or a read error. A
// directory or a FIFO under a module's name reads as missing instead of throwing or blocking.
bool ReadWholeFile(const std::string& path, std::string* out);

// Whether `dir` holds module `hash` with the bytes the hash names.
bool HasModuleFile(const std::string& dir, const std::string& hash);

// Stores `bytes`, already checked against `hash`, unless `dir` holds that module already.
absl::Status WriteModuleFile(const std::string& dir, const std::string& hash,
                             absl::string_view bytes);

// Marks module `hash` as just used (its modification time), so that trimming keeps it longest.
void TouchModuleFile(const std::string& dir, const std::string& hash);

// The cache's bound and trimming, shared with the host's compile cache (module_cache_files.h).
using scheduler::ModuleCacheLimitBytes;
using scheduler::TrimModuleCache;

// The modules of a delta, whole, by hash. Slices of one module must arrive in order and add up to
// its total_size; modules of at most kMaxModuleBytes. INVALID_ARGUMENT otherwise. Does not check
// the bytes against their hash (ModuleCache::Store does).
inline constexpr uint64_t kMaxModuleBytes = uint64_t{1} << 30;
absl::StatusOr<std::map<std::string, std::string>> AssembleModules(
    const google::protobuf::RepeatedPtrField<v1::ModuleChunk>& chunks);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_MODULE_STORE_H_
