#include "tutorial/scene.h"

#include <cmath>
#include <string>
#include <vector>

#include "tutorial/rt_check.h"
#include "tutorial/variables.h"
#include "tutorial/vec_math.h"

namespace tessera::tutorial {
namespace {

RTgeometry CreateGeometry(RTcontext context, ProgramLoader& programs, const char* module,
                          const char* bounds, const char* intersect) {
  RTgeometry geometry = nullptr;
  RT_CHECK(context, rtGeometryCreate(context, &geometry));
  RT_CHECK(context, rtGeometrySetPrimitiveCount(geometry, 1u));
  RT_CHECK(context, rtGeometrySetBoundingBoxProgram(geometry, programs.Get({module, bounds})));
  RT_CHECK(context, rtGeometrySetIntersectionProgram(geometry, programs.Get({module, intersect})));
  return geometry;
}

RTgeometry CreateBox(RTcontext context, ProgramLoader& programs) {
  RTgeometry box = CreateGeometry(context, programs, "tutorial_box", "box_bounds", "box_intersect");
  Variables vars(context, box, rtGeometryDeclareVariable, "box geometry");
  vars.Float3("boxmin", kBoxMin);
  vars.Float3("boxmax", kBoxMax);
  return box;
}

RTgeometry CreateFloor(RTcontext context, ProgramLoader& programs) {
  RTgeometry floor =
      CreateGeometry(context, programs, "tutorial_parallelogram", "bounds", "intersect");
  const float3 anchor = make_float3(-64.0f, kFloorHeight, -64.0f);
  float3 v1 = make_float3(128.0f, 0.0f, 0.0f);
  float3 v2 = make_float3(0.0f, 0.0f, 128.0f);
  const float3 normal = Normalize(Cross(v2, v1));
  const float d = Dot(normal, anchor);
  // Scaled so that dot(v, p - anchor) is the parametric coordinate.
  v1 = Scale(v1, 1.0f / Dot(v1, v1));
  v2 = Scale(v2, 1.0f / Dot(v2, v2));
  Variables vars(context, floor, rtGeometryDeclareVariable, "floor geometry");
  vars.Float4("plane", make_float4(normal.x, normal.y, normal.z, d));
  vars.Float3("v1", v1);
  vars.Float3("v2", v2);
  vars.Float3("anchor", anchor);
  return floor;
}

// The plane through `p` with outward normal `n`, as chull_intersect expects it.
float4 MakePlane(float3 n, const float3& p) {
  n = Normalize(n);
  return make_float4(n.x, n.y, n.z, -Dot(n, p));
}

// A hexagonal prism with a slanted top, as in the SDK tutorial.
RTgeometry CreateChull(RTcontext context, ProgramLoader& programs) {
  RTgeometry chull =
      CreateGeometry(context, programs, "tutorial_chull", "chull_bounds", "chull_intersect");
  constexpr int kSides = 6;
  RTbuffer planes = nullptr;
  RT_CHECK(context, rtBufferCreate(context, RT_BUFFER_INPUT, &planes));
  RT_CHECK(context, rtBufferSetFormat(planes, RT_FORMAT_FLOAT4));
  RT_CHECK(context, rtBufferSetSize1D(planes, kSides + 2));
  void* mapped = nullptr;
  RT_CHECK(context, rtBufferMap(planes, &mapped));
  float4* plane = static_cast<float4*>(mapped);
  const float3 xlate = kChullCenter;
  const float two_pi = 2.0f * static_cast<float>(M_PI);
  for (int i = 0; i < kSides; ++i) {
    const float angle = static_cast<float>(i) / kSides * two_pi;
    const float x = std::cos(angle);
    const float z = std::sin(angle);
    plane[i] = MakePlane(make_float3(x, 0, z),
                         Add(make_float3(x * kChullRadius, 0, z * kChullRadius), xlate));
  }
  plane[kSides + 0] = MakePlane(make_float3(0, -1, 0), Add(make_float3(0, kChullMinY, 0), xlate));
  const float top_angle = 5.0f / kSides * two_pi;
  plane[kSides + 1] = MakePlane(make_float3(std::cos(top_angle), 0.7f, std::sin(top_angle)),
                                Add(make_float3(0, kChullMaxY, 0), xlate));
  RT_CHECK(context, rtBufferUnmap(planes));

  Variables vars(context, chull, rtGeometryDeclareVariable, "chull geometry");
  vars.Object("planes", planes);
  vars.Float3("chull_bbmin", -kChullRadius + xlate.x, kChullMinY + xlate.y,
              -kChullRadius + xlate.z);
  vars.Float3("chull_bbmax", kChullRadius + xlate.x, kChullMaxY + xlate.y, kChullRadius + xlate.z);
  return chull;
}

RTmaterial CreateMaterial(RTcontext context, ProgramLoader& programs, const ProgramRef& closest_hit,
                          const ProgramRef& any_hit) {
  RTmaterial material = nullptr;
  RT_CHECK(context, rtMaterialCreate(context, &material));
  RT_CHECK(context, rtMaterialSetClosestHitProgram(material, 0, programs.Get(closest_hit)));
  if (any_hit.present()) {
    RT_CHECK(context, rtMaterialSetAnyHitProgram(material, 1, programs.Get(any_hit)));
  }
  return material;
}

RTmaterial CreateBoxMaterial(RTcontext context, ProgramLoader& programs, const StepConfig& step) {
  RTmaterial m = CreateMaterial(context, programs, step.box_closest_hit, step.opaque_any_hit);
  Variables vars(context, m, rtMaterialDeclareVariable, "box material");
  vars.Float3("Ka", 0.3f, 0.3f, 0.3f);
  vars.Float3("Kd", 0.6f, 0.7f, 0.8f);
  vars.Float3("Ks", 0.8f, 0.9f, 0.8f);
  vars.Float("phong_exp", 88);
  vars.Float3("reflectivity_n", 0.2f, 0.2f, 0.2f);
  return m;
}

RTmaterial CreateFloorMaterial(RTcontext context, ProgramLoader& programs, const StepConfig& step) {
  RTmaterial m = CreateMaterial(context, programs, step.floor_closest_hit, step.opaque_any_hit);
  Variables vars(context, m, rtMaterialDeclareVariable, "floor material");
  vars.Float3("Ka", 0.3f, 0.3f, 0.1f);
  vars.Float3("Kd", 194 / 255.f * .6f, 186 / 255.f * .6f, 151 / 255.f * .6f);
  vars.Float3("Ks", 0.4f, 0.4f, 0.4f);
  vars.Float("phong_exp", 88);
  vars.Float3("reflectivity", 0.1f, 0.1f, 0.1f);
  vars.Float3("reflectivity_n", 0.05f, 0.05f, 0.05f);
  vars.Float3("tile_v0", kTileV0);
  vars.Float3("tile_v1", kTileV1);
  vars.Float3("crack_color", 0.1f, 0.1f, 0.1f);
  vars.Float("crack_width", 0.02f);
  vars.Float("tile_alternate", 0.8f);
  return m;
}

RTmaterial CreateChullMaterial(RTcontext context, ProgramLoader& programs, const StepConfig& step) {
  RTmaterial m = CreateMaterial(context, programs, step.chull_closest_hit, step.chull_any_hit);
  Variables vars(context, m, rtMaterialDeclareVariable, "chull material");
  if (step.chull_closest_hit.function == std::string("glass_closest_hit_radiance")) {
    vars.Float("importance_cutoff", 1e-2f);
    vars.Float3("cutoff_color", 0.34f, 0.55f, 0.85f);
    vars.Float("fresnel_exponent", 3.0f);
    vars.Float("fresnel_minimum", 0.1f);
    vars.Float("fresnel_maximum", 1.0f);
    vars.Float("refraction_index", 1.4f);
    vars.Float3("refraction_color", 1.0f, 1.0f, 1.0f);
    vars.Float3("reflection_color", 1.0f, 1.0f, 1.0f);
    vars.Int("refraction_maxdepth", 100);
    vars.Int("reflection_maxdepth", 100);
    vars.Float3("extinction_constant", std::log(0.80f), std::log(0.89f), std::log(0.75f));
    vars.Float3("shadow_attenuation", 0.4f, 0.7f, 0.4f);
  } else {
    // Blue steel: Phong with shadows and a Schlick reflection (the floor's step 6 program).
    vars.Float3("Ka", 0.2f, 0.25f, 0.3f);
    vars.Float3("Kd", 0.25f, 0.35f, 0.55f);
    vars.Float3("Ks", 0.8f, 0.8f, 0.8f);
    vars.Float("phong_exp", 64);
    vars.Float3("reflectivity_n", 0.3f, 0.3f, 0.3f);
  }
  return m;
}

// One object: its own GeometryInstance, GeometryGroup and Acceleration.
RTgeometrygroup CreateObject(RTcontext context, RTgeometry geometry, RTmaterial material,
                             const char* builder) {
  RTgeometryinstance instance = nullptr;
  RT_CHECK(context, rtGeometryInstanceCreate(context, &instance));
  RT_CHECK(context, rtGeometryInstanceSetGeometry(instance, geometry));
  RT_CHECK(context, rtGeometryInstanceSetMaterialCount(instance, 1));
  RT_CHECK(context, rtGeometryInstanceSetMaterial(instance, 0, material));

  RTacceleration accel = nullptr;
  RT_CHECK(context, rtAccelerationCreate(context, &accel));
  RT_CHECK(context, rtAccelerationSetBuilder(accel, builder));
  RT_CHECK(context, rtAccelerationSetTraverser(accel, builder));

  RTgeometrygroup group = nullptr;
  RT_CHECK(context, rtGeometryGroupCreate(context, &group));
  RT_CHECK(context, rtGeometryGroupSetAcceleration(group, accel));
  RT_CHECK(context, rtGeometryGroupSetChildCount(group, 1));
  RT_CHECK(context, rtGeometryGroupSetChild(group, 0, instance));
  return group;
}

}  // namespace

void BuildScene(RTcontext context, const StepConfig& step, ProgramLoader& programs) {
  // Single-primitive objects: both a Bvh and NoAccel are valid; the scene uses both kinds.
  std::vector<RTgeometrygroup> objects;
  objects.push_back(CreateObject(context, CreateBox(context, programs),
                                 CreateBoxMaterial(context, programs, step), "Bvh"));
  objects.push_back(CreateObject(context, CreateFloor(context, programs),
                                 CreateFloorMaterial(context, programs, step), "NoAccel"));
  if (step.has_chull()) {
    objects.push_back(CreateObject(context, CreateChull(context, programs),
                                   CreateChullMaterial(context, programs, step), "Bvh"));
  }

  RTacceleration accel = nullptr;
  RT_CHECK(context, rtAccelerationCreate(context, &accel));
  RT_CHECK(context, rtAccelerationSetBuilder(accel, "Bvh"));
  RT_CHECK(context, rtAccelerationSetTraverser(accel, "Bvh"));

  RTgroup top = nullptr;
  RT_CHECK(context, rtGroupCreate(context, &top));
  RT_CHECK(context, rtGroupSetAcceleration(top, accel));
  RT_CHECK(context, rtGroupSetChildCount(top, static_cast<unsigned int>(objects.size())));
  for (unsigned int i = 0; i < objects.size(); ++i) {
    RT_CHECK(context, rtGroupSetChild(top, i, objects[i]));
  }

  Variables vars(context, context, rtContextDeclareVariable, "context");
  vars.Object("top_object", top);
  vars.Object("top_shadower", top);
}

}  // namespace tessera::tutorial
