#include "tutorial/variables.h"

#include "tutorial/rt_check.h"

namespace tessera::tutorial {

void Variables::Check(RTresult code, const char* call, const char* name) {
  CheckRt(context_, code, std::string(call) + "(" + scope_name_ + " variable '" + name + "')");
}

RTvariable Variables::Declare(const char* name) {
  RTvariable v = nullptr;
  Check(declare_(name, &v), "DeclareVariable", name);
  return v;
}

void Variables::Float(const char* name, float f) {
  Check(rtVariableSet1f(Declare(name), f), "rtVariableSet1f", name);
}

void Variables::Float3(const char* name, float x, float y, float z) {
  Check(rtVariableSet3f(Declare(name), x, y, z), "rtVariableSet3f", name);
}

void Variables::Float4(const char* name, const float4& v) {
  Check(rtVariableSet4f(Declare(name), v.x, v.y, v.z, v.w), "rtVariableSet4f", name);
}

void Variables::Int(const char* name, int i) {
  Check(rtVariableSet1i(Declare(name), i), "rtVariableSet1i", name);
}

void Variables::Uint(const char* name, unsigned int u) {
  Check(rtVariableSet1ui(Declare(name), u), "rtVariableSet1ui", name);
}

void Variables::Object(const char* name, RTobject object) {
  Check(rtVariableSetObject(Declare(name), object), "rtVariableSetObject", name);
}

}  // namespace tessera::tutorial
