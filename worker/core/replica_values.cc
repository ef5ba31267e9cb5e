// Deltas that change only variable values (a camera moved, a frame counter) and buffer contents,
// and perhaps the graph (a transform moved, a group's children): Replica::Apply writes the new
// bytes where the old ones were, so that a launch plan, whose bindings point at them
// (binding.cc), stays valid and need not be made again. Making a plan costs time in proportion to
// the scene (16,384 geometry instances: 30–50 ms) and freeing the old one as much.
#include <cstring>

#include "absl/hash/hash.h"
#include "replica.h"

namespace tessera::worker {
namespace {

using Variables = google::protobuf::RepeatedPtrField<v1::Variable>;

template <typename T>
bool SameValues(const std::vector<T>& held, const google::protobuf::RepeatedField<T>& sent) {
  return held.size() == static_cast<size_t>(sent.size()) &&
         std::equal(held.begin(), held.end(), sent.begin());
}

bool SameRefs(const std::vector<NodeRef>& held,
              const google::protobuf::RepeatedPtrField<v1::NodeRef>& sent) {
  if (held.size() != static_cast<size_t>(sent.size())) return false;
  for (int i = 0; i < sent.size(); ++i) {
    if (held[i].id != sent[i].id() || held[i].type != sent[i].type()) return false;
  }
  return true;
}

// Whether `sent` holds the variables of `held` with the same types, objects and sizes.
bool SameLayout(const Scope& held, const Variables& sent) {
  if (held.size() != static_cast<size_t>(sent.size())) return false;
  for (const v1::Variable& v : sent) {
    auto it = held.find(v.name());
    if (it == held.end()) return false;
    const Value& h = it->second;
    if (h.type != v.type() || h.object_id != v.object_id() || h.data.size() != v.data().size()) {
      return false;
    }
  }
  return true;
}

// The variables of the object `held` holds under `id`, if `same` says the delta's copy of it
// differs in nothing else; else null.
template <typename Rec, typename Same>
Scope* HeldScope(std::unordered_map<uint64_t, Rec>& held, uint64_t id, Same&& same) {
  auto it = held.find(id);
  return it != held.end() && same(it->second) ? &it->second.vars : nullptr;
}

bool SameContext(const ContextRec& held, const v1::ContextState& c) {
  bool same = held.entry_point_count == c.entry_point_count() &&
              held.ray_type_count == c.ray_type_count() &&
              SameValues(held.ray_generation, c.ray_generation()) &&
              SameValues(held.exception, c.exception()) && SameValues(held.miss, c.miss()) &&
              held.stack_size == c.stack_size() && held.print_enabled == c.print_enabled() &&
              held.print_buffer_size == c.print_buffer_size() &&
              held.exception_mask == c.exception_mask() &&
              held.user_exceptions == c.user_exceptions() && held.num_threads == c.num_threads() &&
              held.accuracy_flags == c.accuracy_flags();
  for (int i = 0; i < 3; ++i) {
    same = same &&
           held.print_index[i] == (i < c.print_launch_index_size() ? c.print_launch_index(i) : -1);
  }
  return same && SameLayout(held.vars, c.variables());
}

}  // namespace

bool Replica::IsGraphKind(v1::Object::KindCase kind) {
  return kind == v1::Object::kGroup || kind == v1::Object::kGeometryGroup ||
         kind == v1::Object::kTransform || kind == v1::Object::kAcceleration;
}

Replica::DeltaScope Replica::Classify(const v1::StateDelta& delta,
                                      std::vector<ValueWrite>* writes) {
  writes->clear();
  // New bytes for buffers whose shape stays (no Buffer object in the delta) land in place too.
  if (!delta.modules().empty()) return DeltaScope::kEverything;
  if (!SameContext(context_, delta.context())) return DeltaScope::kEverything;
  DeltaScope scope_of_delta = DeltaScope::kValues;
  for (uint64_t id : delta.removed()) {
    if (!IsGraphKind(KindOf(id))) return DeltaScope::kEverything;
    scope_of_delta = DeltaScope::kGraph;
  }
  writes->push_back({&context_.vars, &delta.context().variables()});
  for (const v1::Object& o : delta.objects()) {
    Scope* scope = nullptr;  // the held object's variables, if nothing else of it changes
    const Variables* sent = nullptr;
    switch (o.kind_case()) {
      case v1::Object::kProgram: {
        const auto& p = o.program();
        scope = HeldScope(programs, p.id(), [&](const ProgramRec& h) {
          return h.module_path == p.module_path() && h.module_hash == p.module_hash() &&
                 h.function == p.function();
        });
        sent = &p.variables();
        break;
      }
      case v1::Object::kGeometry: {
        const auto& g = o.geometry();
        scope = HeldScope(geometries, g.id(), [&](const GeometryRec& h) {
          return h.primitive_count == g.primitive_count() &&
                 h.intersection == g.intersection_program() &&
                 h.bounds == g.bounding_box_program() && h.builtin_triangles == g.has_triangles() &&
                 h.mesh_stamp == absl::HashOf(g.triangles().SerializeAsString());
        });
        sent = &g.variables();
        break;
      }
      case v1::Object::kMaterial: {
        const auto& m = o.material();
        scope = HeldScope(materials, m.id(), [&](const MaterialRec& h) {
          return SameValues(h.closest_hit, m.closest_hit()) && SameValues(h.any_hit, m.any_hit());
        });
        sent = &m.variables();
        break;
      }
      case v1::Object::kGeometryInstance: {
        const auto& gi = o.geometry_instance();
        scope = HeldScope(instances, gi.id(), [&](const InstanceRec& h) {
          return h.geometry == gi.geometry() && SameValues(h.materials, gi.materials());
        });
        sent = &gi.variables();
        break;
      }
      case v1::Object::kSelector: {
        const auto& sel = o.selector();
        scope = HeldScope(selectors, sel.id(), [&](const SelectorRec& h) {
          return h.visit == sel.visit_program() && SameRefs(h.children, sel.children());
        });
        sent = &sel.variables();
        break;
      }
      case v1::Object::kOptix7ProgramGroup:
      case v1::Object::kOptix7Pipeline:
        continue;  // OptiX 7 state: nothing OptiX 3 programs are bound to
      default:
        // Graph nodes and accelerations change the scenes, not what programs are bound to;
        // buffers (reallocated) change that too.
        if (!IsGraphKind(o.kind_case())) return DeltaScope::kEverything;
        scope_of_delta = DeltaScope::kGraph;
        continue;
    }
    if (scope == nullptr || !SameLayout(*scope, *sent)) return DeltaScope::kEverything;
    writes->push_back({scope, sent});
  }
  return scope_of_delta;
}

void Replica::WriteValues(const std::vector<ValueWrite>& writes) {
  for (const ValueWrite& w : writes) {
    for (const v1::Variable& v : *w.variables) {
      Value& held = w.scope->at(v.name());
      // Same size (Classify): the bytes stay where bindings point.
      if (!v.data().empty()) std::memcpy(held.data.data(), v.data().data(), v.data().size());
    }
  }
}

}  // namespace tessera::worker
