// Motion blur, transform traversables, graphs deeper than one instance level and built-in spheres
// on the OptiX 7 engine, end to end (programs/engine_trace.cu, __closesthit__graph). The
// expectations are the OptiX 7.7 guide's: keys evenly spaced over the motion range with time
// clamped or vanishing outside it (5.10.1), matrix keys interpolated element-wise (5.10.4), SRT
// keys by nlerp and C = T * R * S (5.10.5), transform lists outermost first (11.11), the most
// recently visited instance's id and index (11.7).
#include <cmath>
#include <cstring>

#include "engine_fixture.h"

namespace tessera::optix7_test {
namespace {

class MotionTest : public EngineTest {
 protected:
  MotionTest() {
    sbt_.raygen = Raygen(trace_module(), "__raygen__trace");
    sbt_.miss = {Miss(trace_module(), "__miss__probe")};
    sbt_.hit = {HitGroup(trace_module(), "__closesthit__graph")};
  }

  // Triangles with one vertex buffer per motion key.
  OptixTraversableHandle MovingTriangles(const std::vector<std::vector<float>>& keys,
                                         const OptixMotionOptions& motion) {
    std::vector<CUdeviceptr> buffers;
    for (const std::vector<float>& k : keys) buffers.push_back(Upload(k));
    OptixBuildInput in = Triangles(keys[0], {0, 1, 2});
    in.triangleArray.vertexBuffers = buffers.data();
    return Build({in}, motion);
  }

  // One launch index tracing down -z from (x, y) at `time`.
  Result At(OptixTraversableHandle handle, float x, float y, float time, float z = 1.f) {
    EngineParams p = DownZ(x, y);
    p.origin.z = z;
    p.handle = handle;
    p.time = time;
    Result r = Run(sbt_, p, 1);
    EXPECT_TRUE(r.prepared.ok()) << r.prepared;
    EXPECT_EQ(r.tile.exceptions_size(), 0) << r.tile.DebugString();
    return r;
  }

  static bool Hit(const Result& r) { return r.word(0, 0) == Sbt::kHitBase; }

