// End-to-end tests of the in-process device fed hand-built proto messages: binding, tracing
// through user geometry, triangles and transforms, nesting, exceptions and printing.
#include "tessera/worker/inproc_device.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <map>
#include <string>
#include <thread>

#include "tessera/rt.h"
#include "testdata/module_delta.h"

namespace tessera {
namespace {

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";

class Scene {
 public:
  Scene() {
    auto* c = delta_.mutable_context();
    c->set_entry_point_count(1);
    c->set_ray_type_count(1);
    c->set_stack_size(1024);
    c->set_exception_mask(1u << (RT_EXCEPTION_STACK_OVERFLOW - RT_EXCEPTION_PROGRAM_ID_INVALID));
    for (int i = 0; i < 3; ++i) c->add_print_launch_index(-1);
    delta_.set_session_id(1);
  }
  uint64_t Program(const std::string& function) {
    auto* p = delta_.add_objects()->mutable_program();
    p->set_id(++next_id_);
    p->set_module_path(kModule);
    if (module_hash_.empty()) {
      module_hash_ = testing::AddModuleBytes(&delta_, testing::ReadModuleFile(kModule));
    }
    p->set_module_hash(module_hash_);
    p->set_function(function);
    return p->id();
  }
  uint64_t Buffer(uint32_t desc, uint32_t format, uint64_t element_size,
                  std::vector<uint64_t> dims) {
    auto* b = delta_.add_objects()->mutable_buffer();
    b->set_id(++next_id_);
    b->set_desc(desc);
    b->set_format(format);
    b->set_element_size(element_size);
    for (uint64_t d : dims) b->add_dims(d);
    return b->id();
  }
  void Chunk(uint64_t buffer, const void* data, size_t size) {
    auto* c = delta_.add_chunks();
    c->set_buffer_id(buffer);
    c->set_data(data, size);
  }
  static void SetObject(google::protobuf::RepeatedPtrField<v1::Variable>* vars,
                        const std::string& name, uint32_t type, uint64_t id) {
    auto* v = vars->Add();
    v->set_name(name);
    v->set_type(type);
    v->set_object_id(id);
  }
  static void SetValue(google::protobuf::RepeatedPtrField<v1::Variable>* vars,
                       const std::string& name, uint32_t type, const void* data, size_t size) {
    auto* v = vars->Add();
    v->set_name(name);
    v->set_type(type);
    v->set_data(data, size);
  }
  google::protobuf::RepeatedPtrField<v1::Variable>* ContextVars() {
    return delta_.mutable_context()->mutable_variables();
  }
  v1::ContextState* Context() { return delta_.mutable_context(); }

  // A GeometryGroup with one sphere instance; returns the group id.
  uint64_t SphereGroup(float x, float y, float z, float r, uint64_t closest_hit,
                       uint64_t any_hit = 0) {
    uint64_t is = Program("sphere_intersect"), bb = Program("sphere_bounds");
    auto* g = delta_.add_objects()->mutable_geometry();
    g->set_id(++next_id_);
    g->set_primitive_count(1);
    g->set_intersection_program(is);
    g->set_bounding_box_program(bb);
    float s[4] = {x, y, z, r};
    SetValue(g->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, s, sizeof(s));
    auto* m = delta_.add_objects()->mutable_material();
    m->set_id(++next_id_);
    m->add_closest_hit(closest_hit);
    m->add_any_hit(any_hit);
    float tint[3] = {1, 1, 1};
    SetValue(m->mutable_variables(), "tint", RT_OBJECTTYPE_FLOAT3, tint, sizeof(tint));
    auto* gi = delta_.add_objects()->mutable_geometry_instance();
    gi->set_id(++next_id_);
    gi->set_geometry(g->id());
    gi->add_materials(m->id());
    last_instance_ = gi->id();
    auto* a = delta_.add_objects()->mutable_acceleration();
    a->set_id(++next_id_);
    a->set_builder("Bvh");
    auto* gg = delta_.add_objects()->mutable_geometry_group();
    gg->set_id(++next_id_);
    gg->set_acceleration(a->id());
    gg->add_children(gi->id());
    return gg->id();
  }
  uint64_t last_instance() const { return last_instance_; }
  v1::StateDelta& delta() { return delta_; }
  uint64_t NextId() { return ++next_id_; }

