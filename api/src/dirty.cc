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

void NotifyStructureChanged(Object* changed) {
  absl::flat_hash_set<Object*> seen;
  std::vector<Object*> stack{changed};
  while (!stack.empty()) {
    Object* node = stack.back();
    stack.pop_back();
    if (!seen.insert(node).second) continue;
    if (node->kind() == Kind::kGeometryGroup || node->kind() == Kind::kGroup) {
      if (Object* accel = static_cast<AcceleratedNode*>(node)->acceleration()) {
        static_cast<Acceleration*>(accel)->MarkDirty();
      }
    }
    for (const auto& [parent, count] : node->parents()) {
      if (parent->alive() && Propagates(node->kind(), parent->kind())) stack.push_back(parent);
    }
  }
}

}  // namespace tessera::api
