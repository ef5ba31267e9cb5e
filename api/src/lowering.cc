#include "lowering.h"

#include <algorithm>

#include "acceleration.h"
#include "acceleration_data.h"
#include "buffer.h"
#include "context.h"
#include "context_extension.h"
#include "geometry.h"
#include "hash.h"
#include "nodes.h"
#include "program.h"
#include "texture_sampler.h"
#include "validate.h"

namespace tessera::api {
namespace {

uint64_t IdOf(const Object* o) { return o == nullptr ? 0 : o->id(); }

void LowerVariables(const VariableScope& scope,
                    google::protobuf::RepeatedPtrField<v1::Variable>* out) {
  for (const Variable* v : scope.variables()) {
    // Declared but never set: nothing for a program to read; its static initializer applies.
    if (!v->has_value()) continue;
    v1::Variable* pv = out->Add();
    pv->set_name(v->name());
    pv->set_type(static_cast<uint32_t>(v->type()));
    if (v->holds_object()) {
      pv->set_object_id(IdOf(v->object()));
    } else {
      pv->set_data(v->data().data(), v->data().size());
    }
  }
}

void LowerNodeRef(const Object* node, v1::NodeRef* out) {
  out->set_id(IdOf(node));
  out->set_type(node == nullptr ? RT_OBJECTTYPE_UNKNOWN : ObjectTypeOf(node->kind()));
}

void LowerContext(const Context& c, v1::ContextState* out) {
  out->set_version(c.version());
  out->set_entry_point_count(c.entry_point_count());
  out->set_ray_type_count(c.ray_type_count());
  for (unsigned i = 0; i < c.entry_point_count(); ++i) {
    out->add_ray_generation(IdOf(c.ray_generation(i)));
    out->add_exception(IdOf(c.exception_program(i)));
  }
  for (unsigned i = 0; i < c.ray_type_count(); ++i) out->add_miss(IdOf(c.miss(i)));
  out->set_stack_size(c.stack_size());
  out->set_print_enabled(c.print_enabled());
  out->set_print_buffer_size(c.print_buffer_size());
  for (int v : c.print_launch_index()) out->add_print_launch_index(v);
  out->set_exception_mask(c.exception_mask());
  out->set_user_exceptions(c.user_exceptions());
  LowerVariables(c.variables(), out->mutable_variables());
  // 0 = the device's own thread count (in-process: CPU_NUM_THREADS at creation, which defaults to
  // the hardware threads; a local worker: its share of the cores).
  out->set_num_threads(c.num_threads_set() ? static_cast<uint32_t>(c.num_threads()) : 0);
  out->set_accuracy_flags(c.accuracy_flags());
}

// `ordinal`: the device the delta is for.
void LowerObject(const Context& c, Object& o, int ordinal, v1::Object* out) {
  switch (o.kind()) {
    case Kind::kProgram: {
      auto& p = static_cast<Program&>(o);
      v1::Program* m = out->mutable_program();
      m->set_id(p.id());
      m->set_version(p.version());
      m->set_module_path(p.module_path());
      m->set_module_hash(p.module_hash());
      m->set_function(p.function());
      m->set_has_id(p.id_taken());
      LowerVariables(p.variables(), m->mutable_variables());
      break;
    }
    case Kind::kBuffer: {
      auto& b = static_cast<Buffer&>(o);
      v1::Buffer* m = out->mutable_buffer();
      m->set_id(b.id());
      m->set_version(b.version());
      m->set_desc(b.desc());
      m->set_format(static_cast<uint32_t>(b.format()));
      m->set_element_size(b.element_size());
      for (size_t d : b.dims()) m->add_dims(d);
      m->set_return_writes(b.returns_device_writes(ordinal));
      m->set_mip_level_count(b.mip_levels());
      break;
    }
    case Kind::kTextureSampler: {
      auto& t = static_cast<TextureSampler&>(o);
      v1::TextureSampler* m = out->mutable_texture_sampler();
      m->set_id(t.id());
      m->set_version(t.version());
      m->set_buffer(IdOf(t.buffer()));
      for (unsigned d = 0; d < 3; ++d) m->add_wrap(t.wrap_mode(d));
      m->set_min_filter(t.min_filter());
      m->set_mag_filter(t.mag_filter());
      m->set_mip_filter(t.mip_filter());
      m->set_max_anisotropy(t.max_anisotropy());
      m->set_mip_level_clamp_min(t.mip_level_clamp_min());
      m->set_mip_level_clamp_max(t.mip_level_clamp_max());
      m->set_mip_level_bias(t.mip_level_bias());
      m->set_read_mode(t.read_mode());
      m->set_index_mode(t.indexing_mode());
      break;
    }
    case Kind::kGeometry: {
      auto& g = static_cast<Geometry&>(o);
      v1::Geometry* m = out->mutable_geometry();
      m->set_id(g.id());
      m->set_version(g.version());
      m->set_primitive_count(g.primitive_count());
      m->set_intersection_program(IdOf(g.intersection_program()));
      m->set_bounding_box_program(IdOf(g.bounding_box_program()));
      LowerVariables(g.variables(), m->mutable_variables());
      break;
    }
    case Kind::kGeometryTriangles: {
      auto& g = static_cast<GeometryTriangles&>(o);
      v1::Geometry* m = out->mutable_geometry();
      m->set_id(g.id());
      m->set_version(g.version());
      m->set_primitive_count(g.primitive_count());
      LowerVariables(g.variables(), m->mutable_variables());
      v1::TriangleMesh* t = m->mutable_triangles();
      t->set_vertex_buffer(IdOf(g.vertex_buffer()));
      t->set_vertex_count(g.vertex_count());
      t->set_vertex_offset(g.vertices().offset);
      t->set_vertex_stride(g.vertices().stride);
      t->set_vertex_format(static_cast<uint32_t>(g.vertices().format));
      t->set_index_buffer(IdOf(g.index_buffer()));
      t->set_index_offset(g.indices().offset);
      t->set_index_stride(g.indices().stride);
      t->set_index_format(static_cast<uint32_t>(g.indices().format));
      t->set_primitive_index_offset(g.primitive_index_offset());
      t->set_attribute_program(IdOf(g.attribute_program()));
      t->set_material_count(g.material_count());
      t->set_material_index_buffer(IdOf(g.material_index_buffer()));
      t->set_material_index_offset(g.material_indices().offset);
      t->set_material_index_stride(g.material_indices().stride);
      t->set_material_index_format(static_cast<uint32_t>(g.material_indices().format));
      break;
    }
    case Kind::kMaterial: {
      auto& mat = static_cast<Material&>(o);
      v1::Material* m = out->mutable_material();
      m->set_id(mat.id());
      m->set_version(mat.version());
      for (unsigned r = 0; r < c.ray_type_count(); ++r) {
        m->add_closest_hit(IdOf(mat.closest_hit(r)));
        m->add_any_hit(IdOf(mat.any_hit(r)));
      }
      LowerVariables(mat.variables(), m->mutable_variables());
      break;
    }
    case Kind::kGeometryInstance: {
      auto& gi = static_cast<GeometryInstance&>(o);
      v1::GeometryInstance* m = out->mutable_geometry_instance();
      m->set_id(gi.id());
      m->set_version(gi.version());
      m->set_geometry(IdOf(gi.geometry()));
      for (unsigned i = 0; i < gi.material_count(); ++i) m->add_materials(IdOf(gi.material(i)));
      LowerVariables(gi.variables(), m->mutable_variables());
      break;
    }
    case Kind::kGeometryGroup: {
      auto& gg = static_cast<GeometryGroup&>(o);
      v1::GeometryGroup* m = out->mutable_geometry_group();
      m->set_id(gg.id());
      m->set_version(gg.version());
      m->set_acceleration(IdOf(gg.acceleration()));
      for (unsigned i = 0; i < gg.child_count(); ++i) m->add_children(IdOf(gg.child(i)));
      break;
    }
    case Kind::kGroup: {
      auto& g = static_cast<Group&>(o);
      v1::Group* m = out->mutable_group();
      m->set_id(g.id());
      m->set_version(g.version());
      m->set_acceleration(IdOf(g.acceleration()));
      for (unsigned i = 0; i < g.child_count(); ++i) LowerNodeRef(g.child(i), m->add_children());
      break;
    }
    case Kind::kSelector: {
      auto& s = static_cast<Selector&>(o);
      v1::Selector* m = out->mutable_selector();
      m->set_id(s.id());
      m->set_version(s.version());
      m->set_visit_program(IdOf(s.visit_program()));
      for (unsigned i = 0; i < s.child_count(); ++i) LowerNodeRef(s.child(i), m->add_children());
      LowerVariables(s.variables(), m->mutable_variables());
      break;
    }
    case Kind::kTransform: {
      auto& t = static_cast<Transform&>(o);
      v1::Transform* m = out->mutable_transform();
      m->set_id(t.id());
      m->set_version(t.version());
      for (float f : t.matrix()) m->add_matrix(f);
      for (float f : t.inverse()) m->add_inverse(f);
      LowerNodeRef(t.child(), m->mutable_child());
      break;
    }
    case Kind::kAcceleration: {
      auto& a = static_cast<Acceleration&>(o);
      v1::Acceleration* m = out->mutable_acceleration();
      m->set_id(a.id());
      m->set_version(a.version());
      m->set_builder(a.builder());
      m->set_traverser(a.traverser());
      for (const auto& [k, v] : a.properties()) (*m->mutable_properties())[k] = v;
      m->set_build_epoch(a.build_epoch());
      LowerRestoredBounds(a, m);
      break;
    }
    case Kind::kContext:
    case Kind::kVariable:
      break;
  }
}

// Adds the chunks of `b` the device lacks; returns what it holds afterwards. With device pointers
// for every device, device `ordinal` gets its own view instead of the host contents.
BufferSyncState LowerChunks(Buffer& b, const BufferSyncState* known, int ordinal,
                            v1::StateDelta* delta) {
  BufferSyncState next;
  next.byte_size = b.byte_size();
  next.host_write_epoch = b.host_write_epoch();
  const unsigned char* own = b.PerDeviceBytes(ordinal);
  const unsigned char* source = own != nullptr ? own : b.bytes();
  if (own != nullptr) {
    for (uint64_t begin = 0; begin < b.byte_size(); begin += kChunkBytes) {
      next.hashes.push_back(ChunkHash(reinterpret_cast<const char*>(own) + begin,
                                      std::min<uint64_t>(kChunkBytes, b.byte_size() - begin)));
    }
  } else {
    next.hashes = b.ChunkHashes();
  }
  const std::vector<uint64_t>& hashes = next.hashes;
  const bool same_shape = known != nullptr && known->byte_size == b.byte_size() &&
                          known->hashes.size() == hashes.size();
  // GPU_LOCAL copies diverge on each device, so equal hashes prove nothing there: every host
  // write is broadcast in full, to a device with its own view too (a single pointer's contents
  // reach every device at every launch that way); otherwise a view is compared with what the
  // device was last sent.
  const bool force =
      b.gpu_local() && (known == nullptr || known->host_write_epoch != b.host_write_epoch());
  for (size_t i = 0; i < hashes.size(); ++i) {
    const bool changed = !same_shape || known->hashes[i] != hashes[i];
    const bool ship = b.gpu_local() && own == nullptr ? force : changed || force;
    if (!ship) continue;
    uint64_t begin = i * kChunkBytes;
    uint64_t end = std::min<uint64_t>(b.byte_size(), begin + kChunkBytes);
    v1::BufferChunk* chunk = delta->add_chunks();
    chunk->set_buffer_id(b.id());
    chunk->set_offset(begin);
    chunk->set_data(source + begin, end - begin);
    chunk->set_hash(hashes[i]);
  }
  return next;
}

// Ships the module of `p` in slices, unless the device has it or this delta carries it already.
void LowerModule(const Program& p, const DeviceSync& sync, PreparedDelta* out) {
  LowerModuleBytes(p.module_hash(), p.module_bytes(), sync, out);
}

}  // namespace

PreparedDelta BuildDelta(Context& context, const DeviceSync& sync) {
  PreparedDelta out;
  v1::StateDelta& delta = out.delta;
  delta.set_session_id(sync.session_id);
  delta.set_sequence(sync.next_sequence);
  LowerContext(context, delta.mutable_context());

  // What travels: reachable objects the device has not seen at their version, and every buffer
  // (their chunks may have changed), reachable or not. Found before sorting, so that a launch
  // after a small change sorts only that: with 100,000 instances sorting them all took longer
  // than the rest of the delta.
  std::vector<Object*> objects;
  auto seen_at_version = [&](const Object* o) {
    auto known = sync.versions.find(o->id());
    return known != sync.versions.end() && known->second == o->version();
  };
  // Samplers travel like buffers, reachable or not (programs reach them by id); they hold no
  // texels, so a sampler is lowered only when its version changed.
  for (Object* o : context.Reachable()) {
    if (o->kind() != Kind::kBuffer && o->kind() != Kind::kTextureSampler && !seen_at_version(o)) {
      objects.push_back(o);
    }
  }
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kBuffer ||
        (object->kind() == Kind::kTextureSampler && !seen_at_version(object))) {
      objects.push_back(object);
    }
  }
  // Creation order: programs and buffers usually come before what refers to them.
  std::sort(objects.begin(), objects.end(),
            [](const Object* a, const Object* b) { return a->id() < b->id(); });

  for (Object* o : objects) {
    const bool relowered = !seen_at_version(o);
    if (relowered) {
      LowerObject(context, *o, sync.ordinal, delta.add_objects());
      out.versions.emplace_back(o->id(), o->version());
      if (o->kind() == Kind::kProgram) LowerModule(static_cast<Program&>(*o), sync, &out);
    }
    if (o->kind() == Kind::kBuffer) {
      auto& b = static_cast<Buffer&>(*o);
      if (!b.ships_content()) continue;
      // A buffer object travels again only after the host reallocated it (rtBufferSetSize,
      // SetFormat, SetElementSize), and a device zeroes its copy whenever it takes a buffer
      // object: chunk hashes it held before say nothing about it then, so every chunk travels.
      auto it = sync.buffers.find(b.id());
      const BufferSyncState* state = relowered || it == sync.buffers.end() ? nullptr : &it->second;
      out.buffers.emplace_back(b.id(), LowerChunks(b, state, sync.ordinal, &delta));
    }
  }

  std::vector<uint64_t> removed;
  for (const auto& [id, version] : sync.versions) {
    if (context.FindById(id) == nullptr) removed.push_back(id);
  }
  std::sort(removed.begin(), removed.end());
  for (uint64_t id : removed) delta.add_removed(id);
  return out;
}