 private:
  v1::StateDelta delta_;
  std::string module_hash_;  // of kModule, whose bytes the delta carries once set
  uint64_t next_id_ = 0;
  uint64_t last_instance_ = 0;
};

struct Result {
  absl::Status status;
  std::map<uint64_t, std::string> buffers;
  std::vector<v1::PrintRecord> prints;
  std::vector<v1::ExceptionReport> exceptions;
  int region_messages = 0;  // results that carried written regions
};

// `tile_rows` > 0 cuts a 2D launch into tiles of that many rows.
Result Launch(Device& device, v1::StateDelta& delta, std::vector<uint64_t> dims,
              uint64_t sequence = 1, uint64_t tile_rows = 0) {
  delta.set_sequence(sequence);
  Result r;
  r.status = device.Apply(delta);
  if (!r.status.ok()) return r;
  v1::LaunchRequest req;
  req.set_session_id(1);
  req.set_launch_id(sequence);  // a new launch: INPUT_OUTPUT contents are snapshot
  for (uint64_t d : dims) req.add_dims(d);
  const uint64_t rows =
      dims.size() == 2 && tile_rows > 0 ? tile_rows : (dims.size() == 2 ? dims[1] : 0);
  if (rows == 0) {
    auto* tile = req.add_tiles();
    for (uint64_t d : dims) {
      tile->add_origin(0);
      tile->add_size(d);
    }
  }
  for (uint64_t y = 0; rows > 0 && y < dims[1]; y += rows) {
    auto* tile = req.add_tiles();
    tile->set_index(req.tiles_size() - 1);
    tile->add_origin(0);
    tile->add_origin(y);
    tile->add_size(dims[0]);
    tile->add_size(std::min(rows, dims[1] - y));
  }
  std::atomic<bool> cancel{false};
  r.status = device.Launch(req, cancel, [&](v1::TileResult&& t) {
    // Regions hold the elements programs touched; the rest reads as zeros (see Pixel).
    if (t.regions_size() > 0) ++r.region_messages;
    for (const auto& reg : t.regions()) {
      std::string& b = r.buffers[reg.buffer_id()];
      if (b.size() < reg.offset() + reg.data().size()) b.resize(reg.offset() + reg.data().size());
      b.replace(reg.offset(), reg.data().size(), reg.data());
    }
    for (const auto& p : t.prints()) r.prints.push_back(p);
    for (const auto& e : t.exceptions()) r.exceptions.push_back(e);
  });
  return r;
}

const float* Pixel(const Result& r, uint64_t buffer, int x, int y, int width) {
  static const float kUnwritten[4] = {0, 0, 0, 0};
  auto it = r.buffers.find(buffer);
  const size_t offset = 16 * (size_t(y) * width + x);
  if (it == r.buffers.end() || it->second.size() < offset + 16) return kUnwritten;
  return reinterpret_cast<const float*>(it->second.data() + offset);
}

// A scene whose ray generation program `write_index` writes (x, y, scale) into a FLOAT4 output
// buffer of w x h; returns the buffer's id.
uint64_t WriteIndexScene(Scene& s, uint64_t w, uint64_t h) {
  s.Context()->add_ray_generation(s.Program("write_index"));
  const uint64_t out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {w, h});
  Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
  return out;
}

TEST(InprocDevice, RayGenerationWritesEveryIndexWithStaticInitializer) {
  auto device = CreateInprocDevice(2);
  Scene s;
  const uint64_t out = WriteIndexScene(s, 7, 5);
  Result r = Launch(*device, s.delta(), {7, 5});
  ASSERT_TRUE(r.status.ok()) << r.status;
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 7; ++x) {
      const float* p = Pixel(r, out, x, y, 7);
      EXPECT_EQ(p[0], x);
      EXPECT_EQ(p[1], y);
      EXPECT_EQ(p[2], 2.0f);  // static initializer of `scale`
    }
  }
}

