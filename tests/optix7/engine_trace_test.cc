// The OptiX 7 engine's optixTrace end to end: real program modules (programs/engine_trace.cu),
// accelerations built as optixAccelBuild builds them, SBT records in device memory, and what every
// program saw read back from device memory. The expectations are the OptiX 7.7 guide's: SBT
// indexing (7.3), hit kinds and barycentrics (11.5), instance transforms, ids, masks and flags
// (5.5), ray flags and any-hit control (11.2).
#include <cstring>

#include "engine_fixture.h"

namespace tessera::optix7_test {
namespace {

TEST_F(EngineTest, TrianglesHitAndMissWithPayloadsBarycentricsAndSbtIndexing) {
  // Input 0: one triangle, one record. Input 1: two triangles with their own records (SBT index
  // offsets 0 and 1) and primitive index offset 10. SBT-GAS indices: 0, then 1 and 2.
  std::vector<float> two = Triangle(2);
  const std::vector<float> c = Triangle(4);
  two.insert(two.end(), c.begin(), c.end());
  const OptixTraversableHandle gas =
      Build({Triangles(Triangle(0), {0, 1, 2}), Triangles(two, {0, 1, 2, 3, 4, 5}, 0, 10, {0, 1})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  const uint64_t probe = HitGroup(trace_module(), "__closesthit__probe");
  sbt.hit = {probe, probe, probe};
  EngineParams p = DownZ(0.25f, 0.5f);
  p.step.x = 2.f;  // x = 0.25, 2.25, 4.25, 6.25: triangles A, B, C, then nothing
  p.handle = gas;
  Result r = Run(sbt, p, 4);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.tile.exceptions_size(), 0);
  const uint32_t values[3] = {0xA0, 0xA1, 0xA2};
  const uint32_t prims[3] = {0, 10, 11};
  for (unsigned i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(r.word(i, 0), values[i]);
    EXPECT_EQ(r.word(i, 1), prims[i]);  // with the input's primitive index offset
    EXPECT_EQ(r.word(i, 2), static_cast<uint32_t>(OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE));
    EXPECT_NEAR(r.real(i, 3), 0.25f, 1e-5f);  // barycentrics: the weights of vertices 1 and 2
    EXPECT_NEAR(r.real(i, 4), 0.5f, 1e-5f);
    EXPECT_EQ(r.word(i, 5), ~0u);  // no instance (guide 11.7)
    EXPECT_EQ(r.word(i, 6), i);    // SBT-GAS index
    EXPECT_NEAR(r.real(i, 7), 1.f, 1e-6f);
    EXPECT_EQ(r.word(i, 9), 1u);  // front face
    EXPECT_EQ(r.word(i, 10), 0u);
    EXPECT_NEAR(r.real(i, 11), 0.25f + 2.f * i, 1e-5f);  // object space is world space
    EXPECT_NEAR(r.real(i, 12), 0.25f + 2.f * i, 1e-5f);
    EXPECT_EQ(r.word(i, 13), static_cast<uint32_t>(gas));
    EXPECT_EQ(r.real(i, 14), 2.f * i + 1.f);  // optixGetTriangleVertexData: vertex 1's x
    EXPECT_EQ(r.word(i, 15), 1u);             // optixGetTriangleBarycentrics are attributes 0 and 1
  }
  // The miss program: its record, the ray's tmax, flags and mask; the rest untouched.
  EXPECT_EQ(r.word(3, 0), Sbt::kMissBase);
  EXPECT_EQ(r.real(3, 7), 100.f);
  EXPECT_EQ(r.word(3, 8), 0u);
  EXPECT_EQ(r.word(3, 9), 0xFFu);
  EXPECT_EQ(r.word(3, 1), ~0u);

  // Two ray types: stride 2, offset 1, miss index 1 (guide 7.3.5).
  sbt.hit = {probe, probe, probe, probe, probe, probe};
  sbt.miss.push_back(sbt.miss[0]);
  p.sbt_stride = 2;
  p.sbt_offset = 1 | 0x30;  // only the lowest 4 bits count
  p.miss_index = 1;
  r = Run(sbt, p, 4);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 0xA1u);
  EXPECT_EQ(r.word(1, 0), 0xA3u);
  EXPECT_EQ(r.word(2, 0), 0xA5u);
  EXPECT_EQ(r.word(3, 0), Sbt::kMissBase + 1);

  // An index past the hit group records raises TRAVERSAL_INVALID_HIT_SBT; without an exception
  // program the tile reports it.
  sbt.hit = {probe};
  p.sbt_offset = 0;
  p.sbt_stride = 1;
  p.miss_index = 0;
  sbt.miss.resize(1);
  r = Run(sbt, p, 2);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  ASSERT_GE(r.tile.exceptions_size(), 1);
  EXPECT_EQ(static_cast<int>(r.tile.exceptions(0).code()),
            OPTIX_EXCEPTION_CODE_TRAVERSAL_INVALID_HIT_SBT);
  EXPECT_EQ(r.tile.exceptions(0).launch_index(0), 1u);
  EXPECT_NE(r.tile.exceptions(0).details().find("hit group record 1"), std::string::npos)
      << r.tile.exceptions(0).details();
}

TEST_F(EngineTest, CustomPrimitivesReportAttributesAndAnAnyHitIgnoresSome) {
  // Spheres along -z; the any-hit program ignores even primitives, so the nearest (0) is passed
  // over for the next (1).
  const std::vector<float4> spheres = {make_float4(0, 0, -2, 0.5f), make_float4(0, 0, -4, 0.5f),
                                       make_float4(0, 0, -6, 0.5f), make_float4(0, 0, -8, 0.5f)};
  EngineParams p = DownZ(0.f, 0.f);
  p.handle = Build({Spheres(spheres)});
  p.spheres = reinterpret_cast<const float4*>(Upload(spheres));
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__ignore_even",
                      "__intersection__sphere")};
  const Result r = Run(sbt, p, 2);  // x = 0 hits, x = 1 passes beside every sphere
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.tile.exceptions_size(), 0);
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  EXPECT_EQ(r.word(0, 1), 1u);  // primitive 0 was ignored
  EXPECT_EQ(r.word(0, 2), 5u);  // the intersection program's hit kind
  EXPECT_EQ(r.word(0, 3), 10u);
  EXPECT_EQ(r.word(0, 4), 77u);
  EXPECT_NEAR(r.real(0, 7), 4.5f, 1e-5f);
  EXPECT_EQ(r.word(0, 9), 0u);   // hit kind 5: the lowest bit set reads as a back face
  EXPECT_GE(r.word(0, 10), 2u);  // any-hit ran on 0 (ignored) and 1 at least
  EXPECT_EQ(r.word(0, 15), 0u);  // not a triangle: no vertex data asked for
  EXPECT_EQ(r.word(1, 0), Sbt::kMissBase);
  EXPECT_EQ(r.word(1, 10), 0u);
}

