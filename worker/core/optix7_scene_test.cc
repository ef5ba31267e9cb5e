// Embree scenes from OptiX 7 acceleration descriptors: triangles hit where they are, custom
// primitives bounded by their boxes, instances placed by their transforms, one build per content
// hash, and handles that are no descriptor refused.
#include "optix7_scene.h"

#include <gtest/gtest.h>
#include <optix_types.h>
#include <tessera/accuracy.h>
#include <tessera/optix7_ext.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace tessera::worker {
namespace {

using memory::AccelHeader;
using memory::AccelInput;
using memory::AccelKind;

// A descriptor assembled by hand, as optixAccelBuild lays it out.
class Descriptor {
 public:
  // One triangle input: `vertices` float[3] each, `indices` uint32[3] each.
  static Descriptor Triangles(const std::vector<float>& vertices,
                              const std::vector<uint32_t>& indices, uint64_t hash) {
    Descriptor d;
    AccelInput in{};
    in.primitive_count = static_cast<uint32_t>(indices.size() / 3);
    in.vertex_count = static_cast<uint32_t>(vertices.size() / 3);
    in.num_sbt_records = 1;
    in.vertices_offset = d.Append(vertices.data(), vertices.size() * 4);
    in.indices_offset = d.Append(indices.data(), indices.size() * 4);
    const uint32_t flags = 0;
    in.flags_offset = d.Append(&flags, 4);
    d.Finish(AccelKind::kTriangles, {in}, in.primitive_count, hash);
    return d;
  }
  static Descriptor Custom(const std::vector<float>& boxes, uint64_t hash) {
    Descriptor d;
    AccelInput in{};
    in.primitive_count = static_cast<uint32_t>(boxes.size() / 6);
    in.num_sbt_records = 1;
    in.aabbs_offset = d.Append(boxes.data(), boxes.size() * 4);
    const uint32_t flags = 0;
    in.flags_offset = d.Append(&flags, 4);
    d.Finish(AccelKind::kCustom, {in}, in.primitive_count, hash);
    return d;
  }
  // Instances of `child` translated by `offsets` along x.
  static Descriptor Instances(uint64_t child, const std::vector<float>& offsets, uint64_t hash) {
    Descriptor d;
    std::vector<unsigned char> records(offsets.size() * memory::kInstanceBytes, 0);
    for (size_t k = 0; k < offsets.size(); ++k) {
      float t[12] = {1, 0, 0, offsets[k], 0, 1, 0, 0, 0, 0, 1, 0};
      std::memcpy(&records[k * 80], t, 48);
      std::memcpy(&records[k * 80 + 64], &child, 8);
    }
    d.bytes_.resize(sizeof(AccelHeader));
    d.Append(records.data(), records.size());
    d.FinishHeader(AccelKind::kInstances, 1, offsets.size(), hash);
    return d;
  }
  uint64_t handle() const { return reinterpret_cast<uint64_t>(bytes_.data()); }
  AccelInput& input(size_t i) {
    return reinterpret_cast<AccelInput*>(bytes_.data() + header().inputs_offset)[i];
  }
  float* vertices() { return reinterpret_cast<float*>(bytes_.data() + input(0).vertices_offset); }
  size_t size() const { return bytes_.size(); }
  AccelHeader& header() { return *reinterpret_cast<AccelHeader*>(bytes_.data()); }

 private:
  Descriptor() { bytes_.reserve(1 << 16); }  // never moves: handles are addresses
  uint64_t Append(const void* data, size_t n) {
    const uint64_t at = bytes_.size();
    bytes_.resize(at + (n + 7) / 8 * 8, 0);
    std::memcpy(&bytes_[at], data, n);
    return at;
  }
  void Finish(AccelKind kind, std::vector<AccelInput> inputs, uint64_t primitives, uint64_t hash) {
    // Inputs after the data here: offsets count from the header either way.
    const uint64_t at = Append(inputs.data(), inputs.size() * sizeof(AccelInput));
    FinishHeader(kind, static_cast<uint32_t>(inputs.size()), primitives, hash);
    header().inputs_offset = at;
  }
  void FinishHeader(AccelKind kind, uint32_t inputs, uint64_t primitives, uint64_t hash) {
    if (bytes_.size() < sizeof(AccelHeader)) bytes_.resize(sizeof(AccelHeader));
    AccelHeader& h = header();
    std::memcpy(h.magic, memory::kAccelMagic, 8);
    h.version = memory::kAccelFormatVersion;
    h.kind = kind;
    h.total_size = bytes_.size();
    h.content_hash = hash;
    h.input_count = inputs;
    h.primitive_count = primitives;
    h.inputs_offset = sizeof(AccelHeader);
  }
  std::vector<unsigned char> bytes_ = std::vector<unsigned char>(sizeof(AccelHeader), 0);
};

// Custom primitives of the test: a hit at the box's centre along the ray.
void HitBoxCentre(const RTCIntersectFunctionNArguments* args) {
  const float* boxes = *static_cast<const float* const*>(args->geometryUserPtr);
  const float* b = boxes + 6 * args->primID;
  RTCRayHitN* rh = args->rayhit;
  RTCRay* ray = reinterpret_cast<RTCRay*>(rh);
  RTCHit* hit = reinterpret_cast<RTCHit*>(reinterpret_cast<char*>(rh) + sizeof(RTCRay));
  const float t = ((b[0] + b[3]) * 0.5f - ray->org_x) / ray->dir_x;
  if (t > ray->tnear && t < ray->tfar) {
    ray->tfar = t;
    hit->geomID = args->geomID;
    hit->primID = args->primID;
    hit->instID[0] = args->context->instID[0];
  }
}

class Optix7SceneTest : public ::testing::Test {
 protected:
  Optix7SceneTest()
      : device_(rtcNewDevice(nullptr)),
        cache_(device_, &HitBoxCentre, [this](uint64_t a) { return Readable(a); }) {}