TEST(InprocDevice, ContextVariableOverridesStaticInitializer) {
  auto device = CreateInprocDevice(1);
  Scene s;
  const uint64_t out = WriteIndexScene(s, 2, 2);
  float scale = 7.5f;
  Scene::SetValue(s.ContextVars(), "scale", RT_OBJECTTYPE_FLOAT, &scale, 4);
  Result r = Launch(*device, s.delta(), {2, 2});
  ASSERT_TRUE(r.status.ok()) << r.status;
  EXPECT_EQ(Pixel(r, out, 1, 1, 2)[2], 7.5f);
}

// As in OptiX, a value binds only to a variable declared with its type, though the bytes fit;
// user data binds to any declaration of its size.
TEST(InprocDevice, ValueOfAnotherTypeIsATypeMismatchNamingTheVariable) {
  auto device = CreateInprocDevice(1);
  Scene s;
  const uint64_t out = WriteIndexScene(s, 2, 2);
  const int three = 3;
  Scene::SetValue(s.ContextVars(), "scale", RT_OBJECTTYPE_INT, &three, 4);
  Result r = Launch(*device, s.delta(), {2, 2});
  ASSERT_EQ(r.status.code(), absl::StatusCode::kInvalidArgument) << r.status;
  EXPECT_NE(r.status.message().find("'scale' is declared as float but was set as int"),
            std::string::npos)
      << r.status;

  const float user = 4.5f;
  s.delta().mutable_objects()->Clear();
  s.ContextVars()->RemoveLast();
  Scene::SetValue(s.ContextVars(), "scale", RT_OBJECTTYPE_USER, &user, 4);
  r = Launch(*device, s.delta(), {2, 2}, /*sequence=*/2);
  ASSERT_TRUE(r.status.ok()) << r.status;
  EXPECT_EQ(Pixel(r, out, 1, 1, 2)[2], 4.5f);
}

class SphereTest : public ::testing::Test {
 protected:
  void SetUp() override {
    s.Context()->add_ray_generation(s.Program("camera"));
    s.Context()->add_miss(s.Program("miss"));
    out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {kSize, kSize});
    Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
  }
  static constexpr int kSize = 16;
  Scene s;
  uint64_t out = 0;
};

TEST_F(SphereTest, HitsShowTheNormalAndMissesTheBackground) {
  uint64_t gg = s.SphereGroup(0, 0, 0, 1, s.Program("closest_hit"));
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg);
  auto device = CreateInprocDevice(2);
  Result r = Launch(*device, s.delta(), {kSize, kSize});
  ASSERT_TRUE(r.status.ok()) << r.status;
  const float* center = Pixel(r, out, kSize / 2, kSize / 2, kSize);
  EXPECT_NEAR(center[2], 0.0f, 0.15f);  // normal points at the camera: -z
  EXPECT_GT(center[0], 0.3f);
  const float* corner = Pixel(r, out, 0, 0, kSize);
  EXPECT_EQ(corner[0], 0.f);
  EXPECT_EQ(corner[2], 1.f);  // miss color
}

