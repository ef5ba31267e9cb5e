// The objects behind OptiX 7's opaque handles (OptixDeviceContext, OptixModule, OptixTask,
// OptixProgramGroup, OptixPipeline) and the registry that checks a handle before anything reads
// it: a destroyed, null, made-up or wrongly typed handle is OPTIX_ERROR_INVALID_VALUE, never a
// crash. Objects hold what they name by shared_ptr (a program group its modules, a pipeline its
// groups), so destroying a module that a pipeline still uses is memory-safe; OptiX leaves that
// undefined, the pipeline keeps working here.
#ifndef TESSERA_API_OPTIX7_HOST_OBJECTS_H_
#define TESSERA_API_OPTIX7_HOST_OBJECTS_H_

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/strings/string_view.h"
#include "compile_options.h"
#include "elf_symbols.h"
#include "launch7.h"
#include "optix_types.h"

namespace tessera::optix7 {

enum class ObjectKind { kContext, kModule, kTask, kProgramGroup, kPipeline };

// Log levels of OptixLogCallback.
enum LogLevel : unsigned { kLogFatal = 1, kLogError = 2, kLogWarning = 3, kLogPrint = 4 };

// An OptixDeviceContext: the log callback, the disk cache settings and, from the first launch,
// the devices launches run on.
class DeviceContext {
 public:
  static constexpr ObjectKind kKind = ObjectKind::kContext;

  // `cuda_device`: the CUDA device the context was made on, whose Tessera device alone runs its
  // launches, or kEveryDevice (cuda_devices.h) to tile them over every device.
  DeviceContext(const OptixDeviceContextOptions& options, std::string cache_location,
                int cuda_device);
  ~DeviceContext();

  int cuda_device() const { return cuda_device_; }

  // Calls the callback when `level` is within its level. Thread-safe.
  void Log(unsigned level, absl::string_view tag, absl::string_view message) const;
  void SetLogCallback(OptixLogCallback callback, void* data, unsigned level);

  bool validation() const { return validation_; }

  // TESSERA_ACCURACY_* bits (tesseraOptixDeviceContextSetAccuracy; initially TESSERA_ACCURACY):
  // what later launches and module creations use.
  uint32_t accuracy_flags() const { return accuracy_flags_.load(std::memory_order_relaxed); }
  void set_accuracy_flags(uint32_t flags) {
    accuracy_flags_.store(flags, std::memory_order_relaxed);
  }

  // The disk cache: Tessera's module cache directory (api/src/module_compiler.h), which modules
  // this context compiles use. Disabling it is remembered and reported, but modules are still
  // files there: workers load them by path.
  struct Cache {
    bool enabled = true;
    std::string location;
    bool location_chosen = false;  // by optixDeviceContextSetCacheLocation
    size_t low_water_mark = 0;
    size_t high_water_mark = 0;
  };
  Cache cache() const;
  void set_cache(const Cache& cache);

  // The context's launch target, created at the first call. Launches of one context are
  // serialized, as OptiX serializes them on a stream. `f` returns an absl::Status.
  template <typename F>
  absl::Status WithLaunchTarget(F&& f) {
    std::lock_guard<std::mutex> lock(launch_mutex_);
    if (!target_) {
      absl::StatusOr<LaunchTargetPtr> made = CreateLaunchTarget(cuda_device_);
      if (!made.ok()) return made.status();
      target_ = *std::move(made);
    }
    return f(*target_);
  }
  // Bytes launches sent and received so far (tessera/optix7_ext.h); 0 before the first.
  void TransferStats(uint64_t* sent, uint64_t* received) {
    std::lock_guard<std::mutex> lock(launch_mutex_);
    *sent = *received = 0;
    if (target_) TargetTransferStats(*target_, sent, received);
  }

 private:
  const bool validation_;
  const int cuda_device_;
  std::atomic<uint32_t> accuracy_flags_;
  mutable std::mutex mutex_;
  OptixLogCallback callback_ ABSL_GUARDED_BY(mutex_) = nullptr;
  void* callback_data_ ABSL_GUARDED_BY(mutex_) = nullptr;
  unsigned callback_level_ ABSL_GUARDED_BY(mutex_) = 0;
  Cache cache_ ABSL_GUARDED_BY(mutex_);
  std::mutex launch_mutex_;
  LaunchTargetPtr target_ ABSL_GUARDED_BY(launch_mutex_);
};

// An OptixModule: a program module in the module cache with its exported symbols, or a built-in
// intersection (optixBuiltinISModuleGet), which has no file.
struct Module {
  static constexpr ObjectKind kKind = ObjectKind::kModule;

  std::shared_ptr<DeviceContext> context;
  std::string name;                      // for messages: "<string>", a path, "built-in sphere"
  std::shared_ptr<LaunchModule> launch;  // null for a built-in intersection
  ElfSymbols symbols;
  OptixPrimitiveType builtin = OPTIX_PRIMITIVE_TYPE_CUSTOM;  // a built-in's type
  PipelineOptions options;
  int payload_values = 0;  // the most payload values its compile options allow

  bool is_builtin() const { return launch == nullptr; }
};

// An OptixTask of optixModuleCreateWithTasks: the module is complete when the task is made, so
// executing it only consumes it.
struct Task {
  static constexpr ObjectKind kKind = ObjectKind::kTask;
  std::shared_ptr<DeviceContext> context;
  std::shared_ptr<Module> module;
};

struct ProgramGroup {
  static constexpr ObjectKind kKind = ObjectKind::kProgramGroup;

  std::shared_ptr<DeviceContext> context;
  std::vector<std::shared_ptr<const Module>> modules;  // what `launch.modules` points into
  LaunchProgramGroup launch;
  OptixStackSizes stack_sizes{};
};

struct Pipeline {
  static constexpr ObjectKind kKind = ObjectKind::kPipeline;

  std::shared_ptr<DeviceContext> context;
  std::vector<std::shared_ptr<const ProgramGroup>> groups;  // what `launch.groups` points into
  LaunchPipeline launch;
  unsigned max_trace_depth = 0;
};

// The next object id of this process (program groups, pipelines): ids are never reused, so a
// device that saw an id knows its object for good (objects are immutable: version 1).
uint64_t NextObjectId();

// Live handles. A handle is the object's address.
void RegisterObject(ObjectKind kind, std::shared_ptr<void> object, const DeviceContext* owner);
std::shared_ptr<void> FindObject(ObjectKind kind, const void* handle);
// Forgets `handle`; false when it was not a live object of `kind`.
bool UnregisterObject(ObjectKind kind, const void* handle);
// Forgets every object `owner` made (optixDeviceContextDestroy destroys them, as in OptiX).
void UnregisterObjectsOf(const DeviceContext* owner);

template <typename T>
void Register(const std::shared_ptr<T>& object, const DeviceContext* owner) {
  RegisterObject(T::kKind, object, owner);
}
template <typename T>
std::shared_ptr<T> Find(const void* handle) {
  return std::static_pointer_cast<T>(FindObject(T::kKind, handle));
}

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_HOST_OBJECTS_H_
