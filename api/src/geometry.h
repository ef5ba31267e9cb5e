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

 private:
  void DropLinks() override;

  unsigned primitive_count_ = 0;
  bool primitive_count_set_ = false;
  Links programs_;  // [0] intersection, [1] bounding box
  VariableScope variables_;
  bool dirty_ = true;
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
  void SetGeometry(Geometry* geometry);
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
