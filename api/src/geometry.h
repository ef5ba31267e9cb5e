// Geometry, Material and GeometryInstance: the leaves of the node graph, where primitives meet
// the programs that intersect and shade them.
#ifndef TESSERA_API_SRC_GEOMETRY_H_
#define TESSERA_API_SRC_GEOMETRY_H_

#include "object.h"
#include "variable_scope.h"

namespace tessera::api {

class Program;

class Geometry : public Object {
 public:
  static constexpr Kind kKind = Kind::kGeometry;

  Geometry(Context* context, uint64_t id);
  // Built-in triangles (GeometryTriangles) or a geometry with programs.
  static bool Is(const Object* o) {
    return o != nullptr && (o->kind() == Kind::kGeometry || o->kind() == Kind::kGeometryTriangles);
  }

  unsigned primitive_count() const { return primitive_count_; }
  bool primitive_count_set() const { return primitive_count_set_; }
  void SetPrimitiveCount(unsigned count);
  Object* intersection_program() const { return programs_.Get(0); }
  Object* bounding_box_program() const { return programs_.Get(1); }
  void SetIntersectionProgram(Program* program);
  void SetBoundingBoxProgram(Program* program);

  // rtGeometryMarkDirty: accelerations above rebuild; cleared when a launch ships it.
  bool dirty() const { return dirty_; }
  void MarkDirty();
  void ClearDirty() { dirty_ = false; }

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override;

 protected:
  Geometry(Kind kind, Context* context, uint64_t id);
  void DropLinks() override;

 private:
  unsigned primitive_count_ = 0;
  bool primitive_count_set_ = false;
  Links programs_;  // [0] intersection, [1] bounding box
  VariableScope variables_;
  bool dirty_ = true;
};

// OptiX 6 GeometryTriangles: triangles Embree intersects itself, from a vertex buffer and an
// optional index buffer, with an optional attribute program in place of an intersection program.
class GeometryTriangles : public Geometry {
 public:
  static constexpr Kind kKind = Kind::kGeometryTriangles;

  // Where an array of elements lies in a buffer. `buffer` is null until set.
  struct Array {
    uint64_t offset = 0, stride = 0;
    RTformat format = RT_FORMAT_UNKNOWN;
    uint64_t element_bytes = 0;  // of `format`
  };

  GeometryTriangles(Context* context, uint64_t id);

  Object* vertex_buffer() const { return buffers_.Get(0); }
  Object* index_buffer() const { return buffers_.Get(1); }
  Object* material_index_buffer() const { return buffers_.Get(2); }
  Object* attribute_program() const { return attribute_.Get(0); }
  unsigned vertex_count() const { return vertex_count_; }
  const Array& vertices() const { return vertices_; }
  const Array& indices() const { return indices_; }
  const Array& material_indices() const { return material_indices_; }
  unsigned primitive_index_offset() const { return primitive_index_offset_; }
  unsigned material_count() const { return material_count_; }

  void SetVertices(unsigned count, Object* buffer, const Array& where);
  void SetIndices(Object* buffer, const Array& where);
  void SetMaterialIndices(Object* buffer, const Array& where);
  void SetAttributeProgram(Program* program);
  void SetPrimitiveIndexOffset(unsigned offset);
  void SetMaterialCount(unsigned count);

  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override;
  void Changed();

  Links buffers_;    // [0] vertices, [1] indices, [2] material indices
  Links attribute_;  // [0] attribute program
  unsigned vertex_count_ = 0;
  Array vertices_, indices_, material_indices_;
  unsigned primitive_index_offset_ = 0;
  unsigned material_count_ = 1;
};

class Material : public Object {
 public:
  static constexpr Kind kKind = Kind::kMaterial;

  Material(Context* context, uint64_t id);

  // Per ray type; null when unset. The caller checks `ray_type` against the context.
  Object* closest_hit(unsigned ray_type) const { return closest_hit_.Get(ray_type); }
  Object* any_hit(unsigned ray_type) const { return any_hit_.Get(ray_type); }
  void SetClosestHit(unsigned ray_type, Program* program);
  void SetAnyHit(unsigned ray_type, Program* program);

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override;

  Links closest_hit_;
  Links any_hit_;
  VariableScope variables_;
};

class GeometryInstance : public Object {
 public:
  static constexpr Kind kKind = Kind::kGeometryInstance;

  GeometryInstance(Context* context, uint64_t id);

  Object* geometry() const { return geometry_.Get(0); }
  void SetGeometry(Geometry* geometry);  // a Geometry or GeometryTriangles
  unsigned material_count() const { return static_cast<unsigned>(materials_.size()); }
  void SetMaterialCount(unsigned count);
  Object* material(unsigned index) const { return materials_.Get(index); }
  void SetMaterial(unsigned index, Material* material);

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override;

  Links geometry_;
  Links materials_;
  VariableScope variables_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_GEOMETRY_H_
