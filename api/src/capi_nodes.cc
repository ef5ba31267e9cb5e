// rtGroup*, rtGeometryGroup*, rtSelector*, rtTransform*.
#include "acceleration.h"
#include "boundary.h"
#include "geometry.h"
#include "nodes.h"
#include "program.h"
#include "scope_api.h"
#include "validate.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

constexpr const char* kNodeKinds = "a group, geometry group, transform or selector";

absl::StatusOr<Object*> NodeArg(RTobject child, Context* context) {
  return AnyArg(child, context, "child",
                {Kind::kGroup, Kind::kGeometryGroup, Kind::kTransform, Kind::kSelector},
                kNodeKinds);
}

absl::Status ChildType(Object* child, RTobjecttype* type) {
  TS_RETURN_IF_ERROR(NotNull(type, "type pointer"));
  *type = child == nullptr ? RT_OBJECTTYPE_UNKNOWN : ObjectTypeOf(child->kind());
  return absl::OkStatus();
}

template <typename T>
RTresult SetAccelerationCall(const char* fn, const void* node, RTacceleration acceleration) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Acceleration * a,
                        Arg<Acceleration>(acceleration, n.context(), "acceleration"));
    n.SetAcceleration(a);
    return absl::OkStatus();
  });
}

template <typename T>
RTresult GetAccelerationCall(const char* fn, const void* node, RTacceleration* acceleration) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(acceleration, "acceleration pointer"));
    *acceleration = ToHandle<RTacceleration>(n.acceleration());
    return absl::OkStatus();
  });
}

template <typename T>
RTresult SetChildCountCall(const char* fn, const void* node, unsigned count) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    n.SetChildCount(count);
    return absl::OkStatus();
  });
}

template <typename T>
RTresult GetChildCountCall(const char* fn, const void* node, unsigned* count) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(count, "count pointer"));
    *count = n.child_count();
    return absl::OkStatus();
  });
}

template <typename T, typename H>
RTresult GetChildCall(const char* fn, const void* node, unsigned index, H* child) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(child, "child pointer"));
    TS_RETURN_IF_ERROR(CheckIndex(index, n.child_count(), "child", "children"));
    *child = ToHandle<H>(n.child(index));
    return absl::OkStatus();
  });
}

template <typename T>
RTresult GetChildTypeCall(const char* fn, const void* node, unsigned index, RTobjecttype* type) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(type, "type pointer"));
    TS_RETURN_IF_ERROR(CheckIndex(index, n.child_count(), "child", "children"));
    return ChildType(n.child(index), type);
  });
}

// Group and Selector children: any node kind.
template <typename T>
RTresult SetNodeChildCall(const char* fn, const void* node, unsigned index, RTobject child) {
  return Call<T>(fn, node, [&](T& n) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Object * c, NodeArg(child, n.context()));
    TS_RETURN_IF_ERROR(CheckIndex(index, n.child_count(), "child", "children"));
    n.SetChild(index, c);
    return absl::OkStatus();
  });
}

}  // namespace

