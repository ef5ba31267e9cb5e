// The traversable nodes: GeometryGroup (instances under one acceleration), Group (nodes under
// one acceleration), Selector (nodes chosen by a visit program) and Transform (one child seen
// through a matrix).
#ifndef TESSERA_API_SRC_NODES_H_
#define TESSERA_API_SRC_NODES_H_

#include "absl/status/status.h"
#include "matrix4.h"
#include "object.h"
#include "variable_scope.h"

namespace tessera::api {

class Acceleration;
class Program;

// Children plus an acceleration: the common part of GeometryGroup and Group.
class AcceleratedNode : public Object {
 public:
  Object* acceleration() const { return acceleration_.Get(0); }
  void SetAcceleration(Acceleration* acceleration);
  unsigned child_count() const { return static_cast<unsigned>(children_.size()); }
  void SetChildCount(unsigned count);
  Object* child(unsigned index) const { return children_.Get(index); }
  // The caller checks the child's kind.
  void SetChild(unsigned index, Object* child);
  void VisitEdges(EdgeVisitor visit) const override;

 protected:
  AcceleratedNode(Kind kind, Context* context, uint64_t id);

 private:
  void DropLinks() override;

  Links acceleration_;
  Links children_;
};

class GeometryGroup : public AcceleratedNode {
 public:
  static constexpr Kind kKind = Kind::kGeometryGroup;
  GeometryGroup(Context* context, uint64_t id) : AcceleratedNode(kKind, context, id) {}
};

class Group : public AcceleratedNode {
 public:
  static constexpr Kind kKind = Kind::kGroup;
  Group(Context* context, uint64_t id) : AcceleratedNode(kKind, context, id) {}
};

class Selector : public Object {
 public:
  static constexpr Kind kKind = Kind::kSelector;

  Selector(Context* context, uint64_t id);

  Object* visit_program() const { return visit_.Get(0); }
  void SetVisitProgram(Program* program);
  unsigned child_count() const { return static_cast<unsigned>(children_.size()); }
  void SetChildCount(unsigned count);
  Object* child(unsigned index) const { return children_.Get(index); }
  void SetChild(unsigned index, Object* child);

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override;

  Links visit_;
  Links children_;
  VariableScope variables_;
};

class Transform : public Object {
 public:
  static constexpr Kind kKind = Kind::kTransform;

  Transform(Context* context, uint64_t id);

  // Row-major object→world and world→object.
  const Matrix4& matrix() const { return matrix_; }
  const Matrix4& inverse() const { return inverse_; }
  // `inverse` null: computed; a singular matrix is then RT_ERROR_INVALID_VALUE.
  absl::Status SetMatrix(const Matrix4& matrix, const Matrix4* inverse);

  Object* child() const { return child_.Get(0); }
  void SetChild(Object* child);
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  void DropLinks() override { child_.Resize(0); }

  Matrix4 matrix_;
  Matrix4 inverse_;
  Links child_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_NODES_H_
