#include "acceleration_data.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

#include "absl/strings/str_cat.h"
#include "geometry.h"
#include "nodes.h"
#include "program.h"
#include "status.h"
#include "tessera/scheduler/device.h"
#include "tessera/scheduler/log.h"

namespace tessera::api {
namespace {

// The live GeometryGroups and Groups `a` is on, by id: a shared acceleration's first one stands
// for all (the guide requires them to hold matching geometry).
std::vector<AcceleratedNode*> NodesOf(const Acceleration& a) {
  std::vector<AcceleratedNode*> nodes;
  for (const auto& [parent, count] : a.parents()) {
    if (!parent->alive()) continue;
    if (parent->kind() != Kind::kGeometryGroup && parent->kind() != Kind::kGroup) continue;
    auto* node = static_cast<AcceleratedNode*>(parent);
    if (node->acceleration() == &a) nodes.push_back(node);
  }
  std::sort(nodes.begin(), nodes.end(),
            [](const Object* x, const Object* y) { return x->id() < y->id(); });
  return nodes;
}

uint32_t NodeKind(const AcceleratedNode& node) {
  return node.kind() == Kind::kGeometryGroup ? RT_OBJECTTYPE_GEOMETRY_GROUP : RT_OBJECTTYPE_GROUP;
}

// What a build of `node` runs over: per GeometryInstance its geometry's kind, primitive count and
// bounding-box program; per Group child its type. No geometry data (buffers, variables).
absl::StatusOr<std::vector<BuildInput>> InputsOf(const AcceleratedNode& node) {
  std::vector<BuildInput> inputs(node.child_count());
  for (unsigned i = 0; i < node.child_count(); ++i) {
    const Object* child = node.child(i);
    if (child == nullptr) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(node.Describe(), ": child ", i, " is not set"));
    }
    BuildInput& in = inputs[i];
    if (node.kind() == Kind::kGroup) {
      in.kind = ObjectTypeOf(child->kind());
      continue;
    }
    const Object* g = static_cast<const GeometryInstance*>(child)->geometry();
    if (!Geometry::Is(g)) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(node.Describe(), ": child ", i, " has no geometry"));
    }
    const auto* geometry = static_cast<const Geometry*>(g);
    in.kind = g->kind() == Kind::kGeometryTriangles ? kTrianglesInput : kGeometryInput;
    in.primitive_count = geometry->primitive_count();
    if (const Object* p = geometry->bounding_box_program(); p != nullptr) {
      const auto* program = static_cast<const Program*>(p);
      in.bounds_program =
          absl::StrCat("'", program->function(), "' in module ", program->module_hash());
    }
  }
  return inputs;
}

std::string LaunchFirst() {
  return "launch first (rtContextLaunch1D(context, 0, 0) builds accelerations without tracing)";
}

// The bounds devices computed for `node`'s build at `a`'s epoch, from the first device that holds
// it (every device computes the same ones).
absl::Status ReadBounds(Context& context, const Acceleration& a, const AcceleratedNode& node,
                        const std::vector<BuildInput>& inputs, AccelerationBlob* blob) {
  v1::AccelerationBoundsRequest request;
  request.set_acceleration(a.id());
  request.set_build_epoch(a.build_epoch());
  request.set_geometry_group(node.id());
  std::string why = "the context has no devices yet";
  for (DeviceSlot& slot : context.device_slots()) {
    if (slot.device == nullptr) continue;
    request.set_session_id(slot.sync.session_id);
    absl::StatusOr<v1::AccelerationBoundsReply> reply = slot.device->AccelerationBounds(request);
    if (!reply.ok()) {
      why = absl::StrCat("device '", slot.desc.name, "' (", slot.desc.address,
                         "): ", reply.status().message());
      continue;
    }
    if (static_cast<size_t>(reply->children_size()) != inputs.size()) {
      return RtError(RT_ERROR_UNKNOWN,
                     absl::StrCat(a.Describe(), ": device '", slot.desc.name, "' built ",
                                  node.Describe(), " over ", reply->children_size(),
                                  " children, the host knows ", inputs.size()));
    }
    blob->bounds.assign(inputs.size(), {});
    for (size_t i = 0; i < inputs.size(); ++i) {
      const v1::PrimitiveBounds& c = reply->children(static_cast<int>(i));
      if (!c.has_bounds()) continue;
      if (c.bounds().size() != inputs[i].primitive_count * 6 * sizeof(float)) {
        return RtError(
            RT_ERROR_UNKNOWN,
            absl::StrCat(a.Describe(), ": device '", slot.desc.name, "' sent ", c.bounds().size(),
                         " bytes of bounds for child ", i, " of ", node.Describe(), ", which has ",
                         inputs[i].primitive_count, " primitives"));
      }
      std::vector<float>& out = blob->bounds[i];
      out.resize(inputs[i].primitive_count * 6);
      std::memcpy(out.data(), c.bounds().data(), c.bounds().size());
    }
    return absl::OkStatus();
  }
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat(a.Describe(), " is not built on any device (",
                                                      why, "); ", LaunchFirst()));
}

}  // namespace