TEST_F(SphereTest, TransformMovesTheSphereAndTransformsNormals) {
  uint64_t gg = s.SphereGroup(0, 0, 0, 0.5f, s.Program("closest_hit"));
  // Group -> Transform(translate x by +1) -> Transform(identity) -> GeometryGroup: two
  // transform levels, deeper than Embree's single instance level.
  auto* a = s.delta().add_objects()->mutable_acceleration();
  a->set_id(s.NextId());
  a->set_builder("Bvh");
  auto* inner = s.delta().add_objects()->mutable_transform();
  inner->set_id(s.NextId());
  float ident[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (float f : ident) {
    inner->add_matrix(f);
    inner->add_inverse(f);
  }
  inner->mutable_child()->set_id(gg);
  inner->mutable_child()->set_type(RT_OBJECTTYPE_GEOMETRY_GROUP);
  auto* outer = s.delta().add_objects()->mutable_transform();
  outer->set_id(s.NextId());
  float m[16] = {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float inv[16] = {1, 0, 0, -1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) {
    outer->add_matrix(m[i]);
    outer->add_inverse(inv[i]);
  }
  outer->mutable_child()->set_id(inner->id());
  outer->mutable_child()->set_type(RT_OBJECTTYPE_TRANSFORM);
  auto* group = s.delta().add_objects()->mutable_group();
  group->set_id(s.NextId());
  group->set_acceleration(a->id());
  auto* ch = group->add_children();
  ch->set_id(outer->id());
  ch->set_type(RT_OBJECTTYPE_TRANSFORM);
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GROUP, group->id());
  auto device = CreateInprocDevice(2);
  Result r = Launch(*device, s.delta(), {kSize, kSize});
  ASSERT_TRUE(r.status.ok()) << r.status;
  // Camera spans x in [-2, 2]: the sphere now sits at x = 1 → pixel 12; the old center misses.
  EXPECT_EQ(Pixel(r, out, kSize / 2, kSize / 2, kSize)[2], 1.f);
  const float* hit = Pixel(r, out, 12, kSize / 2, kSize);
  EXPECT_LT(hit[2], 0.5f);
}

TEST_F(SphereTest, NestedTraceUpToStackLimitThenOverflowRunsExceptionProgram) {
  uint64_t gg = s.SphereGroup(0, 0, 0, 1, s.Program("recursive_hit"));
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg);
  int depth = 3;
  Scene::SetValue(s.ContextVars(), "max_depth", RT_OBJECTTYPE_INT, &depth, 4);
  s.Context()->add_exception(s.Program("exception"));
  auto device = CreateInprocDevice(2);
  Result r = Launch(*device, s.delta(), {kSize, kSize});
  ASSERT_TRUE(r.status.ok()) << r.status;
  // Center: hit (depth 0) → inner ray starts inside the sphere, hits the back (1) → then it
  // leaves the sphere and misses (blue) → colors add one red per level.
  const float* c = Pixel(r, out, kSize / 2, kSize / 2, kSize);
  EXPECT_EQ(c[0], 2.f);
  EXPECT_EQ(c[2], 1.f);

  // A stack too small for two levels raises RT_EXCEPTION_STACK_OVERFLOW.
  Scene s2;
  s2.Context()->add_ray_generation(s2.Program("camera"));
  s2.Context()->add_miss(s2.Program("miss"));
  s2.Context()->add_exception(s2.Program("exception"));
  s2.Context()->set_stack_size(128);
  uint64_t out2 = s2.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {kSize, kSize});
  Scene::SetObject(s2.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out2);
  uint64_t gg2 = s2.SphereGroup(0, 0, 0, 1, s2.Program("recursive_hit"));
  Scene::SetObject(s2.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg2);
  auto device2 = CreateInprocDevice(1);
  Result r2 = Launch(*device2, s2.delta(), {kSize, kSize});
  ASSERT_TRUE(r2.status.ok()) << r2.status;
  const float* e = Pixel(r2, out2, kSize / 2, kSize / 2, kSize);
  EXPECT_EQ(e[0], float(RT_EXCEPTION_STACK_OVERFLOW));
  EXPECT_EQ(e[3], -1.f);
  EXPECT_EQ(Pixel(r2, out2, 0, 0, kSize)[2], 1.f);  // misses are unaffected
}

TEST(InprocDevice, UserExceptionAndBufferBoundsFollowEnableFlags) {
  for (bool enabled : {false, true}) {
    Scene s;
    s.Context()->add_ray_generation(s.Program("throw_user"));
    s.Context()->add_exception(s.Program("exception"));
    s.Context()->set_user_exceptions(enabled);
    uint64_t out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {2, 2});
    Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
    auto device = CreateInprocDevice(1);
    Result r = Launch(*device, s.delta(), {2, 2});
    ASSERT_TRUE(r.status.ok()) << r.status;
    EXPECT_EQ(Pixel(r, out, 1, 1, 2)[0], enabled ? float(RT_EXCEPTION_USER + 5) : 0.f);
  }
  for (bool enabled : {false, true}) {
    Scene s;
    s.Context()->add_ray_generation(s.Program("read_out_of_bounds"));
    s.Context()->add_exception(s.Program("exception"));
    if (enabled) {
      s.Context()->set_exception_mask(
          1u << (RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS - RT_EXCEPTION_PROGRAM_ID_INVALID));
    }
    uint64_t out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {2, 2});
    Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
    auto device = CreateInprocDevice(1);
    Result r = Launch(*device, s.delta(), {2, 2});
    ASSERT_TRUE(r.status.ok()) << r.status;
    EXPECT_EQ(Pixel(r, out, 0, 0, 2)[0],
              enabled ? float(RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS) : 0.f);
  }
}

