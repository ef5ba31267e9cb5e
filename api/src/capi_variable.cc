// rtVariable*: typed set/get of values, objects and user data.
#include <array>

#include "boundary.h"
#include "variable.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

template <typename T, size_t N>
RTresult SetValues(const char* fn, RTvariable v, RTobjecttype type, const T* values) {
  return Call<Variable>(fn, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(values, "value pointer"));
    return var.SetPlain(type, values, sizeof(T) * N);
  });
}

template <typename T, size_t N>
RTresult GetValues(const char* fn, RTvariable v, RTobjecttype type, T* values) {
  return Call<Variable>(fn, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(values, "value pointer"));
    return var.GetPlain(type, values, sizeof(T) * N);
  });
}

// Scalar-output forms (rtVariableGet3f(v, &x, &y, &z)): every pointer must be non-null.
template <typename T, size_t N>
RTresult GetScattered(const char* fn, RTvariable v, RTobjecttype type,
                      const std::array<T*, N>& outs) {
  return Call<Variable>(fn, v, [&](Variable& var) -> absl::Status {
    for (T* out : outs) TS_RETURN_IF_ERROR(NotNull(out, "value pointer"));
    T values[N];
    TS_RETURN_IF_ERROR(var.GetPlain(type, values, sizeof(values)));
    for (size_t i = 0; i < N; ++i) *outs[i] = values[i];
    return absl::OkStatus();
  });
}

// Matrices are stored row-major (rows x cols); `transpose` means `m` is column-major.
template <int R, int C>
RTresult SetMatrix(const char* fn, RTvariable v, int transpose, const float* m) {
  return Call<Variable>(fn, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(m, "matrix pointer"));
    float rows[R * C];
    for (int r = 0; r < R; ++r) {
      for (int c = 0; c < C; ++c) rows[r * C + c] = transpose != 0 ? m[c * R + r] : m[r * C + c];
    }
    return var.SetPlain(MatrixType(R, C), rows, sizeof(rows));
  });
}

template <int R, int C>
RTresult GetMatrix(const char* fn, RTvariable v, int transpose, float* m) {
  return Call<Variable>(fn, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(m, "matrix pointer"));
    float rows[R * C];
    TS_RETURN_IF_ERROR(var.GetPlain(MatrixType(R, C), rows, sizeof(rows)));
    for (int r = 0; r < R; ++r) {
      for (int c = 0; c < C; ++c) (transpose != 0 ? m[c * R + r] : m[r * C + c]) = rows[r * C + c];
    }
    return absl::OkStatus();
  });
}

}  // namespace

#define TS_SET_SCALARS(suffix, T, type_fn, N, ...)                      \
  RTresult rtVariableSet##N##suffix(RTvariable v, TS_PARAMS_##N(T)) {   \
    const T values[N] = {__VA_ARGS__};                                  \
    return SetValues<T, N>(__func__, v, type_fn(N), values);            \
  }                                                                     \
  RTresult rtVariableSet##N##suffix##v(RTvariable v, const T* values) { \
    return SetValues<T, N>(__func__, v, type_fn(N), values);            \
  }                                                                     \
  RTresult rtVariableGet##N##suffix##v(RTvariable v, T* values) {       \
    return GetValues<T, N>(__func__, v, type_fn(N), values);            \
  }

#define TS_PARAMS_1(T) T a1
#define TS_PARAMS_2(T) T a1, T a2
#define TS_PARAMS_3(T) T a1, T a2, T a3
#define TS_PARAMS_4(T) T a1, T a2, T a3, T a4

