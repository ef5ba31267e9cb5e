// What the OptiX 7 host API tests share: an SDK-style setup (optixInit, a device context with a
// log callback that keeps every message) and modules from source text. The tests link libtessera
// as an application does and reach every function through the function table.
#ifndef TESSERA_TESTS_OPTIX7_HOST_API_FIXTURE_H_
#define TESSERA_TESTS_OPTIX7_HOST_API_FIXTURE_H_

#include <gtest/gtest.h>
#include <optix.h>
#include <optix_stubs.h>

#include <string>
#include <vector>

namespace tessera_test {

// A program module with one entry function of each kind, the launch parameters and a function
// that is no entry point.
extern const char kAllKindsSource[];

// A raygen program group's description.
OptixProgramGroupDesc Raygen(OptixModule module, const char* name);

struct LogMessage {
  unsigned level;
  std::string tag;
  std::string message;
};

class OptixHostTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;

  // A context (validation mode as asked) whose messages go to log_.
  OptixDeviceContext CreateContext(bool validation);

  // Whether a logged message at `level` contains `text`.
  bool Logged(unsigned level, const std::string& text) const;

  // A module of kAllKindsSource (or `source`) in `context` (context_ by default).
  OptixModule CompileModule(const std::string& source = kAllKindsSource,
                            OptixDeviceContext context = nullptr);

  OptixDeviceContext context_ = nullptr;
  OptixModuleCompileOptions module_options_{};
  OptixPipelineCompileOptions pipeline_options_{};
  std::vector<LogMessage> log_;
  std::vector<OptixDeviceContext> contexts_;
};

}  // namespace tessera_test

#endif  // TESSERA_TESTS_OPTIX7_HOST_API_FIXTURE_H_