TEST(InprocDevice, PrintRespectsEnableAndLaunchIndexFilter) {
  Scene s;
  s.Context()->add_ray_generation(s.Program("print_index"));
  s.Context()->set_print_enabled(true);
  s.Context()->set_print_launch_index(0, 1);  // only x == 1
  auto device = CreateInprocDevice(2);
  Result r = Launch(*device, s.delta(), {3, 2});
  ASSERT_TRUE(r.status.ok()) << r.status;
  ASSERT_EQ(r.prints.size(), 2u);
  for (const auto& p : r.prints) EXPECT_EQ(p.launch_index(0), 1u);
}

TEST(InprocDevice, TraceFromIntersectionProgramFailsTheLaunchWithAMessage) {
  Scene s;
  s.Context()->add_ray_generation(s.Program("camera"));
  s.Context()->add_miss(s.Program("miss"));
  uint64_t out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {4, 4});
  Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
  uint64_t gg = s.SphereGroup(0, 0, 0, 1, s.Program("closest_hit"));
  // Swap in the bad intersection program.
  for (auto& o : *s.delta().mutable_objects()) {
    if (o.has_geometry())
      o.mutable_geometry()->set_intersection_program(s.Program("bad_intersect"));
  }
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg);
  auto device = CreateInprocDevice(1);
  Result r = Launch(*device, s.delta(), {4, 4});
  ASSERT_FALSE(r.status.ok());
  EXPECT_NE(r.status.message().find("rtTrace"), std::string::npos) << r.status;
  EXPECT_NE(r.status.message().find("intersection"), std::string::npos) << r.status;
}

// A module's functions carry no signature: a bounding box program set as another kind would
// write its bounds through whatever its second argument register held. Every call passes a
// scratch pointer instead, and a program that writes there fails the launch by name.
TEST_F(SphereTest, BoundingBoxProgramSetAsClosestHitFailsTheLaunchByName) {
  uint64_t gg = s.SphereGroup(0, 0, 0, 1, s.Program("sphere_bounds"));
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg);
  auto device = CreateInprocDevice(2);
  Result r = Launch(*device, s.delta(), {kSize, kSize});
  ASSERT_EQ(r.status.code(), absl::StatusCode::kFailedPrecondition) << r.status;
  EXPECT_NE(r.status.message().find("sphere_bounds"), std::string::npos) << r.status;
  EXPECT_NE(r.status.message().find("closest hit"), std::string::npos) << r.status;
  EXPECT_NE(r.status.message().find("bounding box"), std::string::npos) << r.status;
}

TEST(InprocDevice, BoundingBoxProgramSetAsRayGenerationFailsTheLaunchByName) {
  auto device = CreateInprocDevice(1);
  Scene s;
  s.Context()->add_ray_generation(s.Program("sphere_bounds"));
  Result r = Launch(*device, s.delta(), {2, 2});
  ASSERT_EQ(r.status.code(), absl::StatusCode::kFailedPrecondition) << r.status;
  EXPECT_NE(r.status.message().find("sphere_bounds"), std::string::npos) << r.status;
}

