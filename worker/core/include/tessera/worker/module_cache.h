// Where this process's devices keep the program modules hosts send them (worker/core's module
// cache, by content hash): tessera-worker's --module-cache sets it.
#ifndef TESSERA_WORKER_MODULE_CACHE_H_
#define TESSERA_WORKER_MODULE_CACHE_H_

#include <string>

namespace tessera {

// Later modules are stored in and loaded from `dir`; empty restores the default
// ($TESSERA_MODULE_CACHE, else $TESSERA_CACHE_DIR, else $XDG_CACHE_HOME/tessera/modules, else
// ~/.cache/tessera/modules).
void SetModuleCacheDirectory(const std::string& dir);

// The directory in use, created if missing; a private temporary directory, announced by one line
// on stderr, if it cannot be created or written.
std::string ModuleCacheDirectory();

// Removes such temporary directories (exit handlers do it too, for processes that run them).
void RemoveTemporaryModuleCaches();

}  // namespace tessera

#endif  // TESSERA_WORKER_MODULE_CACHE_H_