OptixInstance Instance(const float transform[12], unsigned id, unsigned sbt_offset, unsigned mask,
                       unsigned flags, OptixTraversableHandle child) {
  OptixInstance inst{};
  std::memcpy(inst.transform, transform, sizeof(inst.transform));
  inst.instanceId = id;
  inst.sbtOffset = sbt_offset;
  inst.visibilityMask = mask;
  inst.flags = flags;
  inst.traversableHandle = child;
  return inst;
}

TEST_F(EngineTest, InstancesPlaceTheirGasWithIdsSbtOffsetsMasksAndFlippedFaces) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(0), {0, 1, 2})});
  const float moved[12] = {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0};
  const float scaled[12] = {2, 0, 0, 20, 0, 1, 0, 0, 0, 0, 1, 0};
  const OptixTraversableHandle ias =
      Build({Instances({Instance(moved, 100, 0, 1, OPTIX_INSTANCE_FLAG_FLIP_TRIANGLE_FACING, gas),
                        Instance(scaled, 200, 1, 2, OPTIX_INSTANCE_FLAG_NONE, gas)})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  const uint64_t probe = HitGroup(trace_module(), "__closesthit__probe");
  sbt.hit = {probe, probe};
  EngineParams p = DownZ(10.25f, 0.5f);
  p.step.x = 10.25f;  // x = 10.25 (instance 0), 20.5 (instance 1), 30.75 (nothing)
  p.handle = ias;
  Result r = Run(sbt, p, 3);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.tile.exceptions_size(), 0);
  // Instance 0: record 0, id 100, index 0, its facing flipped.
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  EXPECT_EQ(r.word(0, 5), 100u);
  EXPECT_EQ(r.word(0, 8), 0u);
  EXPECT_EQ(r.word(0, 2), static_cast<uint32_t>(OPTIX_HIT_KIND_TRIANGLE_BACK_FACE));
  EXPECT_EQ(r.word(0, 9), 0u);
  // Instance 1: sbtOffset 1 selects record 1; id 200, index 1.
  EXPECT_EQ(r.word(1, 0), 0xA1u);
  EXPECT_EQ(r.word(1, 5), 200u);
  EXPECT_EQ(r.word(1, 8), 1u);
  EXPECT_EQ(r.word(1, 2), static_cast<uint32_t>(OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE));
  for (unsigned i = 0; i < 2; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(r.word(i, 6), 0u);
    EXPECT_NEAR(r.real(i, 11), 0.25f, 1e-5f);              // the hit point in object space
    EXPECT_NEAR(r.real(i, 12), 10.25f * (i + 1), 1e-4f);   // and back in world space
    EXPECT_EQ(r.word(i, 13), static_cast<uint32_t>(gas));  // the GAS, not the IAS
    EXPECT_EQ(r.real(i, 14), 1.f);                         // vertex data in object space
  }
  EXPECT_EQ(r.word(2, 0), Sbt::kMissBase);

  // Visibility masks: a ray of mask 1 sees instance 0 only, one of mask 2 instance 1 only.
  p.visibility_mask = 1;
  r = Run(sbt, p, 2);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  EXPECT_EQ(r.word(1, 0), Sbt::kMissBase);
  EXPECT_EQ(r.word(1, 9), 1u);    // the miss program sees the ray's mask
  p.visibility_mask = 2 | 0x100;  // bits past the 8 of a mask do not count
  r = Run(sbt, p, 2);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), Sbt::kMissBase);
  EXPECT_EQ(r.word(1, 0), 0xA1u);

  // The transform queries at instance 1 (x scaled by 2, moved by 20).
  const uint64_t transforms = HitGroup(trace_module(), "__closesthit__transforms");
  sbt.hit = {transforms, transforms};
  p.visibility_mask = 0xFF;
  p.origin.x = 20.5f;
  r = Run(sbt, p, 1);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.tile.exceptions_size(), 0);
  EXPECT_EQ(r.word(0, 0), 1u);     // one instance on the way to the GAS
  EXPECT_EQ(r.word(0, 1), 200u);   // optixGetInstanceIdFromHandle
  EXPECT_EQ(r.real(0, 2), 2.f);    // the instance's transform
  EXPECT_EQ(r.real(0, 3), -10.f);  // and its inverse: x' = (x - 20) / 2
  EXPECT_EQ(r.real(0, 4), 20.f);   // object to world
  EXPECT_EQ(r.word(0, 5), 1u);     // OPTIX_TRANSFORM_TYPE_INSTANCE
  EXPECT_EQ(r.word(0, 6), static_cast<uint32_t>(gas));
  EXPECT_EQ(r.real(0, 7), 0.5f);  // normals by the inverse transpose
  EXPECT_EQ(r.real(0, 8), 0.5f);
  EXPECT_EQ(r.word(0, 9), static_cast<uint32_t>(gas));  // optixGetInstanceTraversableFromIAS
  EXPECT_EQ(r.real(0, 10), 0.5f);                       // world to object
}