  Sbt sbt_;
};

TEST_F(MotionTest, TrianglesMoveBetweenKeysAndClampOrVanishOutsideTheirRange) {
  // Key 0 at x in [0, 1], key 1 at [10, 11], over time [0, 1].
  const OptixTraversableHandle gas =
      MovingTriangles({Triangle(0), Triangle(10)}, OptixMotionOptions{2, 0, 0.f, 1.f});
  for (float time : {0.f, 0.5f, 1.f}) {
    SCOPED_TRACE(time);
    const float x0 = 10.f * time;
    Result r = At(gas, x0 + 0.25f, 0.25f, time);
    ASSERT_TRUE(Hit(r));
    EXPECT_EQ(r.word(0, 1), 0u);         // no transforms
    EXPECT_EQ(r.word(0, 6), ~0u);        // no instance
    EXPECT_EQ(r.word(0, 8), 2u);         // optixGetGASMotionStepCount
    EXPECT_EQ(r.real(0, 9), 1.f);        // optixGetGASMotionTimeEnd
    EXPECT_EQ(r.real(0, 3), 1.f);        // t
    EXPECT_FLOAT_EQ(r.real(0, 14), x0);  // optixGetTriangleVertexData at the ray's time
    EXPECT_EQ(r.word(0, 13), static_cast<uint32_t>(OPTIX_PRIMITIVE_TYPE_TRIANGLE));
    // Where the triangle is at other times is empty now.
    EXPECT_FALSE(Hit(At(gas, x0 + 0.25f + 5.f, 0.25f, time)));
  }
  // Outside the range time is clamped: at 1.5 the triangle stays at key 1, at -1 at key 0.
  EXPECT_TRUE(Hit(At(gas, 10.25f, 0.25f, 1.5f)));
  EXPECT_TRUE(Hit(At(gas, 0.25f, 0.25f, -1.f)));

  // OPTIX_MOTION_FLAG_END_VANISH removes it after the range; START_VANISH before it.
  const OptixTraversableHandle vanishing = MovingTriangles(
      {Triangle(0), Triangle(10)},
      OptixMotionOptions{2, OPTIX_MOTION_FLAG_START_VANISH | OPTIX_MOTION_FLAG_END_VANISH, 0.f,
                         1.f});
  EXPECT_TRUE(Hit(At(vanishing, 10.25f, 0.25f, 1.f)));
  EXPECT_FALSE(Hit(At(vanishing, 10.25f, 0.25f, 1.5f)));
  EXPECT_FALSE(Hit(At(vanishing, 0.25f, 0.25f, -0.5f)));

  // A range other than [0, 1], three keys: x 0 at time 2, 10 at 3, 30 at 4.
  const OptixTraversableHandle three = MovingTriangles({Triangle(0), Triangle(10), Triangle(30)},
                                                       OptixMotionOptions{3, 0, 2.f, 4.f});
  Result r = At(three, 20.25f, 0.25f, 3.5f);
  ASSERT_TRUE(Hit(r));
  EXPECT_FLOAT_EQ(r.real(0, 14), 20.f);
  EXPECT_EQ(r.word(0, 8), 3u);
  EXPECT_EQ(r.real(0, 9), 4.f);
  EXPECT_TRUE(Hit(At(three, 5.25f, 0.25f, 2.5f)));

  // Instanced directly by an IAS (an Embree instance: the GAS's range is the IAS's time).
  const OptixTraversableHandle ias = Build({Instances({Translated(100.f, 5, gas)})});
  r = At(ias, 105.25f, 0.25f, 0.5f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.word(0, 1), 1u);
  EXPECT_EQ(r.word(0, 6), 5u);
  EXPECT_FLOAT_EQ(r.real(0, 4), 5.25f);  // object space
  EXPECT_FLOAT_EQ(r.real(0, 12), 105.25f);
  // Two moving GASes of different ranges under one IAS: the second becomes a node.
  const OptixTraversableHandle both =
      Build({Instances({Translated(100.f, 5, gas), Translated(200.f, 6, three)})});
  EXPECT_TRUE(Hit(At(both, 105.25f, 0.25f, 0.5f)));
  r = At(both, 220.25f, 0.25f, 3.5f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.word(0, 6), 6u);
  EXPECT_FLOAT_EQ(r.real(0, 14), 20.f);
}

TEST_F(MotionTest, CustomPrimitiveBoxesMoveWithTheirKeys) {
  // Spheres as custom primitives (params.spheres holds the centre the intersection program
  // uses); the boxes per key bound where the program looks: a box around x = 0 at time 0 and
  // around x = 10 at time 1 hides the sphere at x = 0 from rays at time 1.
  const std::vector<float4> spheres = {make_float4(0.f, 0.f, 0.f, 0.5f)};
  const std::vector<OptixAabb> key0 = {{-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f}};
  const std::vector<OptixAabb> key1 = {{9.5f, -0.5f, -0.5f, 10.5f, 0.5f, 0.5f}};
  std::vector<CUdeviceptr> boxes = {Upload(key0), Upload(key1)};
  OptixBuildInput in = Spheres(spheres);
  in.customPrimitiveArray.aabbBuffers = boxes.data();
  const OptixTraversableHandle gas = Build({in}, OptixMotionOptions{2, 0, 0.f, 1.f});
  sbt_.hit = {HitGroup(trace_module(), "__closesthit__probe", "", "__intersection__sphere")};
  EngineParams p = DownZ(0.f, 0.f);
  p.handle = gas;
  p.spheres = reinterpret_cast<const float4*>(Upload(spheres));
  p.time = 0.f;
  Result r = Run(sbt_, p, 1);
  ASSERT_TRUE(r.prepared.ok()) << r.prepared;
  EXPECT_EQ(r.word(0, 0), Sbt::kHitBase);
  EXPECT_EQ(r.word(0, 2), 5u);  // the program's hit kind
  p.time = 1.f;
  r = Run(sbt_, p, 1);
  EXPECT_EQ(r.word(0, 0), Sbt::kMissBase);
}

TEST_F(MotionTest, MatrixMotionTransformMovesItsChildAndShowsInTheTransformList) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(0), {0, 1, 2})});
  OptixMatrixMotionTransform mt{};
  mt.child = gas;
  mt.motionOptions = OptixMotionOptions{2, 0, 0.f, 1.f};
  const float keys[2][12] = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0},
                             {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0}};
  std::memcpy(mt.transform, keys, sizeof(keys));
  const OptixTraversableHandle motion =
      Transform(&mt, sizeof(mt), OPTIX_TRANSFORM_TYPE_MATRIX_MOTION_TRANSFORM);
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 7, motion)})});
  for (float time : {0.f, 0.5f, 1.f}) {
    SCOPED_TRACE(time);
    const float x = 10.f * time + 0.25f;
    Result r = At(ias, x, 0.25f, time);
    ASSERT_TRUE(Hit(r));
    EXPECT_EQ(r.word(0, 1), 2u);           // the instance, then the motion transform
    EXPECT_EQ(r.word(0, 2), 0x24u);        // OPTIX_TRANSFORM_TYPE_INSTANCE (4), MATRIX_MOTION (2)
    EXPECT_EQ(r.word(0, 15), 2u);          // optixGetMatrixMotionTransformFromHandle: its keys
    EXPECT_EQ(r.word(0, 6), 7u);           // the instance's id
    EXPECT_EQ(r.word(0, 7), 0u);           // and index
    EXPECT_EQ(r.word(0, 8), 1u);           // the GAS has no motion
    EXPECT_FLOAT_EQ(r.real(0, 4), 0.25f);  // object space
    EXPECT_FLOAT_EQ(r.real(0, 5), -10.f * time);  // world to object at the ray's time
    EXPECT_FLOAT_EQ(r.real(0, 12), x);            // and back
    EXPECT_FALSE(Hit(At(ias, x + 5.f, 0.25f, time)));
  }
}

