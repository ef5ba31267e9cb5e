// rtGeometryTriangles* (OptiX 6): built-in triangles, and rtGeometryInstance*GeometryTriangles.
#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "buffer.h"
#include "geometry.h"
#include "program.h"
#include "scope_api.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

// Bytes of one element of `format` among the formats `allowed` (with their sizes); 0 otherwise.
size_t AllowedBytes(RTformat format, std::initializer_list<std::pair<RTformat, size_t>> allowed) {
  for (const auto& [f, bytes] : allowed) {
    if (f == format) return bytes;
  }
  return 0;
}

// Where an array lies: `stride` 0 means packed; a stride smaller than an element overlaps them.
absl::StatusOr<GeometryTriangles::Array> ArrayOf(
    RTsize offset, RTsize stride, RTformat format, const char* what, const char* formats,
    std::initializer_list<std::pair<RTformat, size_t>> allowed) {
  const size_t bytes = AllowedBytes(format, allowed);
  if (bytes == 0) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat(what, " format ", static_cast<int>(format), " is not ", formats));
  }
  if (stride != 0 && stride < bytes) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat(what, " stride ", stride, " is less than an element (", bytes, " bytes)"));
  }
  return GeometryTriangles::Array{offset, stride == 0 ? bytes : stride, format, bytes};
}

}  // namespace

extern "C" {

RTresult rtGeometryTrianglesCreate(RTcontext context, RTgeometrytriangles* geometrytriangles) {
  return CreateCall(__func__, context, geometrytriangles,
                    [](Context& c) { return c.Make<GeometryTriangles>(); });
}
RTresult rtGeometryTrianglesDestroy(RTgeometrytriangles geometrytriangles) {
  return DestroyCall<GeometryTriangles>(__func__, geometrytriangles);
}
RTresult rtGeometryTrianglesValidate(RTgeometrytriangles geometrytriangles) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [](GeometryTriangles& g) { return ValidateObject(g); });
}
RTresult rtGeometryTrianglesGetContext(RTgeometrytriangles geometrytriangles, RTcontext* context) {
  return GetContextCall<GeometryTriangles>(__func__, geometrytriangles, context);
}

RTresult rtGeometryTrianglesSetBuildFlags(RTgeometrytriangles geometrytriangles,
                                          RTgeometrybuildflags build_flags) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles&) -> absl::Status {
        const unsigned bits = static_cast<unsigned>(build_flags);
        if ((bits & ~unsigned{RT_GEOMETRY_BUILD_FLAG_RELEASE_BUFFERS}) != 0) {
          return RtError(RT_ERROR_INVALID_VALUE,
                         absl::StrCat("build flags 0x", absl::Hex(bits),
                                      " hold bits OptiX 6 does not define (RT_GEOMETRY_BUILD_FLAG_"
                                      "NONE 0x0, RELEASE_BUFFERS 0x10)"));
        }
        return absl::OkStatus();  // buffers are kept either way (rt.h)
      });
}
RTresult rtGeometryTrianglesSetPrimitiveIndexOffset(RTgeometrytriangles geometrytriangles,
                                                    unsigned int index_offset) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   g.SetPrimitiveIndexOffset(index_offset);
                                   return absl::OkStatus();
                                 });
}
RTresult rtGeometryTrianglesGetPrimitiveIndexOffset(RTgeometrytriangles geometrytriangles,
                                                    unsigned int* index_offset) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   TS_RETURN_IF_ERROR(NotNull(index_offset, "offset pointer"));
                                   *index_offset = g.primitive_index_offset();
                                   return absl::OkStatus();
                                 });
}

RTresult rtGeometryTrianglesSetPrimitiveCount(RTgeometrytriangles geometrytriangles,
                                              unsigned int num_triangles) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   g.SetPrimitiveCount(num_triangles);
                                   return absl::OkStatus();
                                 });
}
RTresult rtGeometryTrianglesGetPrimitiveCount(RTgeometrytriangles geometrytriangles,
                                              unsigned int* num_triangles) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   TS_RETURN_IF_ERROR(NotNull(num_triangles, "count pointer"));
                                   *num_triangles = g.primitive_count();
                                   return absl::OkStatus();
                                 });
}

RTresult rtGeometryTrianglesSetTriangleIndices(RTgeometrytriangles geometrytriangles,
                                               RTbuffer index_buffer,
                                               RTsize index_buffer_byte_offset,
                                               RTsize tri_indices_byte_stride,
                                               RTformat tri_indices_format) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles& g) -> absl::Status {
        TS_ASSIGN_OR_RETURN(Buffer * b, Arg<Buffer>(index_buffer, g.context(), "index buffer"));
        TS_ASSIGN_OR_RETURN(
            GeometryTriangles::Array where,
            ArrayOf(index_buffer_byte_offset, tri_indices_byte_stride, tri_indices_format,
                    "triangle index", "RT_FORMAT_UNSIGNED_INT3 or RT_FORMAT_UNSIGNED_SHORT3",
                    {{RT_FORMAT_UNSIGNED_INT3, 12}, {RT_FORMAT_UNSIGNED_SHORT3, 6}}));
        g.SetIndices(b, where);
        return absl::OkStatus();
      });
}