extern "C" {

// ---- Group
RTresult rtGroupCreate(RTcontext context, RTgroup* group) {
  return CreateCall(__func__, context, group, [](Context& c) { return c.Make<Group>(); });
}
RTresult rtGroupDestroy(RTgroup group) { return DestroyCall<Group>(__func__, group); }
RTresult rtGroupValidate(RTgroup group) {
  return Call<Group>(__func__, group, [](Group& g) { return ValidateObject(g); });
}
RTresult rtGroupGetContext(RTgroup group, RTcontext* context) {
  return GetContextCall<Group>(__func__, group, context);
}
RTresult rtGroupSetAcceleration(RTgroup group, RTacceleration acceleration) {
  return SetAccelerationCall<Group>(__func__, group, acceleration);
}
RTresult rtGroupGetAcceleration(RTgroup group, RTacceleration* acceleration) {
  return GetAccelerationCall<Group>(__func__, group, acceleration);
}
RTresult rtGroupSetChildCount(RTgroup group, unsigned int count) {
  return SetChildCountCall<Group>(__func__, group, count);
}
RTresult rtGroupGetChildCount(RTgroup group, unsigned int* count) {
  return GetChildCountCall<Group>(__func__, group, count);
}
RTresult rtGroupSetChild(RTgroup group, unsigned int index, RTobject child) {
  return SetNodeChildCall<Group>(__func__, group, index, child);
}
RTresult rtGroupGetChild(RTgroup group, unsigned int index, RTobject* child) {
  return GetChildCall<Group>(__func__, group, index, child);
}
RTresult rtGroupGetChildType(RTgroup group, unsigned int index, RTobjecttype* type) {
  return GetChildTypeCall<Group>(__func__, group, index, type);
}

// ---- GeometryGroup
RTresult rtGeometryGroupCreate(RTcontext context, RTgeometrygroup* geometrygroup) {
  return CreateCall(__func__, context, geometrygroup,
                    [](Context& c) { return c.Make<GeometryGroup>(); });
}
RTresult rtGeometryGroupDestroy(RTgeometrygroup geometrygroup) {
  return DestroyCall<GeometryGroup>(__func__, geometrygroup);
}
RTresult rtGeometryGroupValidate(RTgeometrygroup geometrygroup) {
  return Call<GeometryGroup>(__func__, geometrygroup,
                             [](GeometryGroup& g) { return ValidateObject(g); });
}
RTresult rtGeometryGroupGetContext(RTgeometrygroup geometrygroup, RTcontext* context) {
  return GetContextCall<GeometryGroup>(__func__, geometrygroup, context);
}
RTresult rtGeometryGroupSetAcceleration(RTgeometrygroup geometrygroup,
                                        RTacceleration acceleration) {
  return SetAccelerationCall<GeometryGroup>(__func__, geometrygroup, acceleration);
}
RTresult rtGeometryGroupGetAcceleration(RTgeometrygroup geometrygroup,
                                        RTacceleration* acceleration) {
  return GetAccelerationCall<GeometryGroup>(__func__, geometrygroup, acceleration);
}
RTresult rtGeometryGroupSetChildCount(RTgeometrygroup geometrygroup, unsigned int count) {
  return SetChildCountCall<GeometryGroup>(__func__, geometrygroup, count);
}
RTresult rtGeometryGroupGetChildCount(RTgeometrygroup geometrygroup, unsigned int* count) {
  return GetChildCountCall<GeometryGroup>(__func__, geometrygroup, count);
}
RTresult rtGeometryGroupSetChild(RTgeometrygroup geometrygroup, unsigned int index,
                                 RTgeometryinstance geometryinstance) {
  return Call<GeometryGroup>(__func__, geometrygroup, [&](GeometryGroup& g) -> absl::Status {
    TS_ASSIGN_OR_RETURN(GeometryInstance * gi,
                        Arg<GeometryInstance>(geometryinstance, g.context(), "child"));
    TS_RETURN_IF_ERROR(CheckIndex(index, g.child_count(), "child", "children"));
    g.SetChild(index, gi);
    return absl::OkStatus();
  });
}
RTresult rtGeometryGroupGetChild(RTgeometrygroup geometrygroup, unsigned int index,
                                 RTgeometryinstance* geometryinstance) {
  return GetChildCall<GeometryGroup>(__func__, geometrygroup, index, geometryinstance);
}

// ---- Selector
RTresult rtSelectorCreate(RTcontext context, RTselector* selector) {
  return CreateCall(__func__, context, selector, [](Context& c) { return c.Make<Selector>(); });
}
RTresult rtSelectorDestroy(RTselector selector) {
  return DestroyCall<Selector>(__func__, selector);
}
RTresult rtSelectorValidate(RTselector selector) {
  return Call<Selector>(__func__, selector, [](Selector& s) { return ValidateObject(s); });
}
RTresult rtSelectorGetContext(RTselector selector, RTcontext* context) {
  return GetContextCall<Selector>(__func__, selector, context);
}
RTresult rtSelectorSetVisitProgram(RTselector selector, RTprogram program) {
  return Call<Selector>(__func__, selector, [&](Selector& s) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Program * p, Arg<Program>(program, s.context(), "program"));
    s.SetVisitProgram(p);
    return absl::OkStatus();
  });
}
RTresult rtSelectorGetVisitProgram(RTselector selector, RTprogram* program) {
  return Call<Selector>(__func__, selector, [&](Selector& s) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(program, "program pointer"));
    *program = ToHandle<RTprogram>(s.visit_program());
    return absl::OkStatus();
  });
}
RTresult rtSelectorSetChildCount(RTselector selector, unsigned int count) {
  return SetChildCountCall<Selector>(__func__, selector, count);
}
RTresult rtSelectorGetChildCount(RTselector selector, unsigned int* count) {
  return GetChildCountCall<Selector>(__func__, selector, count);
}
RTresult rtSelectorSetChild(RTselector selector, unsigned int index, RTobject child) {
  return SetNodeChildCall<Selector>(__func__, selector, index, child);
}
RTresult rtSelectorGetChild(RTselector selector, unsigned int index, RTobject* child) {
  return GetChildCall<Selector>(__func__, selector, index, child);
}
RTresult rtSelectorGetChildType(RTselector selector, unsigned int index, RTobjecttype* type) {
  return GetChildTypeCall<Selector>(__func__, selector, index, type);
}
RTresult rtSelectorDeclareVariable(RTselector selector, const char* name, RTvariable* v) {
  return ScopeDeclare<Selector>(__func__, selector, name, v);
}
RTresult rtSelectorQueryVariable(RTselector selector, const char* name, RTvariable* v) {
  return ScopeQuery<Selector>(__func__, selector, name, v);
}
RTresult rtSelectorRemoveVariable(RTselector selector, RTvariable v) {
  return ScopeRemove<Selector>(__func__, selector, v);
}
RTresult rtSelectorGetVariableCount(RTselector selector, unsigned int* count) {
  return ScopeCount<Selector>(__func__, selector, count);
}
RTresult rtSelectorGetVariable(RTselector selector, unsigned int index, RTvariable* v) {
  return ScopeGet<Selector>(__func__, selector, index, v);
}