TEST_F(EngineTest, RayFlagsCullFacesAndDisableClosestHit) {
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe")};
  EngineParams down = DownZ(0.25f, 0.5f);
  down.handle = Build({Triangles(Triangle(0), {0, 1, 2})});
  EngineParams up = down;
  up.origin.z = -1.f;
  up.direction.z = 1.f;
  struct Case {
    const char* name;
    const EngineParams& params;
    unsigned flags;
    uint32_t record;  // what payload 0 ends as
    uint32_t kind;
  } cases[] = {
      {"front, no flags", down, 0, 0xA0, OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE},
      {"back, no flags", up, 0, 0xA0, OPTIX_HIT_KIND_TRIANGLE_BACK_FACE},
      {"front, back culled", down, OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES, 0xA0,
       OPTIX_HIT_KIND_TRIANGLE_FRONT_FACE},
      {"back, back culled", up, OPTIX_RAY_FLAG_CULL_BACK_FACING_TRIANGLES, Sbt::kMissBase, ~0u},
      {"front, front culled", down, OPTIX_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES, Sbt::kMissBase,
       ~0u},
      {"back, front culled", up, OPTIX_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES, 0xA0,
       OPTIX_HIT_KIND_TRIANGLE_BACK_FACE},
      // A hit without its closest-hit program changes nothing, and runs no miss program.
      {"closest hit disabled", down, OPTIX_RAY_FLAG_DISABLE_CLOSESTHIT, ~0u, ~0u},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EngineParams p = c.params;
    p.ray_flags = c.flags;
    const Result r = Run(sbt, p, 1);
    ASSERT_TRUE(r.prepared.ok()) << r.prepared;
    EXPECT_EQ(r.word(0, 0), c.record);
    EXPECT_EQ(r.word(0, 2), c.kind);
    if (c.record == Sbt::kMissBase) {
      EXPECT_EQ(r.word(0, 8), c.flags);  // optixGetRayFlags
    }
  }
}

