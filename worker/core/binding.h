// Programs bound to a scope chain (OptiX guide Table 5): what to copy into a module's variable
// slots and buffer views before the program runs. Bindings are computed once per launch plan.
#ifndef TESSERA_WORKER_CORE_BINDING_H_
#define TESSERA_WORKER_CORE_BINDING_H_

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "module.h"
#include "replica.h"

namespace tessera::worker {

enum class ProgramKind {
  kRayGeneration,
  kException,
  kClosestHit,
  kAnyHit,
  kMiss,
  kIntersection,
  kBoundingBox,
  kVisit,
  kAttribute,  // GeometryTriangles (OptiX 6): attributes of a hit on built-in triangles
};
const char* KindName(ProgramKind kind);

// The attribute built-in triangles fill with their barycentrics (OptiX 6).
inline constexpr char kTriangleBarycentrics[] = "rtTriangleBarycentrics";

// Attribute names across all loaded modules → bytes in a hit's attribute block.
class AttributeLayout {
 public:
  static constexpr size_t kMaxBytes = 512;
  // Returns the offset of `name`, adding it; sizes must agree across modules.
  absl::StatusOr<size_t> Offset(const std::string& name, size_t size, const std::string& where);
  // The offset of `name` if some bound program declared it, else -1.
  long Find(const std::string& name) const {
    auto it = entries_.find(name);
    return it == entries_.end() ? -1 : static_cast<long>(it->second.first);
  }

 private:
  std::unordered_map<std::string, std::pair<size_t, size_t>> entries_;  // name -> offset, size
  size_t used_ = 0;

 public:
  size_t used() const { return used_; }
};

struct BoundProgram {
  struct Copy {
    unsigned var;
    const void* src;
    size_t size;
  };
  struct Attribute {
    unsigned var;
    size_t offset;
    size_t size;
  };
  // A variable of the module that receives a semantic value, and how many bytes it takes: its
  // declared size (payload), or that clipped to the value's size (launch index, ray, distance).
  struct SlotRef {
    unsigned var;
    unsigned size;
  };
  ProgramKind kind = ProgramKind::kRayGeneration;
  uint64_t id = 0;
  std::string name;  // "function in module" for messages
  const Module* module = nullptr;
  unsigned module_index = 0;  // module->index(), kept here for the per-call path
  void* function = nullptr;
  // What this binding sets in the module's slots beyond the module's plan-wide invariants.
  std::vector<Copy> copies;
  // A view per rtBuffer slot of the module; a thread running the program points the module at
  // it, so switching programs copies no views.
  std::vector<TesseraBufferView> table;
  // The slots of `table` bound to buffers programs may write (OUTPUT, INPUT_OUTPUT, GPU_LOCAL):
  // what a ray generation program must not touch before its first rtTrace for that ray to be
  // traced in a packet (packet_trace.h).
  std::vector<unsigned> writable_slots;
  // A view per rtTextureSampler slot of the module (TesseraRuntime::texture_view); level_count 0
  // where no scope binds a sampler.
  std::vector<TesseraTextureView> textures;
  std::vector<Attribute> attributes;
  // Two of `attributes` share bytes of the hit's block (one attribute declared twice): a copy
  // through the block then differs from the slots the program left, so it is never skipped.
  bool attributes_alias = false;
  // Variables declared with each semantic (a module may declare one several times, e.g. a
  // radiance and a shadow payload).
  std::vector<SlotRef> launch_index, launch_dim, ray, payload, distance, time;
  // rtCallableProgram variables: the program each names through this binding's scopes (0: none)
  // and the engine's binding of it with this binding's outer scopes (plan.cc), whose address
  // `copies` puts in the variable's slot.
  struct Callable {
    unsigned var;
    uint64_t program;
    const BoundProgram* target;
  };
  std::vector<Callable> callables;
  // The scopes after the program's own, which a callable program it calls searches after its own.
  std::vector<const Scope*> outer;
  // Set once a call showed that the function does not write through the bounding-box result
  // pointer every call passes (CallProgram). Written and read with relaxed atomics by the
  // threads of a launch; it only ever goes from false to true.
  mutable bool arguments_checked = false;
};

// Binds `program_id` with scopes searched in order (the program's own scope comes first).
// `callable`: the program runs through an rtCallableProgram variable of a program of `kind`,
// which it takes the place of (the calls it may make, the values it sees).
absl::StatusOr<BoundProgram> Bind(const Replica& replica, ProgramKind kind, uint64_t program_id,
                                  const std::vector<const Scope*>& scopes,
                                  AttributeLayout& attributes, bool callable = false);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_BINDING_H_
