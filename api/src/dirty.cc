#include "dirty.h"

#include <vector>

#include "absl/container/flat_hash_set.h"
#include "acceleration.h"
#include "nodes.h"

namespace tessera::api {
namespace {

// Which links carry a change upward: buffer → the geometry or instance whose variables hold it;
// geometry → instance; instance → geometry group; node → group, transform or selector.
// Links from programs, materials or the context (variables like top_object) do not.
bool Propagates(Kind child, Kind parent) {
  switch (child) {
    case Kind::kBuffer:
      return parent == Kind::kGeometry || parent == Kind::kGeometryTriangles ||
             parent == Kind::kGeometryInstance;
    case Kind::kGeometry:
    case Kind::kGeometryTriangles:
      return parent == Kind::kGeometryInstance;
    case Kind::kGeometryInstance:
      return parent == Kind::kGeometryGroup;
    case Kind::kGeometryGroup:
    case Kind::kGroup:
    case Kind::kTransform:
    case Kind::kSelector:
      return parent == Kind::kGroup || parent == Kind::kTransform || parent == Kind::kSelector;
    default:
      return false;
  }
}

}  // namespace

void NotifyStructureChanged(Object* changed, const Object* keep_restored) {
  absl::flat_hash_set<Object*> seen;
  std::vector<Object*> stack{changed};
  while (!stack.empty()) {
    Object* node = stack.back();
    stack.pop_back();
    if (!seen.insert(node).second) continue;
    if (node->kind() == Kind::kGeometryGroup || node->kind() == Kind::kGroup) {
      auto* accel = static_cast<Acceleration*>(static_cast<AcceleratedNode*>(node)->acceleration());
      // An acceleration just attached with restored data keeps it: the launch checks it against
      // the graph below (acceleration_data.cc), as OptiX leaves attaching to the application.
      if (accel != nullptr && (accel != keep_restored || accel->restored() == nullptr)) {
        accel->MarkDirty();
      }
    }
    for (const auto& [parent, count] : node->parents()) {
      if (parent->alive() && Propagates(node->kind(), parent->kind())) stack.push_back(parent);
    }
  }
}

}  // namespace tessera::api
