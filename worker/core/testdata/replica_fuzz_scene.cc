#include "replica_fuzz_scene.h"

#include <filesystem>

#include "google/protobuf/descriptor.h"
#include "google/protobuf/message.h"
#include "tessera/rt.h"
#include "tessera/scheduler/tiling.h"
#include "write_index_delta.h"

namespace tessera::fuzz {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

void AddValue(Variables* vars, const std::string& name, uint32_t type, const void* data,
              size_t size) {
  v1::Variable* v = vars->Add();
  v->set_name(name);
  v->set_type(type);
  v->set_data(data, size);
}

void AddObjectRef(Variables* vars, const std::string& name, uint32_t type, uint64_t id) {
  v1::Variable* v = vars->Add();
  v->set_name(name);
  v->set_type(type);
  v->set_object_id(id);
}

v1::Program* AddProgram(v1::StateDelta& d, uint64_t id, const std::string& function) {
  v1::Program* p = d.add_objects()->mutable_program();
  p->set_id(id);
  p->set_version(1);
  p->set_module_path(kModule);
  p->set_module_hash(d.objects(0).program().module_hash());
  p->set_function(function);
  return p;
}

v1::Acceleration* AddAcceleration(v1::StateDelta& d, uint64_t id) {
  v1::Acceleration* a = d.add_objects()->mutable_acceleration();
  a->set_id(id);
  a->set_version(1);
  a->set_builder("Bvh");
  a->set_traverser("Bvh");
  a->set_build_epoch(1);
  return a;
}

v1::Buffer* AddInput(v1::StateDelta& d, uint64_t id, uint32_t format, uint64_t element_size,
                     const void* data, size_t size) {
  v1::Buffer* b = d.add_objects()->mutable_buffer();
  b->set_id(id);
  b->set_version(1);
  b->set_desc(RT_BUFFER_INPUT);
  b->set_format(format);
  b->set_element_size(element_size);
  b->add_dims(size / element_size);
  v1::BufferChunk* chunk = d.add_chunks();
  chunk->set_buffer_id(id);
  chunk->set_data(data, size);
  chunk->set_hash(0x1234);
  return b;
}

// Entry point 0 writes (x, y, scale, 1) at every launch index (write_index); entry point 1 traces
// a camera ray into a Group of Transform → GeometryGroup → sphere and of a GeometryGroup of one
// native triangle (vertex and index buffers, acceleration properties). Another INPUT buffer and
// exception programs make every kind of object, and buffer chunks, travel.
v1::StateDelta SceneDelta() {
  v1::StateDelta d = testing::WriteIndexDelta(kModule, kSession, 1, kWidth, kHeight);
  v1::ContextState* c = d.mutable_context();
  c->set_entry_point_count(2);
  c->add_ray_generation(kCamera);
  c->add_exception(kException);
  c->add_exception(kException);
  c->add_miss(kMiss);
  c->set_exception_mask(1u << (RT_EXCEPTION_STACK_OVERFLOW - RT_EXCEPTION_PROGRAM_ID_INVALID));
  AddValue(c->mutable_variables(), "scale", RT_OBJECTTYPE_FLOAT, &kScale, sizeof(kScale));
  AddObjectRef(c->mutable_variables(), "top_object", RT_OBJECTTYPE_GROUP, kGroup);
  AddProgram(d, kCamera, "camera");
  AddProgram(d, kMiss, "miss");
  AddProgram(d, kException, "exception");
  AddProgram(d, kIntersect, "sphere_intersect");
  AddProgram(d, kBounds, "sphere_bounds");
  AddProgram(d, kClosestHit, "closest_hit");

  v1::Geometry* g = d.add_objects()->mutable_geometry();
  g->set_id(kGeometry);
  g->set_version(1);
  g->set_primitive_count(1);
  g->set_intersection_program(kIntersect);
  g->set_bounding_box_program(kBounds);
  const float sphere[4] = {0, 0, 0, 1};
  AddValue(g->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, sphere, sizeof(sphere));
  v1::Material* m = d.add_objects()->mutable_material();
  m->set_id(kMaterial);
  m->set_version(1);
  m->add_closest_hit(kClosestHit);
  m->add_any_hit(0);
  const float tint[3] = {1, 0.5f, 1};
  AddValue(m->mutable_variables(), "tint", RT_OBJECTTYPE_FLOAT3, tint, sizeof(tint));
  v1::GeometryInstance* gi = d.add_objects()->mutable_geometry_instance();
  gi->set_id(kInstance);
  gi->set_version(1);
  gi->set_geometry(kGeometry);
  gi->add_materials(kMaterial);
  AddAcceleration(d, kGeometryAccel);
  v1::GeometryGroup* gg = d.add_objects()->mutable_geometry_group();
  gg->set_id(kGeometryGroup);
  gg->set_version(1);
  gg->set_acceleration(kGeometryAccel);
  gg->add_children(kInstance);
  v1::Transform* t = d.add_objects()->mutable_transform();
  t->set_id(kTransform);
  t->set_version(1);
  const float matrix[16] = {1, 0, 0, 0.5f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const float inverse[16] = {1, 0, 0, -0.5f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) {
    t->add_matrix(matrix[i]);
    t->add_inverse(inverse[i]);
  }
  t->mutable_child()->set_id(kGeometryGroup);
  t->mutable_child()->set_type(RT_OBJECTTYPE_GEOMETRY_GROUP);
  AddAcceleration(d, kGroupAccel);
  v1::Group* group = d.add_objects()->mutable_group();
  group->set_id(kGroup);
  group->set_version(1);
  group->set_acceleration(kGroupAccel);
  v1::NodeRef* child = group->add_children();
  child->set_id(kTransform);
  child->set_type(RT_OBJECTTYPE_TRANSFORM);

  const float contents[4] = {1, 2, 3, 4};
  AddInput(d, kInput, RT_FORMAT_FLOAT, 4, contents, sizeof(contents));

  // A triangle in the bottom right corner, in front of the sphere.
  const float vertices[9] = {1, -2, 2, 2, -2, 2, 2, -1, 2};
  const int32_t indices[3] = {0, 1, 2};
  AddInput(d, kVertices, RT_FORMAT_FLOAT3, 12, vertices, sizeof(vertices));
  AddInput(d, kIndices, RT_FORMAT_INT3, 12, indices, sizeof(indices));
  v1::Geometry* tg = d.add_objects()->mutable_geometry();
  tg->set_id(kTriangleGeometry);
  tg->set_version(1);
  tg->set_primitive_count(1);
  tg->set_intersection_program(kIntersect);  // reports the attributes of the triangle's hits
  tg->set_bounding_box_program(kBounds);
  // The intersection program reports the triangle's normal where its rays meet this sphere, and
  // all of them do: a hit it does not report would shade with whatever attributes came before.
  const float around_triangle[4] = {1.5f, -1.5f, 2.f, 1.f};
  AddValue(tg->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, around_triangle,
           sizeof(around_triangle));
  AddObjectRef(tg->mutable_variables(), "vertices", RT_OBJECTTYPE_BUFFER, kVertices);
  AddObjectRef(tg->mutable_variables(), "indices", RT_OBJECTTYPE_BUFFER, kIndices);
  v1::GeometryInstance* ti = d.add_objects()->mutable_geometry_instance();
  ti->set_id(kTriangleInstance);
  ti->set_version(1);
  ti->set_geometry(kTriangleGeometry);
  ti->add_materials(kMaterial);
  v1::Acceleration* ta = AddAcceleration(d, kTriangleAccel);
  ta->set_builder("Trbvh");
  (*ta->mutable_properties())["vertex_buffer_name"] = "vertices";
  (*ta->mutable_properties())["index_buffer_name"] = "indices";
  (*ta->mutable_properties())["vertex_buffer_stride"] = "12";
  v1::GeometryGroup* tgg = d.add_objects()->mutable_geometry_group();
  tgg->set_id(kTriangleGroup);
  tgg->set_version(1);
  tgg->set_acceleration(kTriangleAccel);
  tgg->add_children(kTriangleInstance);
  v1::NodeRef* triangles = group->add_children();
  triangles->set_id(kTriangleGroup);
  triangles->set_type(RT_OBJECTTYPE_GEOMETRY_GROUP);
  return d;
}

v1::LaunchRequest ValidRequest(uint32_t entry, uint64_t launch_id) {
  v1::LaunchRequest r;
  r.set_session_id(kSession);
  r.set_launch_id(launch_id);
  r.set_entry_point(entry);
  r.add_dims(kWidth);
  r.add_dims(kHeight);
  for (v1::Tile& t : scheduler::MakeTiles({kWidth, kHeight}, {4, 4})) *r.add_tiles() = t;
  return r;
}

LaunchOutcome RunLaunch(Device& device, const v1::LaunchRequest& request,
                        std::chrono::milliseconds limit) {
  LaunchOutcome out;
  std::atomic<bool> cancel{false};
  std::mutex mu;
  Watchdog watchdog(cancel, limit);
  out.status = NoThrow("Launch", [&] {
    return device.Launch(request, cancel, [&](v1::TileResult&& t) {
      std::lock_guard<std::mutex> lock(mu);
      for (const v1::BufferRegion& r : t.regions()) {
        if (r.buffer_id() != kOutput) continue;
        testing::ApplyRegion(r, kOutput, &out.output);
        auto mark = [&](uint64_t offset, uint64_t size) {
          for (uint64_t e = offset / 16; e < (offset + size) / 16; ++e) out.written.insert(e);
        };
        if (r.run_offsets_size() == 0) mark(r.offset(), r.data().size());
        for (int i = 0; i < r.run_offsets_size() && i < r.run_sizes_size(); ++i) {
          mark(r.run_offsets(i), r.run_sizes(i));
        }
      }
    });
  });
  out.timed_out = watchdog.fired();
  return out;
}

std::unique_ptr<Device> DeviceWith(const v1::StateDelta& delta) {
  std::unique_ptr<Device> device = CreateInprocDevice(2, /*results_in_rounds=*/true);
  absl::Status s = device->Apply(delta);
  EXPECT_TRUE(s.ok()) << s;
  return device;
}

// The index of the first object of `d` with id `id`, or -1.
int ObjectIndex(const v1::StateDelta& d, uint64_t id) {
  for (int i = 0; i < d.objects_size(); ++i) {
    const v1::Object& o = d.objects(i);
    const Reflection* r = o.GetReflection();
    const FieldDescriptor* f = r->GetOneofFieldDescriptor(o, o.GetDescriptor()->oneof_decl(0));
    if (f == nullptr) continue;
    const Message& body = r->GetMessage(o, f);
    if (body.GetReflection()->GetUInt64(body, body.GetDescriptor()->field(0)) == id) return i;
  }
  return -1;
}

v1::Object* ObjectById(v1::StateDelta& d, uint64_t id) {
  const int i = ObjectIndex(d, id);
  return i < 0 ? nullptr : d.mutable_objects(i);
}

void EraseObject(v1::StateDelta& d, uint64_t id) {
  if (const int i = ObjectIndex(d, id); i >= 0) d.mutable_objects()->DeleteSubrange(i, 1);
}

}  // namespace tessera::fuzz