  // Device memory of the test: the descriptors and buffers it registered.
  size_t Readable(uint64_t address) const {
    for (const auto& [at, size] : memory_) {
      if (address >= at && address < at + size) return at + size - address;
    }
    return 0;
  }
  void Register(const Descriptor& d) { memory_.emplace_back(d.handle(), d.size()); }
  void Register(const void* p, size_t n) { memory_.emplace_back(reinterpret_cast<uint64_t>(p), n); }
  ~Optix7SceneTest() override { rtcReleaseDevice(device_); }

  // The hit of a ray from (x, y, -10) along +z, or from (-10, y, z) along +x.
  RTCRayHit Trace(const Optix7Scene& s, float x, float y, float z, bool along_x = false) {
    RTCRayHit rh{};
    rh.ray.org_x = along_x ? -10.f : x;
    rh.ray.org_y = y;
    rh.ray.org_z = along_x ? z : -10.f;
    rh.ray.dir_x = along_x ? 1.f : 0.f;
    rh.ray.dir_z = along_x ? 0.f : 1.f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(s.scene, &context, &rh);
    return rh;
  }

  std::vector<std::pair<uint64_t, size_t>> memory_;
  RTCDevice device_;
  Optix7SceneCache cache_;
};

TEST_F(Optix7SceneTest, TrianglesAreHitWhereTheDescriptorPutsThem) {
  // Two triangles in the z = 0 plane: [0,1]^2 split along its diagonal.
  Descriptor d = Descriptor::Triangles({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}, 7);
  Register(d);
  auto scene = cache_.Get(d.handle());
  ASSERT_TRUE(scene.ok()) << scene.status();
  RTCRayHit hit = Trace(**scene, 0.8f, 0.2f, 0.f);
  EXPECT_EQ(hit.hit.geomID, 0u);
  EXPECT_EQ(hit.hit.primID, 0u);
  EXPECT_FLOAT_EQ(hit.ray.tfar, 10.f);
  EXPECT_EQ(Trace(**scene, 0.2f, 0.8f, 0.f).hit.primID, 1u);
  EXPECT_EQ(Trace(**scene, 1.5f, 0.5f, 0.f).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ((*scene)->input_of_geometry, std::vector<uint32_t>{0});

  // The same content (hash) is built once, whatever handle names it.
  Descriptor copy =
      Descriptor::Triangles({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}, 7);
  Register(copy);
  auto again = cache_.Get(copy.handle());
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(*again, *scene);
  EXPECT_EQ(cache_.built(), 1u);
}

TEST_F(Optix7SceneTest, CustomPrimitivesAreBoundedByTheirBoxesAndInstancesPlaced) {
  Descriptor boxes = Descriptor::Custom({0, 0, 0, 1, 1, 1, 4, 0, 0, 5, 1, 1}, 11);
  Register(boxes);
  auto gas = cache_.Get(boxes.handle());
  ASSERT_TRUE(gas.ok()) << gas.status();
  RTCBounds bounds;
  rtcGetSceneBounds((*gas)->scene, &bounds);
  EXPECT_EQ(bounds.lower_x, 0.f);
  EXPECT_EQ(bounds.upper_x, 5.f);
  RTCRayHit hit = Trace(**gas, 0.f, 0.5f, 0.5f, /*along_x=*/true);
  EXPECT_EQ(hit.hit.primID, 0u);
  EXPECT_FLOAT_EQ(hit.ray.tfar, 10.5f);  // the first box's centre, x = 0.5

  // Two instances of the boxes, 10 and 20 along x.
  Descriptor ias = Descriptor::Instances(boxes.handle(), {10.f, 20.f}, 12);
  Register(ias);
  auto top = cache_.Get(ias.handle());
  ASSERT_TRUE(top.ok()) << top.status();
  EXPECT_EQ((*top)->children.size(), 2u);
  rtcGetSceneBounds((*top)->scene, &bounds);
  EXPECT_EQ(bounds.lower_x, 10.f);
  EXPECT_EQ(bounds.upper_x, 25.f);
  hit = Trace(**top, 0.f, 0.5f, 0.5f, /*along_x=*/true);
  EXPECT_EQ(hit.hit.instID[0], 0u);
  EXPECT_FLOAT_EQ(hit.ray.tfar, 20.5f);  // x = 10.5

  // An instance of an instance build: without the engine's node intersection function it cannot
  // be traced, said so; with it, a node bounded by its child (x from 10 to 25, moved by 100).
  Descriptor nested = Descriptor::Instances(ias.handle(), {100.f}, 13);
  Register(nested);
  auto refused = cache_.Get(nested.handle());
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kUnimplemented);
  EXPECT_NE(refused.status().message().find("no node intersection function"), std::string::npos);
  cache_.set_node_intersect([](const RTCIntersectFunctionNArguments*) {});
  auto deeper = cache_.Get(nested.handle());
  ASSERT_TRUE(deeper.ok()) << deeper.status();
  const Optix7Node* node = (*deeper)->instances[0].node;
  ASSERT_NE(node, nullptr);
  EXPECT_TRUE((*deeper)->deep);
  EXPECT_EQ(node->child, *top);
  EXPECT_EQ(node->child_handle, ias.handle());
  EXPECT_EQ(node->bounds[0], 110.f);
  EXPECT_EQ(node->bounds[3], 125.f);
}

TEST_F(Optix7SceneTest, HandlesThatAreNoDescriptorAreRefused) {
  std::vector<uint64_t> junk(32, 0x1234);
  Register(junk.data(), junk.size() * 8);
  auto s = cache_.Get(reinterpret_cast<uint64_t>(junk.data()));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("traversable handle 0x"), std::string::npos) << s.status();
  EXPECT_NE(s.status().message().find("not an acceleration"), std::string::npos) << s.status();
  // Not device memory at all (here: memory the test did not register): never read.
  Descriptor d = Descriptor::Triangles({0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 1, 2}, 21);
  s = cache_.Get(d.handle());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("not in device memory"), std::string::npos) << s.status();
  EXPECT_FALSE(cache_.Get(0).ok());
  // Shorter than its header says.
  Register(reinterpret_cast<const void*>(d.handle()), 32);
  EXPECT_FALSE(cache_.Get(d.handle()).ok());
  // An instance naming an address outside device memory.
  Descriptor ias = Descriptor::Instances(0x10, {0.f}, 22);
  Register(ias);
  s = cache_.Get(ias.handle());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("instance 0"), std::string::npos) << s.status();
}