// A bounding box program that writes nothing (here a closest-hit program set in its place)
// leaves its primitive's bounds invalid: the primitive is never hit, rather than a box at the
// origin.
TEST_F(SphereTest, BoundsLeftUnwrittenMeanThePrimitiveIsNeverHit) {
  uint64_t gg = s.SphereGroup(0, 0, 0, 1, s.Program("closest_hit"));
  for (auto& o : *s.delta().mutable_objects()) {
    if (o.has_geometry()) o.mutable_geometry()->set_bounding_box_program(s.Program("closest_hit"));
  }
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, gg);
  auto device = CreateInprocDevice(1);
  Result r = Launch(*device, s.delta(), {kSize, kSize});
  ASSERT_TRUE(r.status.ok()) << r.status;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) EXPECT_EQ(Pixel(r, out, x, y, kSize)[2], 1.f);  // misses
  }
}

// A launch whose acceleration takes long to build stops soon after a cancel, without waiting
// for the build: in the bounding box programs (`slow_last_only` 0) or in Embree's build, which
// starts after the cancel (1: only the last primitive's bounds are slow).
class CancelBuildTest : public SphereTest, public ::testing::WithParamInterface<int> {
 protected:
  v1::LaunchRequest Request(uint64_t launch_id) {
    v1::LaunchRequest req;
    req.set_session_id(1);
    req.set_launch_id(launch_id);
    v1::Tile* tile = req.add_tiles();
    for (int i = 0; i < 2; ++i) {
      req.add_dims(kSize);
      tile->add_origin(0);
      tile->add_size(kSize);
    }
    return req;
  }
};

TEST_P(CancelBuildTest, CancelStopsTheBuildPromptlyAndTheDeviceGoesOn) {
  constexpr int kPrimitives = 100000;
  const int slow_last_only = GetParam();
  const unsigned delay_us = slow_last_only ? 700000 : 100;  // 0.7 s once, or 10 s in all
  Scene::SetValue(s.ContextVars(), "bounds_delay_us", RT_OBJECTTYPE_UNSIGNED_INT, &delay_us, 4);
  Scene::SetValue(s.ContextVars(), "slow_last_only", RT_OBJECTTYPE_INT, &slow_last_only, 4);
  Scene::SetValue(s.ContextVars(), "primitive_count", RT_OBJECTTYPE_INT, &kPrimitives, 4);
  uint64_t slow = s.SphereGroup(0, 0, 0, 1, s.Program("closest_hit"));
  for (auto& o : *s.delta().mutable_objects()) {
    if (!o.has_geometry()) continue;
    o.mutable_geometry()->set_primitive_count(kPrimitives);
    o.mutable_geometry()->set_bounding_box_program(s.Program("slow_sphere_bounds"));
  }
  Scene::SetObject(s.ContextVars(), "top_object", RT_OBJECTTYPE_GEOMETRY_GROUP, slow);
  auto device = CreateInprocDevice(1);
  s.delta().set_sequence(1);
  ASSERT_TRUE(device->Apply(s.delta()).ok());
  std::atomic<bool> cancel{false};
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(slow_last_only ? 300 : 200));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  absl::Status status = device->Launch(Request(1), cancel, [](v1::TileResult&&) {});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  canceller.join();
  EXPECT_EQ(status.code(), absl::StatusCode::kCancelled) << status;
  EXPECT_NE(status.message().find(slow_last_only ? "building geometry group" : "bounding box"),
            std::string::npos)
      << status;
  // Uncancelled, the bounds alone take 10 s (or 0.7 s, then Embree builds 100,000 boxes).
  EXPECT_LT(seconds, slow_last_only ? 2.0 : 1.5) << status;

  // The device goes on: a launch on a small sphere renders it.
  s.delta().mutable_objects()->Clear();
  uint64_t small = s.SphereGroup(0, 0, 0, 1, s.Program("closest_hit"));
  for (v1::Variable& v : *s.ContextVars()) {
    if (v.name() == "top_object") v.set_object_id(small);
  }
  Result r = Launch(*device, s.delta(), {kSize, kSize}, /*sequence=*/2);
  ASSERT_TRUE(r.status.ok()) << r.status;
  EXPECT_GT(Pixel(r, out, kSize / 2, kSize / 2, kSize)[0], 0.3f);  // the sphere's normal
}

INSTANTIATE_TEST_SUITE_P(InBoundsAndInEmbree, CancelBuildTest, ::testing::Values(0, 1));

