#include "nodes.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "acceleration.h"
#include "dirty.h"
#include "program.h"
#include "status.h"

namespace tessera::api {

AcceleratedNode::AcceleratedNode(Kind kind, Context* context, uint64_t id)
    : Object(kind, context, id), acceleration_(this, 1), children_(this) {
  Touch();
}

void AcceleratedNode::SetAcceleration(Acceleration* acceleration) {
  acceleration_.Set(0, acceleration);
  Touch();
  NotifyStructureChanged(this, acceleration);
}

void AcceleratedNode::SetChildCount(unsigned count) {
  children_.Resize(count);
  Touch();
  NotifyStructureChanged(this);
}

void AcceleratedNode::SetChild(unsigned index, Object* child) {
  children_.Set(index, child);
  Touch();
  NotifyStructureChanged(this);
}

void AcceleratedNode::VisitEdges(EdgeVisitor visit) const {
  if (Object* a = acceleration_.Get(0)) visit(a, EdgeRole{"acceleration"});
  for (size_t i = 0; i < children_.size(); ++i) {
    if (Object* c = children_.Get(i)) visit(c, EdgeRole{"child", static_cast<int64_t>(i)});
  }
}

void AcceleratedNode::DropLinks() {
  acceleration_.Resize(0);
  children_.Resize(0);
}

Selector::Selector(Context* context, uint64_t id)
    : Object(Kind::kSelector, context, id), visit_(this, 1), children_(this), variables_(this) {
  Touch();
}

void Selector::SetVisitProgram(Program* program) {
  visit_.Set(0, program);
  Touch();
}

void Selector::SetChildCount(unsigned count) {
  children_.Resize(count);
  Touch();
  NotifyStructureChanged(this);
}

void Selector::SetChild(unsigned index, Object* child) {
  children_.Set(index, child);
  Touch();
  NotifyStructureChanged(this);
}

void Selector::VisitEdges(EdgeVisitor visit) const {
  if (Object* p = visit_.Get(0)) visit(p, EdgeRole{"visit program"});
  for (size_t i = 0; i < children_.size(); ++i) {
    if (Object* c = children_.Get(i)) visit(c, EdgeRole{"child", static_cast<int64_t>(i)});
  }
  variables_.VisitEdges(visit);
}

void Selector::DropLinks() {
  visit_.Resize(0);
  children_.Resize(0);
  variables_.Clear();
}

Transform::Transform(Context* context, uint64_t id)
    : Object(Kind::kTransform, context, id),
      matrix_(IdentityMatrix4()),
      inverse_(IdentityMatrix4()),
      child_(this, 1) {
  Touch();
}

namespace {
// What devices can trace: finite entries and an affine bottom row (0, 0, 0, 1). Devices move
// rays with the top three rows only, so a projective bottom row would place the geometry
// differently for traversal, for bounds and for rtTransformPoint. Entries of the bottom row may
// differ from it by rounding (an inverse the application computed): relative to the column.
absl::Status CheckAffine(const Matrix4& m, const char* what) {
  for (float v : m) {
    if (!std::isfinite(v)) {
      return RtError(RT_ERROR_INVALID_VALUE,
                     absl::StrCat(what, " has an entry that is not finite"));
    }
  }
  bool affine = std::fabs(m[15] - 1.0f) <= 1e-5f;
  for (int c = 0; c < 3; ++c) {
    const float column =
        std::fmax(std::fabs(m[c]), std::fmax(std::fabs(m[4 + c]), std::fabs(m[8 + c])));
    affine = affine && std::fabs(m[12 + c]) <= 1e-5f * column;
  }
  if (!affine) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat(what, "'s bottom row is (", m[12], ", ", m[13], ", ", m[14], ", ", m[15],
                     "); transforms must be affine, with a bottom row of "
                     "(0, 0, 0, 1) (a column-major matrix needs transpose = 1)"));
  }
  return absl::OkStatus();
}
}  // namespace

absl::Status Transform::SetMatrix(const Matrix4& matrix, const Matrix4* inverse) {
  TS_RETURN_IF_ERROR(CheckAffine(matrix, "matrix"));
  if (inverse != nullptr) TS_RETURN_IF_ERROR(CheckAffine(*inverse, "inverse matrix"));
  Matrix4 computed;
  if (inverse == nullptr) {
    if (!Invert(matrix, &computed)) {
      return RtError(RT_ERROR_INVALID_VALUE, "matrix is singular and no inverse was given");
    }
    inverse = &computed;
  }
  matrix_ = matrix;
  inverse_ = *inverse;
  Touch();
  NotifyStructureChanged(this);
  return absl::OkStatus();
}

void Transform::SetChild(Object* child) {
  child_.Set(0, child);
  Touch();
  NotifyStructureChanged(this);
}

void Transform::VisitEdges(EdgeVisitor visit) const {
  if (Object* c = child_.Get(0)) visit(c, EdgeRole{"child"});
}

}  // namespace tessera::api
