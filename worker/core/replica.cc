#include "replica.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "tessera/rt.h"

namespace tessera::worker {
namespace {

Scope ToScope(const google::protobuf::RepeatedPtrField<v1::Variable>& vars) {
  Scope scope;
  for (const auto& v : vars) scope[v.name()] = Value{v.type(), v.data(), v.object_id()};
  return scope;
}

NodeRef ToRef(const v1::NodeRef& r) { return NodeRef{r.id(), r.type()}; }

template <typename T>
std::vector<T> ToVector(const google::protobuf::RepeatedField<T>& f) {
  return std::vector<T>(f.begin(), f.end());
}

absl::Status CheckBuffer(const v1::Buffer& b) {
  if (b.dims_size() > 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("buffer #", b.id(), " has ", b.dims_size(), " dimensions (at most 3)"));
  }
  uint64_t count = 1;
  for (uint64_t d : b.dims()) {
    if (d != 0 && count > (uint64_t{1} << 40) / d) {
      return absl::InvalidArgumentError(absl::StrCat("buffer #", b.id(), " is too large"));
    }
    count *= d;
  }
  if (b.element_size() > (1u << 20)) {
    return absl::InvalidArgumentError(
        absl::StrCat("buffer #", b.id(), " has element size ", b.element_size()));
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status Replica::Apply(const v1::StateDelta& delta) {
  // ---- Check everything before changing anything.
  if (session_id_ != 0 && delta.session_id() != session_id_) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta for session ", delta.session_id(), " sent to session ", session_id_));
  }
  if (delta.sequence() != sequence_ + 1) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta ", delta.sequence(), " out of order (expected ", sequence_ + 1, ")"));
  }
  std::unordered_map<uint64_t, uint64_t> new_sizes;  // buffer id -> bytes after this delta
  for (const auto& o : delta.objects()) {
    if (o.kind_case() == v1::Object::KIND_NOT_SET) {
      return absl::InvalidArgumentError("state delta holds an object of no kind");
    }
    if (o.has_buffer()) {
      if (absl::Status s = CheckBuffer(o.buffer()); !s.ok()) return s;
      uint64_t bytes = o.buffer().element_size();
      for (uint64_t d : o.buffer().dims()) bytes *= d;
      if (o.buffer().dims_size() == 0) bytes = 0;
      new_sizes[o.buffer().id()] = bytes;
    }
    if (o.has_transform() &&
        (o.transform().matrix_size() != 16 || o.transform().inverse_size() != 16)) {
      return absl::InvalidArgumentError(
          absl::StrCat("transform #", o.transform().id(), " needs 16 matrix and inverse values"));
    }
  }
  for (const auto& c : delta.chunks()) {
    uint64_t bytes = 0;
    if (auto it = new_sizes.find(c.buffer_id()); it != new_sizes.end()) {
      bytes = it->second;
    } else if (auto b = buffers.find(c.buffer_id()); b != buffers.end()) {
      bytes = b->second.Bytes();
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat("buffer chunk for unknown buffer #", c.buffer_id()));
    }
    if (c.offset() > bytes || c.data().size() > bytes - c.offset()) {
      return absl::OutOfRangeError(absl::StrCat("buffer chunk [", c.offset(), ", +",
                                                c.data().size(), ") outside buffer #",
                                                c.buffer_id(), " of ", bytes, " bytes"));
    }
  }

  // ---- Apply.
  session_id_ = delta.session_id();
  sequence_ = delta.sequence();
  ++generation_;
  const v1::ContextState& c = delta.context();
  context_.entry_point_count = c.entry_point_count();
  context_.ray_type_count = c.ray_type_count();
  context_.ray_generation = ToVector(c.ray_generation());
  context_.exception = ToVector(c.exception());
  context_.miss = ToVector(c.miss());
  context_.stack_size = c.stack_size();
  context_.print_enabled = c.print_enabled();
  for (int i = 0; i < 3; ++i) {
    context_.print_index[i] = i < c.print_launch_index_size() ? c.print_launch_index(i) : -1;
  }
  context_.exception_mask = c.exception_mask();
  context_.user_exceptions = c.user_exceptions();
  context_.num_threads = c.num_threads();
  context_.vars = ToScope(c.variables());