// An n x n grid of squares in z = 0 over [0, 1]^2, two triangles each.
void Grid(unsigned n, std::vector<float>* vertices, std::vector<uint32_t>* indices) {
  for (unsigned y = 0; y <= n; ++y) {
    for (unsigned x = 0; x <= n; ++x) {
      vertices->insert(vertices->end(), {static_cast<float>(x) / static_cast<float>(n),
                                         static_cast<float>(y) / static_cast<float>(n), 0.f});
    }
  }
  for (unsigned y = 0; y < n; ++y) {
    for (unsigned x = 0; x < n; ++x) {
      const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      indices->insert(indices->end(), {a, b, d, a, d, c});
    }
  }
}

TEST_F(Optix7SceneTest, ScenesAreKeyedByTheAccuracyTheyAreBuiltWith) {
  Descriptor d =
      Descriptor::Triangles({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}, 31);
  Register(d);
  auto plain = cache_.Get(d.handle(), 0, 0);
  auto robust = cache_.Get(d.handle(), 0, TESSERA_ACCURACY_ROBUST);
  auto watertight = cache_.Get(d.handle(), 0, TESSERA_ACCURACY_WATERTIGHT);
  ASSERT_TRUE(plain.ok() && robust.ok() && watertight.ok());
  EXPECT_NE(*plain, *robust);
  EXPECT_NE(*robust, *watertight);
  EXPECT_EQ((*plain)->accuracy, 0u);
  EXPECT_EQ((*robust)->accuracy, TESSERA_ACCURACY_ROBUST);
  EXPECT_EQ((*watertight)->accuracy, TESSERA_ACCURACY_WATERTIGHT | TESSERA_ACCURACY_ROBUST);
  ASSERT_EQ((*watertight)->watertight.size(), 1u);
  EXPECT_NE((*watertight)->watertight[0], nullptr);
  EXPECT_EQ(cache_.built(), 3u);
  // The watertight geometry answers as Embree's triangles do: primitive, distance, barycentrics.
  for (const Optix7Scene* s : std::vector<const Optix7Scene*>{*plain, *watertight}) {
    RTCRayHit hit = Trace(*s, 0.75f, 0.25f, 0.f);
    EXPECT_EQ(hit.hit.geomID, 0u);
    EXPECT_EQ(hit.hit.primID, 0u);
    EXPECT_EQ(hit.ray.tfar, 10.f);
    EXPECT_FLOAT_EQ(hit.hit.u, 0.5f);
    EXPECT_FLOAT_EQ(hit.hit.v, 0.25f);
    EXPECT_GT(hit.hit.Ng_z, 0.f);
  }
  // Through the shared diagonal: one of the two triangles, never neither.
  EXPECT_EQ(Trace(**watertight, 0.5f, 0.5f, 0.f).hit.geomID, 0u);
  // A build flag asks the same of one acceleration; the launch's flags add to it.
  d.header().build_flags = TESSERA_OPTIX_BUILD_FLAG_COMPACT;
  auto compact = cache_.Get(d.handle(), 0, TESSERA_ACCURACY_ROBUST);
  ASSERT_TRUE(compact.ok());
  EXPECT_EQ((*compact)->accuracy, TESSERA_ACCURACY_COMPACT | TESSERA_ACCURACY_ROBUST);
}