TEST(InprocDevice, OutOfOrderDeltaIsRejectedAndStateKept) {
  Scene s;
  s.Context()->add_ray_generation(s.Program("write_index"));
  uint64_t out = s.Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, 16, {2, 2});
  Scene::SetObject(s.ContextVars(), "output", RT_OBJECTTYPE_BUFFER, out);
  auto device = CreateInprocDevice(1);
  ASSERT_TRUE(Launch(*device, s.delta(), {2, 2}).status.ok());
  v1::StateDelta bad = s.delta();
  bad.set_sequence(5);
  EXPECT_FALSE(device->Apply(bad).ok());
  v1::StateDelta chunk_out_of_range;
  chunk_out_of_range.set_session_id(1);
  chunk_out_of_range.set_sequence(2);
  *chunk_out_of_range.mutable_context() = s.delta().context();
  auto* c = chunk_out_of_range.add_chunks();
  c->set_buffer_id(out);
  c->set_offset(60);
  c->set_data(std::string(8, 'x'));
  EXPECT_FALSE(device->Apply(chunk_out_of_range).ok());
}

}  // namespace
}  // namespace tessera

namespace tessera {
namespace {

// A worker device sends a call's results in write epochs while later pieces trace. Elements
// written by pieces of several epochs, scattered far from their own rows, and an element changed
// then changed back in a later epoch must reach the host as a single epoch leaves them.
class WriteEpochTest : public ::testing::TestWithParam<int> {
 protected:
  static constexpr uint64_t kWidth = 64, kHeight = 64, kBins = 61;
  static uint32_t Read(const std::string& bytes, size_t i) {
    uint32_t v = 0;
    if (bytes.size() >= 4 * (i + 1)) std::memcpy(&v, bytes.data() + 4 * i, 4);
    return v;
  }
};

TEST_P(WriteEpochTest, ResultsMatchOneEpoch) {
  setenv("TESSERA_WRITE_EPOCHS", std::to_string(GetParam()).c_str(), 1);
  auto device = CreateInprocDevice(4, /*results_in_rounds=*/true);
  unsetenv("TESSERA_WRITE_EPOCHS");
  Scene s;
  uint64_t counts = s.Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, 4, {kBins});
  uint64_t tickets = s.Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, 4, {1});
  uint64_t flags = s.Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_INT, 4, {1});
  std::vector<uint32_t> zeros(kBins, 0);
  s.Chunk(counts, zeros.data(), 4 * kBins);
  s.Chunk(tickets, zeros.data(), 4);
  s.Chunk(flags, zeros.data(), 4);
  Scene::SetObject(s.ContextVars(), "counts", RT_OBJECTTYPE_BUFFER, counts);
  Scene::SetObject(s.ContextVars(), "tickets", RT_OBJECTTYPE_BUFFER, tickets);
  Scene::SetObject(s.ContextVars(), "flags", RT_OBJECTTYPE_BUFFER, flags);
  s.Context()->add_ray_generation(s.Program("scatter_counts"));
  Result r = Launch(*device, s.delta(), {kWidth, kHeight}, 1, /*tile_rows=*/2);
  ASSERT_TRUE(r.status.ok()) << r.status;

  std::vector<uint32_t> expected(kBins, 0), got(kBins);
  for (uint64_t y = 0; y < kHeight; ++y) {
    for (uint64_t x = 0; x < kWidth; ++x) ++expected[(x * 7 + y * 13) % kBins];
  }
  for (size_t i = 0; i < kBins; ++i) got[i] = Read(r.buffers[counts], i);
  EXPECT_EQ(got, expected);
  EXPECT_EQ(Read(r.buffers[tickets], 0), kWidth * kHeight);
  // The flag went to 7 and back to 0: the host has 0, whether 7 travelled or not.
  EXPECT_EQ(Read(r.buffers[flags], 0), 0u);
  // Several epochs: results went out before the call ended.
  if (GetParam() > 1) {
    EXPECT_GT(r.region_messages, 1);
  }
}

INSTANTIATE_TEST_SUITE_P(Epochs, WriteEpochTest, ::testing::Values(1, 2, 8));

}  // namespace
}  // namespace tessera