extern "C" {

TS_SET_SCALARS(f, float, FloatType, 1, a1)
TS_SET_SCALARS(f, float, FloatType, 2, a1, a2)
TS_SET_SCALARS(f, float, FloatType, 3, a1, a2, a3)
TS_SET_SCALARS(f, float, FloatType, 4, a1, a2, a3, a4)
TS_SET_SCALARS(i, int, IntType, 1, a1)
TS_SET_SCALARS(i, int, IntType, 2, a1, a2)
TS_SET_SCALARS(i, int, IntType, 3, a1, a2, a3)
TS_SET_SCALARS(i, int, IntType, 4, a1, a2, a3, a4)
TS_SET_SCALARS(ui, unsigned int, UintType, 1, a1)
TS_SET_SCALARS(ui, unsigned int, UintType, 2, a1, a2)
TS_SET_SCALARS(ui, unsigned int, UintType, 3, a1, a2, a3)
TS_SET_SCALARS(ui, unsigned int, UintType, 4, a1, a2, a3, a4)

RTresult rtVariableGet1f(RTvariable v, float* f1) {
  return GetScattered<float, 1>(__func__, v, FloatType(1), {f1});
}
RTresult rtVariableGet2f(RTvariable v, float* f1, float* f2) {
  return GetScattered<float, 2>(__func__, v, FloatType(2), {f1, f2});
}
RTresult rtVariableGet3f(RTvariable v, float* f1, float* f2, float* f3) {
  return GetScattered<float, 3>(__func__, v, FloatType(3), {f1, f2, f3});
}
RTresult rtVariableGet4f(RTvariable v, float* f1, float* f2, float* f3, float* f4) {
  return GetScattered<float, 4>(__func__, v, FloatType(4), {f1, f2, f3, f4});
}
RTresult rtVariableGet1i(RTvariable v, int* i1) {
  return GetScattered<int, 1>(__func__, v, IntType(1), {i1});
}
RTresult rtVariableGet2i(RTvariable v, int* i1, int* i2) {
  return GetScattered<int, 2>(__func__, v, IntType(2), {i1, i2});
}
RTresult rtVariableGet3i(RTvariable v, int* i1, int* i2, int* i3) {
  return GetScattered<int, 3>(__func__, v, IntType(3), {i1, i2, i3});
}
RTresult rtVariableGet4i(RTvariable v, int* i1, int* i2, int* i3, int* i4) {
  return GetScattered<int, 4>(__func__, v, IntType(4), {i1, i2, i3, i4});
}
RTresult rtVariableGet1ui(RTvariable v, unsigned int* u1) {
  return GetScattered<unsigned int, 1>(__func__, v, UintType(1), {u1});
}
RTresult rtVariableGet2ui(RTvariable v, unsigned int* u1, unsigned int* u2) {
  return GetScattered<unsigned int, 2>(__func__, v, UintType(2), {u1, u2});
}
RTresult rtVariableGet3ui(RTvariable v, unsigned int* u1, unsigned int* u2, unsigned int* u3) {
  return GetScattered<unsigned int, 3>(__func__, v, UintType(3), {u1, u2, u3});
}
RTresult rtVariableGet4ui(RTvariable v, unsigned int* u1, unsigned int* u2, unsigned int* u3,
                          unsigned int* u4) {
  return GetScattered<unsigned int, 4>(__func__, v, UintType(4), {u1, u2, u3, u4});
}

#define TS_MATRIX(R, C)                                                                    \
  RTresult rtVariableSetMatrix##R##x##C##fv(RTvariable v, int transpose, const float* m) { \
    return SetMatrix<R, C>(__func__, v, transpose, m);                                     \
  }                                                                                        \
  RTresult rtVariableGetMatrix##R##x##C##fv(RTvariable v, int transpose, float* m) {       \
    return GetMatrix<R, C>(__func__, v, transpose, m);                                     \
  }

TS_MATRIX(2, 2)
TS_MATRIX(2, 3)
TS_MATRIX(2, 4)
TS_MATRIX(3, 2)
TS_MATRIX(3, 3)
TS_MATRIX(3, 4)
TS_MATRIX(4, 2)
TS_MATRIX(4, 3)
TS_MATRIX(4, 4)

RTresult rtVariableSetObject(RTvariable v, RTobject object) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_ASSIGN_OR_RETURN(
        Object * target,
        AnyArg(object, var.context(), "object",
               {Kind::kBuffer, Kind::kTextureSampler, Kind::kProgram, Kind::kGroup,
                Kind::kGeometryGroup, Kind::kTransform, Kind::kSelector},
               "a buffer, texture sampler, program, group, geometry group, transform or "
               "selector"));
    return var.SetObject(target);
  });
}

RTresult rtVariableGetObject(RTvariable v, RTobject* object) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(object, "object pointer"));
    TS_ASSIGN_OR_RETURN(Object * target, var.GetObject());
    *object = ToHandle<RTobject>(target);
    return absl::OkStatus();
  });
}

RTresult rtVariableSetUserData(RTvariable v, RTsize size, const void* ptr) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    if (size > 0) TS_RETURN_IF_ERROR(NotNull(ptr, "data pointer"));
    return var.SetUserData(ptr, size);
  });
}

RTresult rtVariableGetUserData(RTvariable v, RTsize size, void* ptr) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    if (size > 0) TS_RETURN_IF_ERROR(NotNull(ptr, "data pointer"));
    return var.GetUserData(ptr, size);
  });
}

RTresult rtVariableGetName(RTvariable v, const char** name_return) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(name_return, "name pointer"));
    *name_return = var.name().c_str();
    return absl::OkStatus();
  });
}

RTresult rtVariableGetAnnotation(RTvariable v, const char** annotation_return) {
  return Call<Variable>(__func__, v, [&](Variable&) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(annotation_return, "annotation pointer"));
    // Host-declared variables carry no annotation (those live in program modules).
    *annotation_return = "";
    return absl::OkStatus();
  });
}

RTresult rtVariableGetType(RTvariable v, RTobjecttype* type_return) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(type_return, "type pointer"));
    *type_return = var.type();
    return absl::OkStatus();
  });
}

RTresult rtVariableGetContext(RTvariable v, RTcontext* context) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(context, "context pointer"));
    *context = ToHandle<RTcontext>(var.context());
    return absl::OkStatus();
  });
}

RTresult rtVariableGetSize(RTvariable v, RTsize* size) {
  return Call<Variable>(__func__, v, [&](Variable& var) -> absl::Status {
    TS_RETURN_IF_ERROR(NotNull(size, "size pointer"));
    *size = var.ValueSize();
    return absl::OkStatus();
  });
}

}  // extern "C"
