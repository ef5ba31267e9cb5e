// The C API sweep (see c_api_sweep_test.cc): a world with one live and one destroyed object of
// every kind, and tables of calls into every entry point of tessera/rt.h.
#ifndef TESSERA_TESTS_API_C_API_SWEEP_H_
#define TESSERA_TESTS_API_C_API_SWEEP_H_

#include <functional>
#include <string>
#include <vector>

#include "tessera/rt.h"

namespace tessera::test {

enum class K {
  kContext,
  kBuffer,
  kVariable,
  kProgram,
  kGeometry,
  kMaterial,
  kInstance,
  kGeometryGroup,
  kGroup,
  kSelector,
  kTransform,
  kAcceleration,
  kTriangles,  // GeometryTriangles (OptiX 6)
  kSampler,    // TextureSampler
};

inline const char* KindWord(K k) {
  switch (k) {
    case K::kContext:
      return "context";
    case K::kBuffer:
      return "buffer";
    case K::kVariable:
      return "variable";
    case K::kProgram:
      return "program";
    case K::kGeometry:
      return "geometry";
    case K::kMaterial:
      return "material";
    case K::kInstance:
      return "geometry instance";
    case K::kGeometryGroup:
      return "geometry group";
    case K::kGroup:
      return "group";
    case K::kSelector:
      return "selector";
    case K::kTransform:
      return "transform";
    case K::kAcceleration:
      return "acceleration";
    case K::kTriangles:
      return "geometry triangles";
    case K::kSampler:
      return "texture sampler";
  }
  return "?";
}

// One live object of every kind, one destroyed object of every kind, and scratch outputs.
struct World {
  RTcontext ctx = nullptr;
  RTbuffer buffer = nullptr;
  RTvariable variable = nullptr;
  RTprogram program = nullptr;
  RTgeometry geometry = nullptr;
  RTmaterial material = nullptr;
  RTgeometryinstance instance = nullptr;
  RTgeometrygroup geometry_group = nullptr;
  RTgroup group = nullptr;
  RTselector selector = nullptr;
  RTtransform transform = nullptr;
  RTacceleration acceleration = nullptr;
  RTgeometrytriangles triangles = nullptr;
  RTtexturesampler sampler = nullptr;

  RTcontext dead_ctx = nullptr;
  RTbuffer dead_buffer = nullptr;
  RTvariable dead_variable = nullptr;
  RTprogram dead_program = nullptr;
  RTgeometry dead_geometry = nullptr;
  RTmaterial dead_material = nullptr;
  RTgeometryinstance dead_instance = nullptr;
  RTgeometrygroup dead_geometry_group = nullptr;
  RTgroup dead_group = nullptr;
  RTselector dead_selector = nullptr;
  RTtransform dead_transform = nullptr;
  RTacceleration dead_acceleration = nullptr;
  RTgeometrytriangles dead_triangles = nullptr;
  RTtexturesampler dead_sampler = nullptr;

  // Scratch outputs.
  unsigned u[4] = {};
  int i[4] = {};
  RTsize sz[4] = {1, 1, 1, 1};
  float f[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  unsigned char bytes[64] = {};
  void* ptr = nullptr;
  const char* str = nullptr;
  RTobject obj = nullptr;
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  RTformat format = RT_FORMAT_UNKNOWN;
  struct {
    RTcontext ctx;
    RTbuffer buffer;
    RTvariable variable;
    RTprogram program;
    RTgeometry geometry;
    RTmaterial material;
    RTgeometryinstance instance;
    RTgeometrygroup geometry_group;
    RTgroup group;
    RTselector selector;
    RTtransform transform;
    RTacceleration acceleration;
    RTgeometrytriangles triangles;
    RTtexturesampler sampler;
  } out = {};
  RTwrapmode wrap = RT_WRAP_REPEAT;
  RTfiltermode filter[3] = {};
  RTtexturereadmode read_mode = RT_TEXTURE_READ_ELEMENT_TYPE;
  RTtextureindexmode index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;

  void* Live(K k) const {
    switch (k) {
      case K::kContext:
        return ctx;
      case K::kBuffer:
        return buffer;
      case K::kVariable:
        return variable;
      case K::kProgram:
        return program;
      case K::kGeometry:
        return geometry;
      case K::kMaterial:
        return material;
      case K::kInstance:
        return instance;
      case K::kGeometryGroup:
        return geometry_group;
      case K::kGroup:
        return group;
      case K::kSelector:
        return selector;
      case K::kTransform:
        return transform;
      case K::kAcceleration:
        return acceleration;
      case K::kTriangles:
        return triangles;
      case K::kSampler:
        return sampler;
    }
    return nullptr;
  }

  void* Dead(K k) const {
    switch (k) {
      case K::kContext:
        return dead_ctx;
      case K::kBuffer:
        return dead_buffer;
      case K::kVariable:
        return dead_variable;
      case K::kProgram:
        return dead_program;
      case K::kGeometry:
        return dead_geometry;
      case K::kMaterial:
        return dead_material;
      case K::kInstance:
        return dead_instance;
      case K::kGeometryGroup:
        return dead_geometry_group;
      case K::kGroup:
        return dead_group;
      case K::kSelector:
        return dead_selector;
      case K::kTransform:
        return dead_transform;
      case K::kAcceleration:
        return dead_acceleration;
      case K::kTriangles:
        return dead_triangles;
      case K::kSampler:
        return dead_sampler;
    }
    return nullptr;
  }

  // A live handle of another kind.
  void* Wrong(K k) const { return k == K::kBuffer ? static_cast<void*>(group) : buffer; }
};

// A call whose first argument is a handle, replaced by null, wrong-type and destroyed handles.
struct SubjectCase {
  K kind;
  const char* call;
  std::function<RTresult(World&, void*)> run;
};

// A call with a null pointer argument (everything else valid).
struct CallCase {
  const char* call;
  std::function<RTresult(World&)> run;
};

// A call whose second handle argument (declared type `type`) is replaced.
struct ArgCase {
  const char* type;
  const char* call;
  std::function<RTresult(World&, void*)> run;
};

std::vector<SubjectCase> SubjectCases();
std::vector<CallCase> NullPointerCases();
std::vector<ArgCase> ArgCases();

}  // namespace tessera::test

#endif  // TESSERA_TESTS_API_C_API_SWEEP_H_
