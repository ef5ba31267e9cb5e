// rtGeometry*, rtMaterial*, rtGeometryInstance*.
#include "boundary.h"
#include "geometry.h"
#include "program.h"
#include "scope_api.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

template <typename H>
absl::Status GetProgram(Object* program, H* out) {
  TS_RETURN_IF_ERROR(NotNull(out, "program pointer"));
  *out = ToHandle<H>(program);
  return absl::OkStatus();
}

}  // namespace

extern "C" {

// ---- Geometry
RTresult rtGeometryCreate(RTcontext context, RTgeometry* geometry) {
  return CreateCall(__func__, context, geometry, [](Context& c) { return c.Make<Geometry>(); });
}
RTresult rtGeometryDestroy(RTgeometry geometry) {
  return DestroyCall<Geometry>(__func__, geometry);
}
RTresult rtGeometryValidate(RTgeometry geometry) {
  return Call<Geometry>(__func__, geometry, [](Geometry& g) { return ValidateObject(g); });
}
RTresult rtGeometryGetContext(RTgeometry geometry, RTcontext* context) {
  return GetContextCall<Geometry>(__func__, geometry, context);
}

RTresult rtGeometrySetPrimitiveCount(RTgeometry geometry, unsigned int num_primitives) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    g.SetPrimitiveCount(num_primitives);
    return absl::OkStatus();
  });
}

RTresult rtGeometryGetPrimitiveCount(RTgeometry geometry, unsigned int* num_primitives) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(num_primitives, "count pointer"));
    *num_primitives = g.primitive_count();
    return absl::OkStatus();
  });
}

RTresult rtGeometrySetBoundingBoxProgram(RTgeometry geometry, RTprogram program) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, g.context(), "program"));
    g.SetBoundingBoxProgram(p);
    return absl::OkStatus();
  });
}

RTresult rtGeometryGetBoundingBoxProgram(RTgeometry geometry, RTprogram* program) {
  return Call<Geometry>(__func__, geometry,
                        [&](Geometry& g) { return GetProgram(g.bounding_box_program(), program); });
}

RTresult rtGeometrySetIntersectionProgram(RTgeometry geometry, RTprogram program) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, g.context(), "program"));
    g.SetIntersectionProgram(p);
    return absl::OkStatus();
  });
}

RTresult rtGeometryGetIntersectionProgram(RTgeometry geometry, RTprogram* program) {
  return Call<Geometry>(__func__, geometry,
                        [&](Geometry& g) { return GetProgram(g.intersection_program(), program); });
}

RTresult rtGeometryMarkDirty(RTgeometry geometry) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    g.MarkDirty();
    return absl::OkStatus();
  });
}

RTresult rtGeometryIsDirty(RTgeometry geometry, int* dirty) {
  return Call<Geometry>(__func__, geometry, [&](Geometry& g) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(dirty, "dirty pointer"));
    *dirty = g.dirty() ? 1 : 0;
    return absl::OkStatus();
  });
}

RTresult rtGeometryDeclareVariable(RTgeometry geometry, const char* name, RTvariable* v) {
  return ScopeDeclare<Geometry>(__func__, geometry, name, v);
}
RTresult rtGeometryQueryVariable(RTgeometry geometry, const char* name, RTvariable* v) {
  return ScopeQuery<Geometry>(__func__, geometry, name, v);
}
RTresult rtGeometryRemoveVariable(RTgeometry geometry, RTvariable v) {
  return ScopeRemove<Geometry>(__func__, geometry, v);
}
RTresult rtGeometryGetVariableCount(RTgeometry geometry, unsigned int* count) {
  return ScopeCount<Geometry>(__func__, geometry, count);
}
RTresult rtGeometryGetVariable(RTgeometry geometry, unsigned int index, RTvariable* v) {
  return ScopeGet<Geometry>(__func__, geometry, index, v);
}