TEST_F(MotionTest, SrtMotionTransformRotatesByNlerp) {
  const OptixTraversableHandle gas = Build({Triangles(Triangle(0), {0, 1, 2})});
  OptixSRTMotionTransform srt{};
  srt.child = gas;
  srt.motionOptions = OptixMotionOptions{2, 0, 0.f, 1.f};
  const float s = std::sqrt(0.5f);
  srt.srtData[0] = OptixSRTData{1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0};
  srt.srtData[1] = OptixSRTData{1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, s, s, 0, 0, 0};  // 90 degrees
  const OptixTraversableHandle motion =
      Transform(&srt, sizeof(srt), OPTIX_TRANSFORM_TYPE_SRT_MOTION_TRANSFORM);
  const OptixTraversableHandle ias = Build({Instances({Translated(0.f, 3, motion)})});
  // At time 1 the triangle lies at x in [-1, 0]; at 0.5 it is turned by 45 degrees (the nlerp of
  // two keys is exact half way): object (0.5, 0.25) lies at world (0.17678, 0.53033).
  EXPECT_FALSE(Hit(At(ias, -0.25f, 0.25f, 0.f)));
  Result r = At(ias, -0.25f, 0.25f, 1.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_NEAR(r.real(0, 4), 0.25f, 1e-5f);
  EXPECT_EQ(r.word(0, 2), 0x34u);  // INSTANCE, SRT_MOTION
  EXPECT_EQ(r.word(0, 15), 102u);  // optixGetSRTMotionTransformFromHandle: 2 keys
  r = At(ias, 0.5f * s - 0.25f * s, 0.5f * s + 0.25f * s, 0.5f);
  ASSERT_TRUE(Hit(r));
  EXPECT_NEAR(r.real(0, 4), 0.5f, 1e-5f);
  EXPECT_NEAR(r.real(0, 12), 0.5f * s - 0.25f * s, 1e-5f);
}

TEST_F(MotionTest, ThreeLevelGraphWithAStaticTransform) {
  // top IAS --instance 1 (+100 x)--> mid IAS; mid instance 0 (id 20, +1000 x) is the GAS
  // directly, mid instance 1 (id 21) a static transform (+10 x) over the GAS.
  const OptixTraversableHandle gas = Build({Triangles(Triangle(0), {0, 1, 2})});
  OptixStaticTransform st{};
  st.child = gas;
  const float to_world[12] = {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0};
  const float to_object[12] = {1, 0, 0, -10, 0, 1, 0, 0, 0, 0, 1, 0};
  std::memcpy(st.transform, to_world, sizeof(to_world));
  std::memcpy(st.invTransform, to_object, sizeof(to_object));
  const OptixTraversableHandle fixed =
      Transform(&st, sizeof(st), OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM);
  const OptixTraversableHandle mid =
      Build({Instances({Translated(1000.f, 20, gas), Translated(0.f, 21, fixed)})});
  const OptixTraversableHandle top = Build({Instances({Translated(100.f, 1, mid)})});

  Result r = At(top, 110.25f, 0.25f, 0.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.word(0, 1), 3u);      // top's instance, mid's instance, the static transform
  EXPECT_EQ(r.word(0, 2), 0x144u);  // INSTANCE, INSTANCE, STATIC_TRANSFORM
  EXPECT_EQ(r.word(0, 6), 21u);     // the most recently visited instance
  EXPECT_EQ(r.word(0, 7), 1u);
  EXPECT_EQ(r.word(0, 15), 21u);  // optixGetInstanceIdFromHandle of entry 1
  EXPECT_FLOAT_EQ(r.real(0, 4), 0.25f);
  EXPECT_FLOAT_EQ(r.real(0, 5), -110.f);
  EXPECT_FLOAT_EQ(r.real(0, 12), 110.25f);

  r = At(top, 1100.25f, 0.25f, 0.f);  // mid's Embree instance, inside top's node
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.word(0, 1), 2u);
  EXPECT_EQ(r.word(0, 2), 0x44u);
  EXPECT_EQ(r.word(0, 6), 20u);
  EXPECT_EQ(r.word(0, 7), 0u);
  EXPECT_FLOAT_EQ(r.real(0, 5), -1100.f);
  EXPECT_FALSE(Hit(At(top, 10.25f, 0.25f, 0.f)));  // mid's place without top's instance

  // The closest of hits at several levels wins: a triangle of top at z = 0.5 in front of
  // everything at x 110.25, under mid's node.
  const OptixTraversableHandle near_gas =
      Build({Triangles({109.f, 0, 0.5f, 112.f, 0, 0.5f, 109.f, 1, 0.5f}, {0, 1, 2})});
  const OptixTraversableHandle top2 =
      Build({Instances({Translated(100.f, 1, mid), Translated(0.f, 2, near_gas)})});
  r = At(top2, 110.25f, 0.25f, 0.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.word(0, 6), 2u);
  EXPECT_EQ(r.real(0, 3), 0.5f);
}

