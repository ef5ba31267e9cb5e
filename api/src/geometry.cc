#include "geometry.h"

#include "dirty.h"
#include "program.h"

namespace tessera::api {

Geometry::Geometry(Context* context, uint64_t id) : Geometry(Kind::kGeometry, context, id) {}

Geometry::Geometry(Kind kind, Context* context, uint64_t id)
    : Object(kind, context, id), programs_(this, 2), variables_(this) {
  Touch();
}

void Geometry::SetPrimitiveCount(unsigned count) {
  primitive_count_ = count;
  primitive_count_set_ = true;
  Touch();
  NotifyStructureChanged(this);
}

void Geometry::SetIntersectionProgram(Program* program) {
  programs_.Set(0, program);
  Touch();
  NotifyStructureChanged(this);
}

void Geometry::SetBoundingBoxProgram(Program* program) {
  programs_.Set(1, program);
  Touch();
  NotifyStructureChanged(this);
}

void Geometry::MarkDirty() {
  dirty_ = true;
  NotifyStructureChanged(this);
}

void Geometry::VisitEdges(EdgeVisitor visit) const {
  if (Object* p = programs_.Get(0)) visit(p, EdgeRole{"intersection program"});
  if (Object* p = programs_.Get(1)) visit(p, EdgeRole{"bounding box program"});
  variables_.VisitEdges(visit);
}

void Geometry::DropLinks() {
  programs_.Resize(0);
  variables_.Clear();
}

GeometryTriangles::GeometryTriangles(Context* context, uint64_t id)
    : Geometry(Kind::kGeometryTriangles, context, id), buffers_(this, 3), attribute_(this, 1) {}

void GeometryTriangles::Changed() {
  Touch();
  NotifyStructureChanged(this);
}

void GeometryTriangles::SetVertices(unsigned count, Object* buffer, const Array& where) {
  vertex_count_ = count;
  buffers_.Set(0, buffer);
  vertices_ = where;
  Changed();
}

void GeometryTriangles::SetIndices(Object* buffer, const Array& where) {
  buffers_.Set(1, buffer);
  indices_ = where;
  Changed();
}

void GeometryTriangles::SetMaterialIndices(Object* buffer, const Array& where) {
  buffers_.Set(2, buffer);
  material_indices_ = where;
  Changed();
}

void GeometryTriangles::SetAttributeProgram(Program* program) {
  attribute_.Set(0, program);
  Changed();
}

void GeometryTriangles::SetPrimitiveIndexOffset(unsigned offset) {
  primitive_index_offset_ = offset;
  Changed();
}

void GeometryTriangles::SetMaterialCount(unsigned count) {
  material_count_ = count;
  Changed();
}

void GeometryTriangles::VisitEdges(EdgeVisitor visit) const {
  static const char* const kRoles[] = {"vertex buffer", "index buffer", "material index buffer"};
  for (size_t i = 0; i < 3; ++i) {
    if (Object* b = buffers_.Get(i)) visit(b, EdgeRole{kRoles[i]});
  }
  if (Object* p = attribute_.Get(0)) visit(p, EdgeRole{"attribute program"});
  Geometry::VisitEdges(visit);
}

void GeometryTriangles::DropLinks() {
  buffers_.Resize(0);
  attribute_.Resize(0);
  Geometry::DropLinks();
}

Material::Material(Context* context, uint64_t id)
    : Object(Kind::kMaterial, context, id), closest_hit_(this), any_hit_(this), variables_(this) {
  Touch();
}

void Material::SetClosestHit(unsigned ray_type, Program* program) {
  if (closest_hit_.size() <= ray_type) closest_hit_.Resize(ray_type + 1);
  closest_hit_.Set(ray_type, program);
  Touch();
}

void Material::SetAnyHit(unsigned ray_type, Program* program) {
  if (any_hit_.size() <= ray_type) any_hit_.Resize(ray_type + 1);
  any_hit_.Set(ray_type, program);
  Touch();
}

void Material::VisitEdges(EdgeVisitor visit) const {
  for (size_t i = 0; i < closest_hit_.size(); ++i) {
    if (Object* p = closest_hit_.Get(i)) {
      visit(p, EdgeRole{"closest hit program for ray type", static_cast<int64_t>(i)});
    }
  }
  for (size_t i = 0; i < any_hit_.size(); ++i) {
    if (Object* p = any_hit_.Get(i)) {
      visit(p, EdgeRole{"any hit program for ray type", static_cast<int64_t>(i)});
    }
  }
  variables_.VisitEdges(visit);
}

void Material::DropLinks() {
  closest_hit_.Resize(0);
  any_hit_.Resize(0);
  variables_.Clear();
}

GeometryInstance::GeometryInstance(Context* context, uint64_t id)
    : Object(Kind::kGeometryInstance, context, id),
      geometry_(this, 1),
      materials_(this),
      variables_(this) {
  Touch();
}

void GeometryInstance::SetGeometry(Geometry* geometry) {
  geometry_.Set(0, geometry);
  Touch();
  NotifyStructureChanged(this);
}

void GeometryInstance::SetMaterialCount(unsigned count) {
  materials_.Resize(count);
  Touch();
}

void GeometryInstance::SetMaterial(unsigned index, Material* material) {
  materials_.Set(index, material);
  Touch();
}

void GeometryInstance::VisitEdges(EdgeVisitor visit) const {
  if (Object* g = geometry_.Get(0)) visit(g, EdgeRole{"geometry"});
  for (size_t i = 0; i < materials_.size(); ++i) {
    if (Object* m = materials_.Get(i)) visit(m, EdgeRole{"material", static_cast<int64_t>(i)});
  }
  variables_.VisitEdges(visit);
}

void GeometryInstance::DropLinks() {
  geometry_.Resize(0);
  materials_.Resize(0);
  variables_.Clear();
}

}  // namespace tessera::api
