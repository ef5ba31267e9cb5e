#include "tutorial/rt_check.h"

#include <cstdio>

namespace tessera::tutorial {

void CheckRt(RTcontext context, RTresult code, const std::string& what) {
  if (code == RT_SUCCESS) return;
  const char* message = nullptr;
  rtContextGetErrorString(context, code, &message);
  char code_text[32];
  std::snprintf(code_text, sizeof(code_text), "0x%X", static_cast<unsigned>(code));
  // The message names the call itself ("rtContextLaunch2D(context): ..."); the source text of
  // the call (`what`) only fills in when there is none.
  std::string said = message != nullptr ? message : "";
  while (!said.empty() && (said.back() == '\n' || said.back() == ' ')) said.pop_back();
  if (!said.empty()) throw TutorialError(said + " (" + code_text + ")");
  throw TutorialError(what.substr(0, what.find('(')) + " failed (" + code_text + ")");
}

}  // namespace tessera::tutorial