RTresult rtGeometryTrianglesSetVertices(RTgeometrytriangles geometrytriangles,
                                        unsigned int num_vertices, RTbuffer vertex_buffer,
                                        RTsize vertex_buffer_byte_offset, RTsize vertex_byte_stride,
                                        RTformat position_format) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles& g) -> absl::Status {
        TS_ASSIGN_OR_RETURN(Buffer * b, Arg<Buffer>(vertex_buffer, g.context(), "vertex buffer"));
        TS_ASSIGN_OR_RETURN(GeometryTriangles::Array where,
                            ArrayOf(vertex_buffer_byte_offset, vertex_byte_stride, position_format,
                                    "vertex", "RT_FORMAT_FLOAT3 or RT_FORMAT_FLOAT2",
                                    {{RT_FORMAT_FLOAT3, 12}, {RT_FORMAT_FLOAT2, 8}}));
        g.SetVertices(num_vertices, b, where);
        return absl::OkStatus();
      });
}

RTresult rtGeometryTrianglesSetAttributeProgram(RTgeometrytriangles geometrytriangles,
                                                RTprogram program) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles& g) -> absl::Status {
        TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, g.context(), "program"));
        g.SetAttributeProgram(p);
        return absl::OkStatus();
      });
}
RTresult rtGeometryTrianglesGetAttributeProgram(RTgeometrytriangles geometrytriangles,
                                                RTprogram* program) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
                                   *program = ToHandle<RTprogram>(g.attribute_program());
                                   return absl::OkStatus();
                                 });
}

RTresult rtGeometryTrianglesSetMaterialCount(RTgeometrytriangles geometrytriangles,
                                             unsigned int num_materials) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles& g) -> absl::Status {
        if (num_materials == 0) {
          return RtError(RT_ERROR_INVALID_VALUE, "material count 0: triangles need a material");
        }
        g.SetMaterialCount(num_materials);
        return absl::OkStatus();
      });
}
RTresult rtGeometryTrianglesGetMaterialCount(RTgeometrytriangles geometrytriangles,
                                             unsigned int* num_materials) {
  return Call<GeometryTriangles>(__func__, geometrytriangles,
                                 [&](GeometryTriangles& g) -> absl::Status {
                                   TS_RETURN_IF_ERROR(NotNull(num_materials, "count pointer"));
                                   *num_materials = g.material_count();
                                   return absl::OkStatus();
                                 });
}

RTresult rtGeometryTrianglesSetMaterialIndices(RTgeometrytriangles geometrytriangles,
                                               RTbuffer material_index_buffer,
                                               RTsize material_index_buffer_byte_offset,
                                               RTsize material_index_byte_stride,
                                               RTformat material_index_format) {
  return Call<GeometryTriangles>(
      __func__, geometrytriangles, [&](GeometryTriangles& g) -> absl::Status {
        TS_ASSIGN_OR_RETURN(
            Buffer * b, Arg<Buffer>(material_index_buffer, g.context(), "material index buffer"));
        TS_ASSIGN_OR_RETURN(
            GeometryTriangles::Array where,
            ArrayOf(material_index_buffer_byte_offset, material_index_byte_stride,
                    material_index_format, "material index",
                    "RT_FORMAT_UNSIGNED_BYTE, RT_FORMAT_UNSIGNED_SHORT or RT_FORMAT_UNSIGNED_INT",
                    {{RT_FORMAT_UNSIGNED_BYTE, 1},
                     {RT_FORMAT_UNSIGNED_SHORT, 2},
                     {RT_FORMAT_UNSIGNED_INT, 4}}));
        g.SetMaterialIndices(b, where);
        return absl::OkStatus();
      });
}

RTresult rtGeometryTrianglesDeclareVariable(RTgeometrytriangles geometrytriangles, const char* name,
                                            RTvariable* v) {
  return ScopeDeclare<GeometryTriangles>(__func__, geometrytriangles, name, v);
}
RTresult rtGeometryTrianglesQueryVariable(RTgeometrytriangles geometrytriangles, const char* name,
                                          RTvariable* v) {
  return ScopeQuery<GeometryTriangles>(__func__, geometrytriangles, name, v);
}
RTresult rtGeometryTrianglesRemoveVariable(RTgeometrytriangles geometrytriangles, RTvariable v) {
  return ScopeRemove<GeometryTriangles>(__func__, geometrytriangles, v);
}
RTresult rtGeometryTrianglesGetVariableCount(RTgeometrytriangles geometrytriangles,
                                             unsigned int* count) {
  return ScopeCount<GeometryTriangles>(__func__, geometrytriangles, count);
}
RTresult rtGeometryTrianglesGetVariable(RTgeometrytriangles geometrytriangles, unsigned int index,
                                        RTvariable* v) {
  return ScopeGet<GeometryTriangles>(__func__, geometrytriangles, index, v);
}

RTresult rtGeometryInstanceSetGeometryTriangles(RTgeometryinstance geometryinstance,
                                                RTgeometrytriangles geometrytriangles) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_ASSIGN_OR_RETURN(
            GeometryTriangles * g,
            Arg<GeometryTriangles>(geometrytriangles, gi.context(), "geometry triangles"));
        gi.SetGeometry(g);
        return absl::OkStatus();
      });
}

RTresult rtGeometryInstanceGetGeometryTriangles(RTgeometryinstance geometryinstance,
                                                RTgeometrytriangles* geometrytriangles) {
  return Call<GeometryInstance>(
      __func__, geometryinstance, [&](GeometryInstance& gi) -> absl::Status {
        TS_RETURN_IF_ERROR(NotNull(geometrytriangles, "geometry triangles pointer"));
        Object* g = gi.geometry();
        *geometrytriangles = g != nullptr && g->kind() == Kind::kGeometryTriangles
                                 ? ToHandle<RTgeometrytriangles>(g)
                                 : nullptr;
        return absl::OkStatus();
      });
}

}  // extern "C"