PreparedDelta BuildDelta(Context& context, const DeviceSlot& slot) {
  PreparedDelta out = BuildDelta(context, slot.sync);
  if (context.extension() != nullptr) context.extension()->AddToDelta(slot, &out);
  return out;
}

void LowerModuleBytes(const std::string& hash, const std::string& bytes, const DeviceSync& sync,
                      PreparedDelta* out) {
  if (sync.modules.contains(hash) ||
      std::find(out->modules.begin(), out->modules.end(), hash) != out->modules.end()) {
    return;
  }
  // Slices no larger than buffer chunks keep every Apply stream message under the same bound.
  for (uint64_t begin = 0; begin < bytes.size(); begin += kChunkBytes) {
    v1::ModuleChunk* chunk = out->delta.add_modules();
    chunk->set_module_hash(hash);
    chunk->set_offset(begin);
    chunk->set_total_size(bytes.size());
    chunk->set_data(bytes.data() + begin, std::min<uint64_t>(kChunkBytes, bytes.size() - begin));
  }
  out->modules.push_back(hash);
}

void CommitDelta(PreparedDelta&& prepared, DeviceSync* sync) {
  sync->next_sequence = prepared.delta.sequence() + 1;
  sync->context_version = prepared.delta.context().version();
  for (uint64_t id : prepared.delta.removed()) {
    sync->versions.erase(id);
    sync->buffers.erase(id);
  }
  for (auto& [id, version] : prepared.versions) sync->versions[id] = version;
  for (auto& [id, state] : prepared.buffers) sync->buffers[id] = std::move(state);
  for (std::string& hash : prepared.modules) sync->modules.insert(std::move(hash));
  for (const auto& commit : prepared.commits) commit(sync);
}

}  // namespace tessera::api