TEST_F(Optix7SceneTest, AnUpdateRefitsTheSceneOfItsBufferInPlace) {
  std::vector<float> vertices;
  std::vector<uint32_t> indices;
  Grid(400, &vertices, &indices);  // 320,000 triangles
  Descriptor d = Descriptor::Triangles(vertices, indices, 41);
  Descriptor ias = Descriptor::Instances(d.handle(), {0.f}, 42);
  d.header().build_flags = OPTIX_BUILD_FLAG_ALLOW_UPDATE;
  Register(d);
  Register(ias);
  auto t0 = std::chrono::steady_clock::now();
  auto first = cache_.Get(d.handle(), 1);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(first.ok()) << first.status();
  auto top = cache_.Get(ias.handle(), 1);
  ASSERT_TRUE(top.ok()) << top.status();
  EXPECT_EQ(Trace(**top, 0.3f, 0.3f, 0.f).ray.tfar, 10.f);

  // OPTIX_BUILD_OPERATION_UPDATE: the grid moved up by 2, the same buffer, a new content hash.
  for (size_t k = 2; k < vertices.size(); k += 3) d.vertices()[k] = 2.f;
  d.header().content_hash = 43;
  d.input(0).flags = memory::kAccelInputUpdate;
  t0 = std::chrono::steady_clock::now();
  auto refit = cache_.Get(d.handle(), 2);
  const double refit_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(refit.ok()) << refit.status();
  EXPECT_EQ(*refit, *first);  // the same scene
  EXPECT_EQ(cache_.built(), 2u);
  EXPECT_EQ(cache_.refitted(), 1u);
  EXPECT_EQ((*refit)->refits, 1u);
  EXPECT_FLOAT_EQ(Trace(**refit, 0.3f, 0.3f, 0.f).ray.tfar, 12.f);
  // The IAS over it is built again (its old scene held the old bounds).
  auto top2 = cache_.Get(ias.handle(), 2);
  ASSERT_TRUE(top2.ok()) << top2.status();
  EXPECT_EQ(cache_.built(), 3u);
  EXPECT_FLOAT_EQ(Trace(**top2, 0.3f, 0.3f, 0.f).ray.tfar, 12.f);
  std::printf("320,000 triangles: build %.4f s, refit %.4f s\n", build_s, refit_s);

  // A build (no update mark) of the same buffer is a new scene; so is an update that changes the
  // triangles (here: one index).
  d.header().content_hash = 44;
  d.input(0).flags = 0;
  auto rebuilt = cache_.Get(d.handle(), 3);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_EQ(cache_.refitted(), 1u);
  EXPECT_EQ(cache_.built(), 4u);
  d.header().content_hash = 45;
  d.input(0).flags = memory::kAccelInputUpdate;
  reinterpret_cast<uint32_t*>(reinterpret_cast<unsigned char*>(d.handle()) +
                              d.input(0).indices_offset)[0] = 5;
  auto changed = cache_.Get(d.handle(), 4);
  ASSERT_TRUE(changed.ok());
  EXPECT_EQ(cache_.refitted(), 1u);
  EXPECT_EQ(cache_.built(), 5u);
}

}  // namespace
}  // namespace tessera::worker