absl::StatusOr<const std::string*> ExtractAccelerationData(Context& context, Acceleration& a) {
  if (a.dirty()) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat(a.Describe(), " is dirty: its data can only be read once a launch built it; ",
                     LaunchFirst()));
  }
  Acceleration::Extracted& done = a.extracted();
  if (!done.bytes.empty() && done.build_epoch == a.build_epoch() && done.version == a.version()) {
    return &done.bytes;
  }
  AccelerationBlob blob;
  blob.builder = a.builder();
  blob.traverser = a.traverser();
  blob.properties = a.properties();
  const AccelerationBlob* restored = a.restored();
  if (restored != nullptr && a.restore_check() != Acceleration::RestoreCheck::kMismatch) {
    // Built from these bounds (or to be, at the next launch): they are what a build would give.
    blob.node_kind = restored->node_kind;
    blob.inputs = restored->inputs;
    blob.bounds = restored->bounds;
  } else {
    const std::vector<AcceleratedNode*> nodes = NodesOf(a);
    if (nodes.empty()) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(a.Describe(),
                                  " is on no Group or GeometryGroup: it has no structure to read"));
    }
    const AcceleratedNode& node = *nodes.front();
    absl::StatusOr<std::vector<BuildInput>> inputs = InputsOf(node);
    if (!inputs.ok()) return inputs.status();
    blob.node_kind = NodeKind(node);
    blob.inputs = *std::move(inputs);
    // A Group's build is Embree's over its children's boxes, which come from the children's own
    // builds: nothing in it is worth carrying.
    if (node.kind() == Kind::kGeometryGroup) {
      if (absl::Status s = ReadBounds(context, a, node, blob.inputs, &blob); !s.ok()) return s;
    }
  }
  done.bytes = EncodeAccelerationBlob(blob);
  done.build_epoch = a.build_epoch();
  done.version = a.version();
  return &done.bytes;
}

void CheckRestoredAccelerations(Context& context) {
  absl::flat_hash_set<uint64_t>& pending = context.pending_restores();
  for (auto it = pending.begin(); it != pending.end();) {
    Object* object = context.FindById(*it);
    auto* a = object != nullptr && object->kind() == Kind::kAcceleration
                  ? static_cast<Acceleration*>(object)
                  : nullptr;
    const AccelerationBlob* blob = a != nullptr ? a->restored() : nullptr;
    if (blob == nullptr || a->restore_check() != Acceleration::RestoreCheck::kPending) {
      pending.erase(it++);  // destroyed, marked dirty, or checked already
      continue;
    }
    const std::vector<AcceleratedNode*> nodes = NodesOf(*a);
    if (nodes.empty()) {  // checked once it is on a node
      ++it;
      continue;
    }
    pending.erase(it++);
    std::string why;
    for (const AcceleratedNode* node : nodes) {
      if (NodeKind(*node) != blob->node_kind) {
        why = absl::StrCat(node->Describe(), ": the data was saved from a ",
                           blob->node_kind == RT_OBJECTTYPE_GROUP ? "Group" : "GeometryGroup");
        break;
      }
      absl::StatusOr<std::vector<BuildInput>> inputs = InputsOf(*node);
      why = inputs.ok() ? DescribeInputMismatch(blob->inputs, *inputs)
                        : std::string(inputs.status().message());
      if (!why.empty()) {
        why = absl::StrCat(node->Describe(), ": ", why);
        break;
      }
    }
    if (why.empty()) {
      a->set_restore_check(Acceleration::RestoreCheck::kMatches);
      continue;
    }
    a->set_restore_check(Acceleration::RestoreCheck::kMismatch);
    // Once per rtAccelerationSetData: the check is not made again for this data.
    log::Warn(log::Component::kApi,
              "%s: the data rtAccelerationSetData restored was not built over the graph it is on "
              "(%s); it is built afresh, running its bounding-box programs",
              a->Describe(), why);
  }
}

void LowerRestoredBounds(const Acceleration& a, v1::Acceleration* out) {
  const AccelerationBlob* blob = a.restored();
  if (blob == nullptr || a.restore_check() != Acceleration::RestoreCheck::kMatches) return;
  if (blob->node_kind != RT_OBJECTTYPE_GEOMETRY_GROUP) return;
  for (size_t i = 0; i < blob->inputs.size(); ++i) {
    v1::PrimitiveBounds* c = out->add_cached_bounds();
    const std::vector<float>& b = i < blob->bounds.size() ? blob->bounds[i] : std::vector<float>();
    c->set_primitive_count(blob->inputs[i].primitive_count);
    c->set_has_bounds(!b.empty());
    c->mutable_bounds()->assign(reinterpret_cast<const char*>(b.data()), b.size() * sizeof(float));
  }
}

}  // namespace tessera::api
