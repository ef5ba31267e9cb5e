// Program modules: shared libraries built from OptiX-style C++, loaded once per process and
// described by the registry that tessera/device.h builds inside them.
#ifndef TESSERA_WORKER_CORE_MODULE_H_
#define TESSERA_WORKER_CORE_MODULE_H_

#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "tessera/detail/module_abi.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

enum class Semantic {
  kUser,
  kLaunchIndex,
  kLaunchDim,
  kCurrentRay,
  kPayload,
  kDistance,
  kCurrentTime,  // rtCurrentTime: the time of the ray being traced (0 in a launch's own programs)
  kAttribute,
  kCallable,  // rtCallableProgram: the slot holds the engine's binding of the program it names
};

struct ModuleVariable {
  std::string name;
  Semantic semantic = Semantic::kUser;
  std::string attribute;   // attribute name when semantic == kAttribute
  std::string annotation;  // without quotes
  std::string type_name;
  size_t size = 0;
  std::vector<unsigned char> initial;  // the static initializer (or zeros)
  void* (*address)() = nullptr;
};

struct ModuleBuffer {
  std::string name;
  size_t element_size = 0;
  unsigned dimensionality = 1;
};

// One rtTextureSampler declaration (tessera/detail/texture.h).
struct ModuleTexture {
  std::string name;
  size_t element_size = 0;
  unsigned dimensionality = 1;  // 1, 2, 3 or a cudaTextureType* value
  unsigned read_mode = 0;       // cudaTextureReadMode
};

class Module {
 public:
  int index() const { return index_; }
  const std::string& path() const { return path_; }
  const std::vector<ModuleVariable>& variables() const { return variables_; }
  const std::vector<ModuleBuffer>& buffers() const { return buffers_; }
  const std::vector<ModuleTexture>& textures() const { return textures_; }
  // Variables whose value belongs to one invocation (ray, payload, distance, attributes): what a
  // suspended program needs back after a nested call, and their total size.
  const std::vector<unsigned>& per_call() const { return per_call_; }
  size_t per_call_bytes() const { return per_call_bytes_; }
  // The calling thread's slot addresses, one per variable (cached per thread).
  void* const* Slots() const;
  // Whether this is an OptiX 7 module (optix_device.h's tessera_optix7_module_init, which the
  // cache called with the OptiX 7 engine's table): it has entry functions and a launch-parameter
  // variable, none of the OptiX 3 registry (variables, buffers, textures stay empty).
  bool optix7() const { return optix7_; }
  // Whether it was compiled with fast math (TESSERA_MODULE_FLAG_FAST_MATH,
  // TESSERA_OPTIX7_MODULE_FLAG_FAST_MATH): launches that run it flush denormals to zero
  // (float_mode.h, docs/fast_math.md).
  bool fast_math() const { return fast_math_; }
  // Whether its initial-exec build was loaded (static_tls.h): its programs reach their variables
  // without a __tls_get_addr call.
  bool initial_exec() const { return initial_exec_; }
  // The module's own global variable `name` and its size in bytes; null if it defines none.
  void* Data(const std::string& name, size_t* size) const;
  // Null if the module itself defines no global function of that name. Cached: every launch
  // plan binds each (program, scope) pair, and dlsym plus two dladdr1 calls per binding were a
  // sixth of rebuilding a plan of 10,000 instances.
  void* Function(const std::string& name) const;

 private:
  friend class ModuleCache;
  int index_ = 0;
  std::string path_;
  void* handle_ = nullptr;
  const TesseraModuleInfo* info_ = nullptr;
  bool optix7_ = false;
  bool fast_math_ = false;
  bool initial_exec_ = false;
  std::vector<ModuleVariable> variables_;
  std::vector<ModuleBuffer> buffers_;
  std::vector<ModuleTexture> textures_;
  std::vector<unsigned> per_call_;
  size_t per_call_bytes_ = 0;
  mutable std::mutex functions_mu_;
  mutable std::unordered_map<std::string, void*> functions_;
};

// Program modules by content hash (state.proto Program.module_hash). Bytes a host sends are kept
// in an on-disk cache directory (module_store.h) and loaded from there, so a device never needs
// the host's path. A module is loaded once and never unloaded (programs may still run from it).
//
// In-process devices go through the cache too rather than loading the host's path: one code path
// for every device, and the file loaded is immutable under its hash, where the host's file may be
// rebuilt after rtProgramCreateFromPTXFile read it. The cost is one copy of each module in the
// cache directory, written once, and hashing its bytes once per device.
class ModuleCache {
 public:
  // The process-wide cache that devices use.
  static ModuleCache& Get();

  // `directory` empty: DefaultModuleCacheDir(), resolved at first use.
  explicit ModuleCache(std::string directory = "");

  // Later stores and loads use `directory` (empty: the default); loaded modules stay loaded.
  void SetDirectory(std::string directory);
  // The directory in use, created if missing (PrepareModuleCacheDir).
  std::string directory();

  // Checks module bytes received from a host against their hash (INVALID_ARGUMENT naming the
  // module on mismatch) and stores them, unless the directory holds them already.
  absl::Status Store(const std::string& hash, absl::string_view bytes);
  // Whether Load(hash) needs no bytes from the host: loaded, or stored intact in the directory.
  bool Has(const std::string& hash);
  // `origin` (the host's path) names the module in messages.
  absl::StatusOr<const Module*> Load(const std::string& hash, absl::string_view origin = "");

  // For Replica::Apply, after its other checks and before it changes anything: every program of
  // `delta` must name a module that the delta carries (checked against its hash, INVALID_ARGUMENT
  // if it does not match, then stored) or that Has() finds (FAILED_PRECONDITION if not).
  absl::Status Receive(const v1::StateDelta& delta);

 private:
  const std::string& DirectoryLocked();
  // Whether the directory holds module `hash` intact, and marks it used if so: a file check for
  // a hash known intact (another process sharing the directory may have trimmed it since), the
  // full check otherwise.
  bool OnDiskLocked(const std::string& hash);

  // Guards everything below. Held while a module file is read, written or loaded: those happen
  // once per module, and concurrent Applies of one module must not write it twice.
  std::mutex mu_;
  std::string requested_;  // as set; empty: the default
  std::string directory_;  // resolved from requested_ at first use; empty until then
  std::unordered_set<std::string> stored_;  // hashes known intact in directory_
  std::unordered_map<std::string, std::unique_ptr<Module>> modules_;  // by hash
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_MODULE_H_
