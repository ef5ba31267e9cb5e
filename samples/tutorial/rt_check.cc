#include "tutorial/rt_check.h"

#include <cstdio>

namespace tessera::tutorial {

void CheckRt(RTcontext context, RTresult code, const std::string& what) {
  if (code == RT_SUCCESS) return;
  const char* message = nullptr;
  rtContextGetErrorString(context, code, &message);
  char code_text[32];
  std::snprintf(code_text, sizeof(code_text), "0x%X", static_cast<unsigned>(code));
  throw TutorialError(what + " failed (" + code_text +
                      "): " + (message != nullptr ? message : "no error message"));
}

}  // namespace tessera::tutorial