TEST_F(MotionTest, BuiltInSpheresReportFacesAndTheirData) {
  const std::vector<float> centres = {0, 0, 0, 5, 0, 0};
  const std::vector<float> radii = {1.f, 0.5f};
  CUdeviceptr c = Upload(centres), rad = Upload(radii);
  const unsigned flags = OPTIX_GEOMETRY_FLAG_NONE;
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_SPHERES;
  in.sphereArray.vertexBuffers = &c;
  in.sphereArray.numVertices = 2;
  in.sphereArray.radiusBuffers = &rad;
  in.sphereArray.flags = &flags;
  in.sphereArray.numSbtRecords = 1;
  const OptixTraversableHandle gas = Build({in});
  Result r = At(gas, 0.f, 0.f, 0.f, 5.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.real(0, 3), 4.f);  // entering at z = 1
  EXPECT_EQ(r.word(0, 13), static_cast<uint32_t>(OPTIX_PRIMITIVE_TYPE_SPHERE));
  EXPECT_EQ(r.real(0, 14), 0.f);  // optixGetSphereData: the centre
  const uint32_t front = r.word(0, 11);
  r = At(gas, 5.f, 0.f, 0.f, 5.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.real(0, 3), 4.5f);
  EXPECT_EQ(r.real(0, 14), 5.f);
  EXPECT_EQ(r.word(0, 11), front);
  // From inside: the way out, a back face.
  r = At(gas, 0.f, 0.f, 0.f, 0.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.real(0, 3), 1.f);
  EXPECT_NE(r.word(0, 11), front);

  // Moving spheres, one radius for all: centre x 0 at time 0, 10 at time 1.
  const std::vector<float> later = {10, 0, 0, 15, 0, 0};
  std::vector<CUdeviceptr> keys = {c, Upload(later)};
  std::vector<CUdeviceptr> radius_keys = {rad, rad};
  in.sphereArray.vertexBuffers = keys.data();
  in.sphereArray.radiusBuffers = radius_keys.data();
  in.sphereArray.singleRadius = 1;
  const OptixTraversableHandle moving = Build({in}, OptixMotionOptions{2, 0, 0.f, 1.f});
  r = At(moving, 5.f, 0.f, 0.5f, 5.f);
  ASSERT_TRUE(Hit(r));
  EXPECT_EQ(r.real(0, 3), 4.f);  // radius 1 (the first), centre at x 5
  EXPECT_EQ(r.real(0, 14), 5.f);
  EXPECT_FALSE(Hit(At(moving, 0.f, 0.f, 0.5f, 5.f)));
}

}  // namespace
}  // namespace tessera::optix7_test