  for (uint64_t id : delta.removed()) {
    programs.erase(id);
    buffers.erase(id);
    geometries.erase(id);
    materials.erase(id);
    instances.erase(id);
    accelerations.erase(id);
    geometry_groups.erase(id);
    groups.erase(id);
    transforms.erase(id);
    selectors.erase(id);
  }
  for (const auto& o : delta.objects()) {
    switch (o.kind_case()) {
      case v1::Object::kProgram: {
        const auto& p = o.program();
        programs[p.id()] =
            ProgramRec{p.module_path(), p.module_hash(), p.function(), ToScope(p.variables())};
        break;
      }
      case v1::Object::kBuffer: {
        const auto& b = o.buffer();
        BufferRec& r = buffers[b.id()];
        BufferRec before = BufferRec{r.desc, r.format, r.element_size, r.dims, r.ndims, {}};
        r.desc = b.desc();
        r.format = b.format();
        r.element_size = b.element_size();
        r.ndims = b.dims_size();
        r.dims = {0, 1, 1};
        for (int i = 0; i < b.dims_size(); ++i) r.dims[i] = b.dims(i);
        if (r.ndims == 0) r.dims[0] = 0;
        if (r.format != before.format || r.element_size != before.element_size ||
            r.dims != before.dims) {
          // A new shape starts zeroed, like a new buffer; the host resends INPUT contents.
          r.data.assign(r.Bytes(), 0);
        }
        break;
      }
      case v1::Object::kGeometry: {
        const auto& g = o.geometry();
        geometries[g.id()] = GeometryRec{g.primitive_count(), g.intersection_program(),
                                         g.bounding_box_program(), ToScope(g.variables())};
        break;
      }
      case v1::Object::kMaterial: {
        const auto& m = o.material();
        materials[m.id()] =
            MaterialRec{ToVector(m.closest_hit()), ToVector(m.any_hit()), ToScope(m.variables())};
        break;
      }
      case v1::Object::kGeometryInstance: {
        const auto& gi = o.geometry_instance();
        instances[gi.id()] =
            InstanceRec{gi.geometry(), ToVector(gi.materials()), ToScope(gi.variables())};
        break;
      }
      case v1::Object::kGeometryGroup: {
        const auto& gg = o.geometry_group();
        geometry_groups[gg.id()] = GeometryGroupRec{gg.acceleration(), ToVector(gg.children())};
        break;
      }
      case v1::Object::kGroup: {
        const auto& g = o.group();
        GroupRec r{g.acceleration(), {}};
        for (const auto& ch : g.children()) r.children.push_back(ToRef(ch));
        groups[g.id()] = std::move(r);
        break;
      }
      case v1::Object::kTransform: {
        const auto& t = o.transform();
        TransformRec r;
        for (int i = 0; i < 16; ++i) {
          r.matrix[i] = t.matrix(i);
          r.inverse[i] = t.inverse(i);
        }
        r.child = ToRef(t.child());
        transforms[t.id()] = r;
        break;
      }
      case v1::Object::kSelector: {
        const auto& s = o.selector();
        SelectorRec r{s.visit_program(), {}, ToScope(s.variables())};
        for (const auto& ch : s.children()) r.children.push_back(ToRef(ch));
        selectors[s.id()] = std::move(r);
        break;
      }
      case v1::Object::kAcceleration: {
        const auto& a = o.acceleration();
        AccelRec r{a.builder(), a.traverser(), {}, a.build_epoch()};
        for (const auto& [k, v] : a.properties()) r.properties[k] = v;
        accelerations[a.id()] = std::move(r);
        break;
      }
      case v1::Object::KIND_NOT_SET:
        break;
    }
  }
  for (const auto& ch : delta.chunks()) {
    BufferRec& b = buffers[ch.buffer_id()];
    std::memcpy(b.data.data() + ch.offset(), ch.data().data(), ch.data().size());
  }
  return absl::OkStatus();
}

}  // namespace tessera::worker
