// The process-wide table of live handles. A handle is checked here before it is dereferenced, so
// a null, foreign, wrong-typed or destroyed handle is reported instead of touching freed memory.
// Destroyed handles are remembered (kind, id, context) until their context goes away, so messages
// can name them and land on the right context: the latest kMaxRemembered of them, so that an
// application that creates and destroys objects in a long-lived context does not grow the table.
// Handles are tokens that are never reused (Object::handle), so an old handle cannot reach a
// later object.
#ifndef TESSERA_API_SRC_HANDLE_REGISTRY_H_
#define TESSERA_API_SRC_HANDLE_REGISTRY_H_

#include <cstdint>
#include <deque>
#include <mutex>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "object.h"

namespace tessera::api {

struct HandleInfo {
  Kind kind = Kind::kContext;
  Context* context = nullptr;  // null once the context is gone
  uint64_t id = 0;
  Object* object = nullptr;  // live handles only
};

class HandleRegistry {
 public:
  enum class State { kUnknown, kLive, kDestroyed };
  struct Lookup {
    State state = State::kUnknown;
    HandleInfo info;
    Object* object = nullptr;  // set when live
  };

  static HandleRegistry& Get();

  void Add(Object* object);
  // `object` was destroyed: it moves to the graveyard.
  void Remove(Object* object);
  // `context` was destroyed: forget its graveyard entries (they name it).
  void ForgetContext(Context* context);

  Lookup Find(const void* handle) const;

  // Destroyed handles remembered at most; older ones read as unknown handles.
  static constexpr size_t kMaxRemembered = 1 << 16;

 private:
  // Forgets the oldest graveyard entries past kMaxRemembered.
  void Trim() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mu_);

  mutable std::mutex mu_;
  absl::flat_hash_map<const void*, HandleInfo> live_ ABSL_GUARDED_BY(mu_);
  absl::flat_hash_map<const void*, HandleInfo> dead_ ABSL_GUARDED_BY(mu_);
  absl::flat_hash_map<Context*, absl::flat_hash_set<const void*>> dead_by_context_
      ABSL_GUARDED_BY(mu_);
  std::deque<const void*> dead_order_ ABSL_GUARDED_BY(mu_);  // oldest first
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_HANDLE_REGISTRY_H_
