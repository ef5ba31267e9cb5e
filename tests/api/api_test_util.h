// Shared helpers for host API tests.
#ifndef TESSERA_TESTS_API_API_TEST_UTIL_H_
#define TESSERA_TESTS_API_API_TEST_UTIL_H_

#include <cstdlib>
#include <string>

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

// Sets an environment variable for the lifetime of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) {
      had_ = true;
      old_ = old;
    }
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_.c_str(), old_.c_str(), 1);
    } else {
      unsetenv(name_.c_str());
    }
  }

 private:
  std::string name_;
  bool had_ = false;
  std::string old_;
};

}  // namespace tessera::test

#endif  // TESSERA_TESTS_API_API_TEST_UTIL_H_