// ---- Material
RTresult rtMaterialCreate(RTcontext context, RTmaterial* material) {
  return CreateCall(__func__, context, material, [](Context& c) { return c.Make<Material>(); });
}
RTresult rtMaterialDestroy(RTmaterial material) {
  return DestroyCall<Material>(__func__, material);
}
RTresult rtMaterialValidate(RTmaterial material) {
  return Call<Material>(__func__, material, [](Material& m) { return ValidateObject(m); });
}
RTresult rtMaterialGetContext(RTmaterial material, RTcontext* context) {
  return GetContextCall<Material>(__func__, material, context);
}

RTresult rtMaterialSetClosestHitProgram(RTmaterial material, unsigned int ray_type_index,
                                        RTprogram program) {
  return Call<Material>(__func__, material, [&](Material& m) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, m.context(), "program"));
    TS_RETURN_IF_ERROR(
        CheckIndex(ray_type_index, m.context()->ray_type_count(), "ray type", "ray types"));
    m.SetClosestHit(ray_type_index, p);
    return absl::OkStatus();
  });
}

RTresult rtMaterialGetClosestHitProgram(RTmaterial material, unsigned int ray_type_index,
                                        RTprogram* program) {
  return Call<Material>(__func__, material, [&](Material& m) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_RETURN_IF_ERROR(
        CheckIndex(ray_type_index, m.context()->ray_type_count(), "ray type", "ray types"));
    *program = ToHandle<RTprogram>(m.closest_hit(ray_type_index));
    return absl::OkStatus();
  });
}

RTresult rtMaterialSetAnyHitProgram(RTmaterial material, unsigned int ray_type_index,
                                    RTprogram program) {
  return Call<Material>(__func__, material, [&](Material& m) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, m.context(), "program"));
    TS_RETURN_IF_ERROR(
        CheckIndex(ray_type_index, m.context()->ray_type_count(), "ray type", "ray types"));
    m.SetAnyHit(ray_type_index, p);
    return absl::OkStatus();
  });
}

RTresult rtMaterialGetAnyHitProgram(RTmaterial material, unsigned int ray_type_index,
                                    RTprogram* program) {
  return Call<Material>(__func__, material, [&](Material& m) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    TS_RETURN_IF_ERROR(
        CheckIndex(ray_type_index, m.context()->ray_type_count(), "ray type", "ray types"));
    *program = ToHandle<RTprogram>(m.any_hit(ray_type_index));
    return absl::OkStatus();
  });
}

RTresult rtMaterialDeclareVariable(RTmaterial material, const char* name, RTvariable* v) {
  return ScopeDeclare<Material>(__func__, material, name, v);
}
RTresult rtMaterialQueryVariable(RTmaterial material, const char* name, RTvariable* v) {
  return ScopeQuery<Material>(__func__, material, name, v);
}
RTresult rtMaterialRemoveVariable(RTmaterial material, RTvariable v) {
  return ScopeRemove<Material>(__func__, material, v);
}
RTresult rtMaterialGetVariableCount(RTmaterial material, unsigned int* count) {
  return ScopeCount<Material>(__func__, material, count);
}
RTresult rtMaterialGetVariable(RTmaterial material, unsigned int index, RTvariable* v) {
  return ScopeGet<Material>(__func__, material, index, v);
}

// ---- GeometryInstance
RTresult rtGeometryInstanceCreate(RTcontext context, RTgeometryinstance* geometryinstance) {
  return CreateCall(__func__, context, geometryinstance,
                    [](Context& c) { return c.Make<GeometryInstance>(); });
}
RTresult rtGeometryInstanceDestroy(RTgeometryinstance geometryinstance) {
  return DestroyCall<GeometryInstance>(__func__, geometryinstance);
}
RTresult rtGeometryInstanceValidate(RTgeometryinstance geometryinstance) {
  return Call<GeometryInstance>(__func__, geometryinstance,
                                [](GeometryInstance& gi) { return ValidateObject(gi); });
}
RTresult rtGeometryInstanceGetContext(RTgeometryinstance geometryinstance, RTcontext* context) {
  return GetContextCall<GeometryInstance>(__func__, geometryinstance, context);
}

