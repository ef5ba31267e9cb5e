// Shared helpers for host API tests.
#ifndef TESSERA_TESTS_API_API_TEST_UTIL_H_
#define TESSERA_TESTS_API_API_TEST_UTIL_H_

#include <string>

#include "../common/scoped_env.h"
#include "tessera/rt.h"

namespace tessera::test {

// The module built from testdata/test_programs.cc.
inline constexpr const char* kTestModule = TESSERA_TEST_MODULE;

// rtContextGetErrorString for `code` on `context` (may be null).
inline std::string ErrorString(RTcontext context, RTresult code) {
  const char* s = nullptr;
  rtContextGetErrorString(context, code, &s);
  return s == nullptr ? std::string() : std::string(s);
}

}  // namespace tessera::test

#endif  // TESSERA_TESTS_API_API_TEST_UTIL_H_
