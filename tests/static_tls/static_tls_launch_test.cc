// Launches of programs whose modules carry an initial-exec build (docs/programs.md, "Thread-local
// storage"), on the device set of TESSERA_DEVICES: an in-process device with and without static
// TLS reserved for modules (GLIBC_TUNABLES, set by ctest), and worker processes, which reserve it
// themselves. Whichever build a device loads, the results are the same; a module whose
// thread-locals do not fit the room runs from its local-dynamic build.
#include <dirent.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr size_t kWidth = 37, kHeight = 11;

// The initial-exec builds devices wrote into the module cache directory (<hash>.so.ie).
std::vector<std::string> InitialExecFiles(const std::string& dir) {
  std::vector<std::string> files;
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (name.size() > 6 && name.compare(name.size() - 6, 6, ".so.ie") == 0) {
        files.push_back(dir + "/" + name);
      }
    }
    closedir(d);
  }
  return files;
}

class StaticTlsLaunchTest : public RtFixture {};

TEST_F(StaticTlsLaunchTest, BothBuildsGiveTheSameValues) {
  const char* cache = std::getenv("TESSERA_CACHE_DIR");
  ASSERT_NE(cache, nullptr) << "ctest sets TESSERA_CACHE_DIR";
  for (const std::string& f : InitialExecFiles(cache)) unlink(f.c_str());

  Ok(rtContextSetRayTypeCount(ctx_, 1));
  Ok(rtContextSetEntryPointCount(ctx_, 2));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("static_tls_programs", "write_values")));
  Ok(rtContextSetRayGenerationProgram(ctx_, 1, Program("static_tls_big", "write_through_scratch")));
  Ok(rtVariableSet1f(ContextVar("scale"), 0.5f));
  RTbuffer values = Buffer2D("values", RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT, kWidth, kHeight);
  for (unsigned entry : {0u, 1u}) {
    SCOPED_TRACE(entry == 0 ? "initial-exec where there is room" : "too large for the room");
    Ok(rtContextLaunch2D(ctx_, entry, kWidth, kHeight));
    const std::vector<float> got = ReadAs<float>(values);
    for (size_t y = 0; y < kHeight; ++y) {
      for (size_t x = 0; x < kWidth; ++x) {
        const float want = 0.5f * static_cast<float>(x + 100 * y) + (entry == 1 ? 1.f : 0.f);
        ASSERT_EQ(got[y * kWidth + x], want) << x << "," << y;
      }
    }
  }
  // Devices with room wrote out the builds they loaded: worker processes always.
  const char* expect = std::getenv("TESSERA_TEST_EXPECT_INITIAL_EXEC");
  ASSERT_NE(expect, nullptr) << "ctest sets TESSERA_TEST_EXPECT_INITIAL_EXEC";
  EXPECT_EQ(!InitialExecFiles(cache).empty(), std::string(expect) == "1") << cache;
}

}  // namespace
}  // namespace tessera::testing
