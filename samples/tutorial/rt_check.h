// Error handling of the tutorial host code: every rt* call goes through RT_CHECK, which turns a
// failure into a TutorialError carrying the context's error string.
#ifndef TESSERA_SAMPLES_TUTORIAL_RT_CHECK_H_
#define TESSERA_SAMPLES_TUTORIAL_RT_CHECK_H_

#include <stdexcept>
#include <string>

#include "tessera/rt.h"

namespace tessera::tutorial {

// A failure the tutorial reports to the user (and tests can catch).
class TutorialError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws TutorialError naming `what` and rtContextGetErrorString's message unless `code` is
// RT_SUCCESS. `context` may be null (rtContextCreate failed).
void CheckRt(RTcontext context, RTresult code, const std::string& what);

}  // namespace tessera::tutorial

#define RT_CHECK(context, call) ::tessera::tutorial::CheckRt((context), (call), #call)

#endif  // TESSERA_SAMPLES_TUTORIAL_RT_CHECK_H_
