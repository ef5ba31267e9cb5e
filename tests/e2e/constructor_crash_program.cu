// A program module whose static constructor crashes the process that loads it, when
// TESSERA_TEST_CRASH_IN_CONSTRUCTOR is set (workers inherit it from the test): the crash line
// must name the module, not say "outside any program".
#include <optix_world.h>

#include <cstdlib>

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtBuffer<float4, 2> image;

namespace {
struct CrashOnLoad {
  // no_sanitize: built with UBSan (tools/sanitize.sh), the null store would end the process with
  // UBSan's report and SIGABRT instead of the SIGSEGV under test.
  __attribute__((no_sanitize("undefined"))) CrashOnLoad() {
    if (std::getenv("TESSERA_TEST_CRASH_IN_CONSTRUCTOR") != nullptr) {
      *reinterpret_cast<volatile int*>(std::strtoull("0", nullptr, 10)) = 1;
    }
  }
};
const CrashOnLoad crash_on_load;
}  // namespace

RT_PROGRAM void render_loaded() { image[launch_index] = make_float4(1.f); }
