// An environment variable set (or unset) for the lifetime of an object and put back afterwards,
// for tests of settings Tessera reads from the environment: a test that set one and unset it when
// done would also drop a value the whole run was started with (TESSERA_BATCHING=auto, say).
#ifndef TESSERA_TESTS_COMMON_SCOPED_ENV_H_
#define TESSERA_TESTS_COMMON_SCOPED_ENV_H_

#include <cstdlib>
#include <string>

namespace tessera::test {

class ScopedEnv {
 public:
  // `value` null: unset while the object lives.
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
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;
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

#endif  // TESSERA_TESTS_COMMON_SCOPED_ENV_H_
