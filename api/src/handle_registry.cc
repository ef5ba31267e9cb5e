#include "handle_registry.h"

namespace tessera::api {

HandleRegistry& HandleRegistry::Get() {
  // Leaked on purpose: handles may be checked from static destructors of applications.
  static auto* registry = new HandleRegistry;
  return *registry;
}

void HandleRegistry::Add(Object* object) {
  std::lock_guard<std::mutex> lock(mu_);
  live_[object->handle()] = HandleInfo{object->kind(), object->context(), object->id(), object};
}

void HandleRegistry::Remove(Object* object) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = live_.find(object->handle());
  if (it == live_.end()) return;
  HandleInfo info = it->second;
  live_.erase(it);
  info.object = nullptr;
  if (info.kind == Kind::kContext) info.context = nullptr;
  dead_[object->handle()] = info;
  if (info.context != nullptr) dead_by_context_[info.context].insert(object->handle());
  dead_order_.push_back(object->handle());
  Trim();
}

void HandleRegistry::Trim() {
  while (dead_order_.size() > kMaxRemembered) {
    const void* handle = dead_order_.front();
    dead_order_.pop_front();
    auto dead = dead_.find(handle);
    if (dead == dead_.end()) continue;  // its context went first
    if (dead->second.context != nullptr) {
      auto by = dead_by_context_.find(dead->second.context);
      if (by != dead_by_context_.end()) {
        by->second.erase(handle);
        if (by->second.empty()) dead_by_context_.erase(by);
      }
    }
    dead_.erase(dead);
  }
}

void HandleRegistry::ForgetContext(Context* context) {
  std::lock_guard<std::mutex> lock(mu_);
  auto it = dead_by_context_.find(context);
  if (it == dead_by_context_.end()) return;
  for (const void* handle : it->second) {
    auto dead = dead_.find(handle);
    if (dead != dead_.end() && dead->second.context == context) dead_.erase(dead);
  }
  dead_by_context_.erase(it);
}

HandleRegistry::Lookup HandleRegistry::Find(const void* handle) const {
  Lookup result;
  if (handle == nullptr) return result;
  std::lock_guard<std::mutex> lock(mu_);
  if (auto it = live_.find(handle); it != live_.end()) {
    result.state = State::kLive;
    result.info = it->second;
    result.object = it->second.object;
  } else if (auto dead = dead_.find(handle); dead != dead_.end()) {
    result.state = State::kDestroyed;
    result.info = dead->second;
  }
  return result;
}

}  // namespace tessera::api
