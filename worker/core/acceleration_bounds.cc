// SceneCache::AccelerationBounds: the primitive bounds a GeometryGroup's last build computed, for
// rtAccelerationGetData (docs/acceleration_data.md). The bounding-box programs are what a build
// over user geometry costs beyond Embree itself; their results are all a device can hand back
// that another device (or a later run) can reuse, Embree's BVH being no portable format.
#include <cstring>

#include "absl/strings/str_cat.h"
#include "plan.h"
#include "tessera/scheduler/device.h"

namespace tessera::worker {

absl::StatusOr<v1::AccelerationBoundsReply> SceneCache::AccelerationBounds(
    const v1::AccelerationBoundsRequest& request) const {
  const SceneEntry* entry = Find(request.geometry_group());
  if (entry == nullptr || entry->scene == nullptr ||
      entry->acceleration != request.acceleration() ||
      entry->build_epoch != request.build_epoch()) {
    return absl::FailedPreconditionError(absl::StrCat(
        "no build of geometry group #", request.geometry_group(), " with acceleration #",
        request.acceleration(), " at build epoch ", request.build_epoch(), " on this device"));
  }
  uint64_t total = 0;
  for (const auto& info : entry->geometries) total += info->bounds.size() * sizeof(float);
  // Too many to carry: the counts alone, and the devices that restore them run the programs.
  const bool carry = total <= kMaxCarriedBoundsBytes;
  v1::AccelerationBoundsReply reply;
  for (const auto& info : entry->geometries) {
    v1::PrimitiveBounds* child = reply.add_children();
    child->set_primitive_count(info->triangles ? 0 : info->bounds.size() / 6);
    child->set_has_bounds(!info->triangles && carry);
    if (info->triangles || !carry) continue;
    child->mutable_bounds()->assign(reinterpret_cast<const char*>(info->bounds.data()),
                                    info->bounds.size() * sizeof(float));
  }
  return reply;
}

}  // namespace tessera::worker