TEST_F(EngineTest, AnyHitFollowsRayOverInstanceOverGeometryFlags) {
  // The any-hit program ignores every hit: where it runs the ray misses.
  const OptixTraversableHandle plain = Build({Triangles(Triangle(0), {0, 1, 2})});
  const OptixTraversableHandle opaque =
      Build({Triangles(Triangle(0), {0, 1, 2}, OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT)});
  const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  const OptixTraversableHandle plain_disabled = Build(
      {Instances({Instance(identity, 0, 0, 0xFF, OPTIX_INSTANCE_FLAG_DISABLE_ANYHIT, plain)})});
  const OptixTraversableHandle opaque_enforced = Build(
      {Instances({Instance(identity, 0, 0, 0xFF, OPTIX_INSTANCE_FLAG_ENFORCE_ANYHIT, opaque)})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__ignore_all")};
  struct Case {
    const char* name;
    OptixTraversableHandle handle;
    unsigned flags;
    bool hit;
    uint32_t any_hit_calls;
  } cases[] = {
      {"any-hit runs", plain, 0, false, 1},
      {"ray disables", plain, OPTIX_RAY_FLAG_DISABLE_ANYHIT, true, 0},
      {"ray culls enforced", plain, OPTIX_RAY_FLAG_CULL_ENFORCED_ANYHIT, false, 0},
      {"geometry disables", opaque, 0, true, 0},
      {"ray enforces over geometry", opaque, OPTIX_RAY_FLAG_ENFORCE_ANYHIT, false, 1},
      {"ray culls disabled", opaque, OPTIX_RAY_FLAG_CULL_DISABLED_ANYHIT, false, 0},
      {"instance disables", plain_disabled, 0, true, 0},
      {"ray enforces over instance", plain_disabled, OPTIX_RAY_FLAG_ENFORCE_ANYHIT, false, 1},
      {"instance enforces over geometry", opaque_enforced, 0, false, 1},
      {"ray disables over instance", opaque_enforced, OPTIX_RAY_FLAG_DISABLE_ANYHIT, true, 0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EngineParams p = DownZ(0.25f, 0.5f);
    p.handle = c.handle;
    p.ray_flags = c.flags;
    const Result r = Run(sbt, p, 1);
    ASSERT_TRUE(r.prepared.ok()) << r.prepared;
    EXPECT_EQ(r.word(0, 0), c.hit ? 0xA0u : Sbt::kMissBase);
    EXPECT_EQ(r.word(0, 10), c.any_hit_calls);  // 0xDEAD would say the program went on
  }
}

TEST_F(EngineTest, TerminateRayAndTerminateOnFirstHitStopAfterOneAnyHit) {
  // Two triangles on the ray's path, at t = 1 and t = 2.
  std::vector<float> both = Triangle(0);
  const std::vector<float> far = Triangle(0, -1);
  both.insert(both.end(), far.begin(), far.end());
  EngineParams p = DownZ(0.25f, 0.5f);
  p.handle = Build({Triangles(both, {0, 1, 2, 3, 4, 5})});
  Sbt sbt;
  sbt.raygen = Raygen(trace_module(), "__raygen__trace");
  sbt.miss = {Miss(trace_module(), "__miss__probe")};
  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__terminate")};
  Result r = Run(sbt, p, 1);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  EXPECT_EQ(r.word(0, 10), 1u);  // traversal stopped at the first candidate, which was kept
  const float t = r.real(0, 7);
  EXPECT_TRUE(t == 1.f || t == 2.f) << t;

  sbt.hit = {HitGroup(trace_module(), "__closesthit__probe", "__anyhit__count")};
  r = Run(sbt, p, 1);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_NEAR(r.real(0, 7), 1.f, 1e-6f);  // without a flag the closest hit wins
  p.ray_flags = OPTIX_RAY_FLAG_TERMINATE_ON_FIRST_HIT;
  r = Run(sbt, p, 1);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), 0xA0u);
  EXPECT_EQ(r.word(0, 10), 1u);
}

}  // namespace
}  // namespace tessera::optix7_test
