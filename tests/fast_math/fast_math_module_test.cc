// How a device's module cache sees fast-math modules (docs/fast_math.md): the flag each kind of
// build leaves in a module, on both module ABIs, and the loading thread's floating-point mode,
// which a module's constructors (crtfastmath.o's in a module linked with -ffast-math, or the
// module's own) must not change.
#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "float_mode.h"
#include "module.h"
#include "testdata/store_and_load.h"

namespace tessera::worker {
namespace {

// The module at `path`, stored in and loaded from a cache of the build tree.
const Module* Load(const std::string& path) {
  static ModuleCache cache(TESSERA_FAST_MATH_MODULE_CACHE);
  return testing::StoreAndLoad(cache, path);
}

std::string Optix3(const char* name) {
  return std::string(TESSERA_TEST_MODULE_DIR) + "/" + name + ".so";
}

TEST(FastMathModuleTest, EachBuildSaysWhetherItIsFastMath) {
  struct Case {
    std::string path;
    bool optix7;
    bool fast_math;
  };
  const Case cases[] = {
      {Optix3("fast_math_default"), false, false},
      {Optix3("fast_math_fast"), false, true},   // FAST_MATH
      {Optix3("fast_math_plain"), false, true},  // -ffast-math: __FAST_MATH__
      {Optix3("fast_math_constructor"), false, false},
      {TESSERA_FAST_MATH7_DEFAULT, true, false},
      {TESSERA_FAST_MATH7_FAST, true, true},
  };
  for (const Case& c : cases) {
    const Module* m = Load(c.path);
    ASSERT_NE(m, nullptr) << c.path;
    EXPECT_EQ(m->optix7(), c.optix7) << c.path;
    EXPECT_EQ(m->fast_math(), c.fast_math) << c.path;
  }
}

// Loading runs the modules' constructors on this thread: crtfastmath.o's (fast_math_plain, linked
// with -ffast-math) and fast_math_constructor's own both set FTZ/DAZ, which loading undoes.
TEST(FastMathModuleTest, ConstructorsDoNotChangeTheLoadingThreadsMode) {
  ASSERT_FALSE(FlushesDenormals());
  for (const char* name : {"fast_math_plain", "fast_math_constructor"}) {
    // A fresh thread for each: a module is loaded once per process, and this test may follow
    // another that loaded it.
    bool flushes = true;
    std::thread([&] {
      ASSERT_NE(Load(Optix3(name)), nullptr);
      flushes = FlushesDenormals();
    }).join();
    EXPECT_FALSE(flushes) << name << " left the loading thread flushing denormals";
  }
  EXPECT_FALSE(FlushesDenormals());
}

// What the mode scopes do to a thread: set for the scope whatever was there, then put back.
TEST(FastMathModuleTest, ScopedFloatModeSetsAndRestores) {
  const uint64_t before = FloatMode();
  ASSERT_FALSE(FlushesDenormals());
  {
    ScopedFloatMode flush(true);
    EXPECT_TRUE(FlushesDenormals());
    volatile float tiny = 1e-20f;
    EXPECT_EQ(tiny * tiny, 0.f);
    {
      ScopedFloatMode ieee(false);
      EXPECT_FALSE(FlushesDenormals());
      EXPECT_NE(tiny * tiny, 0.f);
    }
    EXPECT_TRUE(FlushesDenormals());
  }
  EXPECT_EQ(FloatMode() & ~kFloatStatusBits, before & ~kFloatStatusBits);
  {
    PreservedFloatMode preserved;
    SetFloatMode(FloatMode() | kFlushDenormalBits);
  }
  EXPECT_FALSE(FlushesDenormals());
}

}  // namespace
}  // namespace tessera::worker
