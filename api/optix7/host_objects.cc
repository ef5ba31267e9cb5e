#include "host_objects.h"

#include <atomic>
#include <utility>

#include "accuracy_flags.h"

namespace tessera::optix7 {
namespace {

struct Entry {
  ObjectKind kind;
  std::shared_ptr<void> object;
  const DeviceContext* owner;
};

class Registry {
 public:
  void Add(ObjectKind kind, std::shared_ptr<void> object, const DeviceContext* owner) {
    std::lock_guard<std::mutex> lock(mutex_);
    const void* key = object.get();
    live_[key] = Entry{kind, std::move(object), owner};
  }
  std::shared_ptr<void> Find(ObjectKind kind, const void* handle) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = live_.find(handle);
    if (it == live_.end() || it->second.kind != kind) return nullptr;
    return it->second.object;
  }
  // The object is released after the lock: its destructor may release others.
  bool Remove(ObjectKind kind, const void* handle) {
    std::shared_ptr<void> released;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = live_.find(handle);
      if (it == live_.end() || it->second.kind != kind) return false;
      released = std::move(it->second.object);
      live_.erase(it);
    }
    return true;
  }
  void RemoveOwnedBy(const DeviceContext* owner) {
    std::vector<std::shared_ptr<void>> released;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (auto it = live_.begin(); it != live_.end();) {
        if (it->second.owner == owner) {
          released.push_back(std::move(it->second.object));
          live_.erase(it++);
        } else {
          ++it;
        }
      }
    }
  }

 private:
  mutable std::mutex mutex_;
  absl::flat_hash_map<const void*, Entry> live_ ABSL_GUARDED_BY(mutex_);
};

Registry& Objects() {
  static Registry* registry = new Registry;  // never destroyed: handles may be used at exit
  return *registry;
}

}  // namespace

DeviceContext::DeviceContext(const OptixDeviceContextOptions& options, std::string cache_location,
                             int cuda_device)
    : validation_(options.validationMode == OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_ALL),
      cuda_device_(cuda_device),
      accuracy_flags_(api::AccuracyFromEnvironment()),
      callback_(options.logCallbackFunction),
      callback_data_(options.logCallbackData),
      callback_level_(static_cast<unsigned>(options.logCallbackLevel)) {
  cache_.location = std::move(cache_location);
}

DeviceContext::~DeviceContext() = default;

void DeviceContext::Log(unsigned level, absl::string_view tag, absl::string_view message) const {
  OptixLogCallback callback;
  void* data;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (callback_ == nullptr || level > callback_level_) return;
    callback = callback_;
    data = callback_data_;
  }
  // OptiX's messages end without a newline; the callback is called outside the lock, so that it
  // may call OptiX functions.
  while (!message.empty() && message.back() == '\n') message.remove_suffix(1);
  const std::string tag_text(tag);
  const std::string text(message);
  callback(level, tag_text.c_str(), text.c_str(), data);
}

void DeviceContext::SetLogCallback(OptixLogCallback callback, void* data, unsigned level) {
  std::lock_guard<std::mutex> lock(mutex_);
  callback_ = callback;
  callback_data_ = data;
  callback_level_ = level;
}

DeviceContext::Cache DeviceContext::cache() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cache_;
}

void DeviceContext::set_cache(const Cache& cache) {
  std::lock_guard<std::mutex> lock(mutex_);
  cache_ = cache;
}

uint64_t NextObjectId() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

void RegisterObject(ObjectKind kind, std::shared_ptr<void> object, const DeviceContext* owner) {
  Objects().Add(kind, std::move(object), owner);
}

std::shared_ptr<void> FindObject(ObjectKind kind, const void* handle) {
  if (handle == nullptr) return nullptr;
  return Objects().Find(kind, handle);
}

bool UnregisterObject(ObjectKind kind, const void* handle) {
  return handle != nullptr && Objects().Remove(kind, handle);
}

void UnregisterObjectsOf(const DeviceContext* owner) { Objects().RemoveOwnedBy(owner); }

}  // namespace tessera::optix7