RTresult rtGeometryInstanceSetGeometry(RTgeometryinstance geometryinstance, RTgeometry geometry) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_ASSIGN_OR_RETURN(Geometry * g, Arg<Geometry>(geometry, gi.context(), "geometry"));
        gi.SetGeometry(g);
        return absl::OkStatus();
      });
}

RTresult rtGeometryInstanceGetGeometry(RTgeometryinstance geometryinstance, RTgeometry* geometry) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_RETURN_IF_ERROR(NotNull(geometry, "geometry pointer"));
        Object* g = gi.geometry();
        // GeometryTriangles come back through
        // rtGeometryInstanceGetGeometryTriangles.
        *geometry =
            g != nullptr && g->kind() == Kind::kGeometry ? ToHandle<RTgeometry>(g) : nullptr;
        return absl::OkStatus();
      });
}

RTresult rtGeometryInstanceSetMaterialCount(RTgeometryinstance geometryinstance,
                                            unsigned int count) {
  return Call<GeometryInstance>(__func__, geometryinstance,
                                [&](GeometryInstance& gi) -> absl::Status {
                                  gi.SetMaterialCount(count);
                                  return absl::OkStatus();
                                });
}

RTresult rtGeometryInstanceGetMaterialCount(RTgeometryinstance geometryinstance,
                                            unsigned int* count) {
  return Call<GeometryInstance>(__func__, geometryinstance,
                                [&](GeometryInstance& gi) -> absl::Status {
                                  TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
                                  *count = gi.material_count();
                                  return absl::OkStatus();
                                });
}

RTresult rtGeometryInstanceSetMaterial(RTgeometryinstance geometryinstance, unsigned int index,
                                       RTmaterial material) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_ASSIGN_OR_RETURN(Material * m, Arg<Material>(material, gi.context(), "material"));
        TS_RETURN_IF_ERROR(CheckIndex(index, gi.material_count(), "material", "materials"));
        gi.SetMaterial(index, m);
        return absl::OkStatus();
      });
}

RTresult rtGeometryInstanceGetMaterial(RTgeometryinstance geometryinstance, unsigned int index,
                                       RTmaterial* material) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_RETURN_IF_ERROR(NotNull(material, "material pointer"));
        TS_RETURN_IF_ERROR(CheckIndex(index, gi.material_count(), "material", "materials"));
        *material = ToHandle<RTmaterial>(gi.material(index));
        return absl::OkStatus();
      });
}

RTresult rtGeometryInstanceDeclareVariable(RTgeometryinstance geometryinstance, const char* name,
                                           RTvariable* v) {
  return ScopeDeclare<GeometryInstance>(__func__, geometryinstance, name, v);
}
RTresult rtGeometryInstanceQueryVariable(RTgeometryinstance geometryinstance, const char* name,
                                         RTvariable* v) {
  return ScopeQuery<GeometryInstance>(__func__, geometryinstance, name, v);
}
RTresult rtGeometryInstanceRemoveVariable(RTgeometryinstance geometryinstance, RTvariable v) {
  return ScopeRemove<GeometryInstance>(__func__, geometryinstance, v);
}
RTresult rtGeometryInstanceGetVariableCount(RTgeometryinstance geometryinstance,
                                            unsigned int* count) {
  return ScopeCount<GeometryInstance>(__func__, geometryinstance, count);
}
RTresult rtGeometryInstanceGetVariable(RTgeometryinstance geometryinstance, unsigned int index,
                                       RTvariable* v) {
  return ScopeGet<GeometryInstance>(__func__, geometryinstance, index, v);
}

}  // extern "C"
