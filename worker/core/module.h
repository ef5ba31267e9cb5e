// Program modules: shared libraries built from OptiX-style C++, loaded once per process and
// described by the registry that tessera/device.h builds inside them.
#ifndef TESSERA_WORKER_CORE_MODULE_H_
#define TESSERA_WORKER_CORE_MODULE_H_

#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "tessera/detail/module_abi.h"

namespace tessera::worker {

enum class Semantic {
  kUser,
  kLaunchIndex,
  kLaunchDim,
  kCurrentRay,
  kPayload,
  kDistance,
  kAttribute
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

class Module {
 public:
  int index() const { return index_; }
  const std::string& path() const { return path_; }
  const std::vector<ModuleVariable>& variables() const { return variables_; }
  const std::vector<ModuleBuffer>& buffers() const { return buffers_; }
  // Variables whose value belongs to one invocation (ray, payload, distance, attributes): what a
  // suspended program needs back after a nested call, and their total size.
  const std::vector<unsigned>& per_call() const { return per_call_; }
  size_t per_call_bytes() const { return per_call_bytes_; }
  // The calling thread's slot addresses, one per variable (cached per thread).
  void* const* Slots() const;
  TesseraBufferView* Views() const { return info_->buffer_views(); }
  // Null if the module has no such exported function.
  void* Function(const std::string& name) const;

 private:
  friend class ModuleCache;
  int index_ = 0;
  std::string path_;
  void* handle_ = nullptr;
  const TesseraModuleInfo* info_ = nullptr;
  std::vector<ModuleVariable> variables_;
  std::vector<ModuleBuffer> buffers_;
  std::vector<unsigned> per_call_;
  size_t per_call_bytes_ = 0;
};

// Process-wide: a module is loaded once and never unloaded (programs may still run from it).
class ModuleCache {
 public:
  static ModuleCache& Get();
  absl::StatusOr<const Module*> Load(const std::string& path);

 private:
  std::mutex mu_;
  std::unordered_map<std::string, std::unique_ptr<Module>> modules_;
  int next_index_ = 0;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_MODULE_H_