// ---- Transform
RTresult rtTransformCreate(RTcontext context, RTtransform* transform) {
  return CreateCall(__func__, context, transform, [](Context& c) { return c.Make<Transform>(); });
}
RTresult rtTransformDestroy(RTtransform transform) {
  return DestroyCall<Transform>(__func__, transform);
}
RTresult rtTransformValidate(RTtransform transform) {
  return Call<Transform>(__func__, transform, [](Transform& t) { return ValidateObject(t); });
}
RTresult rtTransformGetContext(RTtransform transform, RTcontext* context) {
  return GetContextCall<Transform>(__func__, transform, context);
}

RTresult rtTransformSetMatrix(RTtransform transform, int transpose, const float* matrix,
                              const float* inverse_matrix) {
  return Call<Transform>(__func__, transform, [&](Transform& t) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(matrix, "matrix"));
    Matrix4 m;
    std::copy(matrix, matrix + 16, m.begin());
    if (transpose != 0) m = Transpose(m);
    if (inverse_matrix == nullptr) return t.SetMatrix(m, nullptr);
    Matrix4 inv;
    std::copy(inverse_matrix, inverse_matrix + 16, inv.begin());
    if (transpose != 0) inv = Transpose(inv);
    return t.SetMatrix(m, &inv);
  });
}

RTresult rtTransformGetMatrix(RTtransform transform, int transpose, float* matrix,
                              float* inverse_matrix) {
  return Call<Transform>(__func__, transform, [&](Transform& t) -> absl::Status {
    if (matrix == nullptr && inverse_matrix == nullptr) {
      return RtError(RT_ERROR_INVALID_VALUE, "matrix and inverse pointers are both null");
    }
    Matrix4 m = transpose != 0 ? Transpose(t.matrix()) : t.matrix();
    Matrix4 inv = transpose != 0 ? Transpose(t.inverse()) : t.inverse();
    if (matrix != nullptr) std::copy(m.begin(), m.end(), matrix);
    if (inverse_matrix != nullptr) std::copy(inv.begin(), inv.end(), inverse_matrix);
    return absl::OkStatus();
  });
}

RTresult rtTransformSetChild(RTtransform transform, RTobject child) {
  return Call<Transform>(__func__, transform, [&](Transform& t) -> absl::Status {
    TS_ASSIGN_OR_RETURN(Object * c, NodeArg(child, t.context()));
    t.SetChild(c);
    return absl::OkStatus();
  });
}

RTresult rtTransformGetChild(RTtransform transform, RTobject* child) {
  return Call<Transform>(__func__, transform, [&](Transform& t) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(child, "child pointer"));
    *child = ToHandle<RTobject>(t.child());
    return absl::OkStatus();
  });
}

RTresult rtTransformGetChildType(RTtransform transform, RTobjecttype* type) {
  return Call<Transform>(__func__, transform,
                         [&](Transform& t) { return ChildType(t.child(), type); });
}

}  // extern "C"
