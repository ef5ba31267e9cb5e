// Declaring and setting variables on any scope object (context, material, geometry …) with
// every rt* call checked.
#ifndef TESSERA_SAMPLES_TUTORIAL_VARIABLES_H_
#define TESSERA_SAMPLES_TUTORIAL_VARIABLES_H_

#include <optixu/optixu_vector_types.h>

#include <functional>
#include <string>

#include "tessera/rt.h"

namespace tessera::tutorial {

class Variables {
 public:
  // `declare` is the scope's rt*DeclareVariable, e.g. rtMaterialDeclareVariable.
  template <typename Object>
  Variables(RTcontext context, Object object, RTresult (*declare)(Object, const char*, RTvariable*),
            std::string scope_name)
      : context_(context),
        declare_([object, declare](const char* name, RTvariable* v) {
          return declare(object, name, v);
        }),
        scope_name_(std::move(scope_name)) {}

  void Float(const char* name, float f);
  void Float3(const char* name, float x, float y, float z);
  void Float3(const char* name, const float3& v) { Float3(name, v.x, v.y, v.z); }
  void Float4(const char* name, const float4& v);
  void Int(const char* name, int i);
  void Uint(const char* name, unsigned int u);
  // Binds a buffer, graph node or other object.
  void Object(const char* name, RTobject object);

 private:
  RTvariable Declare(const char* name);
  void Check(RTresult code, const char* call, const char* name);

  RTcontext context_;
  std::function<RTresult(const char*, RTvariable*)> declare_;
  std::string scope_name_;
};

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_VARIABLES_H_
