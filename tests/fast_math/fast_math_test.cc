// Fast-math program modules on the OptiX 3 layer (docs/fast_math.md), in process and on worker
// processes: a module built with FAST_MATH, or compiled by a context with
// TESSERA_ACCURACY_FAST_MATH, runs with denormals flushed to zero and still sees NaN and
// infinity (its tests, and RT_EXCEPTION_INVALID_RAY for the rays it computes); default modules
// keep IEEE denormals, bit for bit, also after a fast-math launch on the same threads.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "float_mode.h"  // worker/core: the control word the engine sets
#include "rt_fixture.h"
#include "tessera/accuracy.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kDefault[] = "fast_math_default";
constexpr char kFast[] = "fast_math_fast";
constexpr unsigned kW = 64;  // enough launch indices for every thread of a device to take some

// The calling thread's floating-point mode, without the sticky exception flags that its own
// arithmetic sets.
uint64_t ControlWord() { return tessera::worker::FloatMode() & ~tessera::worker::kFloatStatusBits; }

uint32_t Bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// The IEEE results that `denormals` computes without fast math: products of the values below,
// made here with denormals on (the test's own thread never flushes: SetUp checks it).
struct Expected {
  float product, scaled;
};
Expected IeeeDenormals() {
  volatile float tiny = 1e-20f, denormal = 1e-40f, big = 1e10f;
  return {tiny * tiny, denormal * big};
}

class FastMathTest : public OnDevicesFixture {
 protected:
  void SetUp() override {
    // Compiled modules land in the build tree, not the user's cache.
    setenv("TESSERA_CACHE_DIR", TESSERA_FAST_MATH_CACHE_DIR, 1);
    mode_before_ = ControlWord();
    ASSERT_FALSE(worker::FlushesDenormals()) << "the test thread must start with IEEE denormals";
    OnDevicesFixture::SetUp();
    result_ = Float4Buffer("result", RT_BUFFER_OUTPUT, kW, 1);
    Ok(rtVariableSet1f(ContextVar("tiny"), 1e-20f));
    Ok(rtVariableSet1f(ContextVar("denormal_in"), 1e-40f));
    Ok(rtVariableSet1f(ContextVar("big"), 1e10f));
    Ok(rtVariableSet1f(ContextVar("zero"), 0.f));
    Ok(rtVariableSet1f(ContextVar("one"), 1.f));
    Ok(rtVariableSet1i(ContextVar("mode"), 0));
    // An empty group: the invalid-ray check comes before traversal.
    RTgeometrygroup group = nullptr;
    Ok(rtGeometryGroupCreate(ctx_, &group));
    Ok(rtGeometryGroupSetAcceleration(group, Accel()));
    Ok(rtVariableSetObject(ContextVar("top_object"), group));
    const Expected e = IeeeDenormals();
    ASSERT_NE(e.product, 0.f);  // a denormal, not flushed
    ASSERT_NE(e.scaled, 0.f);
  }
  void TearDown() override {
    OnDevicesFixture::TearDown();
    // The host's thread takes pieces of in-process launches and loads their modules: it must
    // get its own mode back whatever the modules' constructors or launches set.
    EXPECT_EQ(ControlWord(), mode_before_);
  }

  RTprogram Source(const char* function) {
    RTprogram p = nullptr;
    const RTresult r = rtProgramCreateFromPTXFile(ctx_, TESSERA_FAST_MATH_SOURCE, function, &p);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    return p;
  }

  std::vector<Float4> Launch(RTprogram raygen) {
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, raygen));
    const RTresult r = rtContextLaunch2D(ctx_, 0, kW, 1);
    EXPECT_EQ(r, RT_SUCCESS) << Error(r);
    return Read(result_);
  }

  // Every launch index flushed both denormals (FTZ and DAZ), or none did, bit for bit IEEE.
  void ExpectFlushed(const std::vector<Float4>& r, const char* what) {
    ASSERT_EQ(r.size(), kW);
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(Bits(r[x][0]), 0u) << what << ": index " << x << " product " << r[x][0];
      EXPECT_EQ(Bits(r[x][1]), 0u) << what << ": index " << x << " scaled " << r[x][1];
    }
  }
  void ExpectIeee(const std::vector<Float4>& r, const char* what) {
    ASSERT_EQ(r.size(), kW);
    const Expected e = IeeeDenormals();
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(Bits(r[x][0]), Bits(e.product)) << what << ": index " << x;
      EXPECT_EQ(Bits(r[x][1]), Bits(e.scaled)) << what << ": index " << x;
    }
  }

  uint64_t mode_before_ = 0;
  RTbuffer result_ = nullptr;
};

TEST_P(FastMathTest, FastMathModuleFlushesDenormals) {
  ExpectFlushed(Launch(Program(kFast, "denormals")), "FAST_MATH module");
}

TEST_P(FastMathTest, DefaultModuleKeepsIeeeDenormals) {
  ExpectIeee(Launch(Program(kDefault, "denormals")), "default module");
}

// The threads a fast-math launch ran on are shared: the next default launch gets IEEE denormals.
TEST_P(FastMathTest, DefaultLaunchAfterFastMathLaunchIsUnchanged) {
  RTprogram fast = Program(kFast, "denormals");
  RTprogram plain = Program(kDefault, "denormals");
  for (int round = 0; round < 3; ++round) {
    ExpectFlushed(Launch(fast), "FAST_MATH module");
    ExpectIeee(Launch(plain), "default module after a FAST_MATH launch");
  }
}

// An application thread that flushes denormals itself (as renderers often set) launches a
// default module: its programs still get IEEE denormals, whichever thread runs them (TBB hands the
// launching thread's mode to the threads of the arena it starts).
TEST_P(FastMathTest, DefaultLaunchFromAFlushingThreadKeepsIeeeDenormals) {
  RTprogram plain = Program(kDefault, "denormals");
  std::vector<Float4> r;
  {
    worker::ScopedFloatMode application_mode(true);
    r = Launch(plain);
  }
  ExpectIeee(r, "default module launched from a flushing thread");
}

// One fast-math module among a launch's programs (here its exception program) makes the launch a
// fast-math one: the threads run every program of it with the same mode.
TEST_P(FastMathTest, AnyFastMathProgramOfTheLaunchFlushes) {
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kFast, "exception_record")));
  ExpectFlushed(Launch(Program(kDefault, "denormals")), "default raygen, FAST_MATH exception");
}

// A module compiled and linked with plain -ffast-math (__FAST_MATH__) is a fast-math module too.
TEST_P(FastMathTest, PlainFastMathModuleFlushesDenormals) {
  ExpectFlushed(Launch(Program("fast_math_plain", "denormals")), "-ffast-math module");
}

// A module whose constructor sets FTZ/DAZ changes neither the thread that loads it (TearDown
// checks the test's own, which loads modules for an in-process device) nor its launches' results.
TEST_P(FastMathTest, ModuleConstructorsDoNotChangeTheMode) {
  ExpectIeee(Launch(Program("fast_math_constructor", "denormals")), "constructor module");
}

TEST_P(FastMathTest, NanAndInfinityTestsWorkInFastMathModules) {
  for (const char* module : {kFast, kDefault}) {
    const std::vector<Float4> r = Launch(Program(module, "checks"));
    ASSERT_EQ(r.size(), kW);
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(r[x][0], 1.f) << module << ": isnan(0/0) at index " << x;
      EXPECT_EQ(r[x][1], 1.f) << module << ": isinf(1/0) at index " << x;
      EXPECT_EQ(r[x][2], 0.f) << module << ": isfinite(1/0) at index " << x;
      EXPECT_EQ(r[x][3], 1.f) << module << ": NaN != NaN at index " << x;
    }
  }
}

// A NaN or infinity a fast-math program computes into a ray raises RT_EXCEPTION_INVALID_RAY.
TEST_P(FastMathTest, InvalidRaysOfFastMathProgramsRaiseTheException) {
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program(kFast, "exception_record")));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_INVALID_RAY, 1));
  RTprogram raygen = Program(kFast, "invalid_ray");
  for (int mode : {0, 1}) {
    Ok(rtVariableSet1i(ContextVar("mode"), mode));
    const std::vector<Float4> r = Launch(raygen);
    ASSERT_EQ(r.size(), kW);
    for (unsigned x = 0; x < kW; ++x) {
      EXPECT_EQ(r[x][0], float(RT_EXCEPTION_INVALID_RAY)) << "mode " << mode << " index " << x;
    }
  }
}

// TESSERA_ACCURACY_FAST_MATH: source the context compiles gets fast math (NaN tests kept), and
// its launches flush denormals even in modules built without it.
TEST_P(FastMathTest, ContextFlagCompilesSourceWithFastMath) {
  ExpectIeee(Launch(Source("denormals")), "source compiled without the flag");
  Ok(tesseraContextSetAccuracy(ctx_, TESSERA_ACCURACY_FAST_MATH));
  ExpectFlushed(Launch(Source("denormals")), "source compiled with the flag");
  const std::vector<Float4> checks = Launch(Source("checks"));
  EXPECT_EQ(checks[0][0], 1.f) << "isnan(0/0)";
  EXPECT_EQ(checks[0][1], 1.f) << "isinf(1/0)";
  ExpectFlushed(Launch(Program(kDefault, "denormals")), "default module on a fast-math context");
  Ok(tesseraContextSetAccuracy(ctx_, 0));
  ExpectIeee(Launch(Program(kDefault, "denormals")), "default module, flag cleared");
}

// The two compiles of one source are two modules: the flag is part of the compile cache's key.
TEST_P(FastMathTest, ContextFlagIsPartOfTheCompileCacheKey) {
  Ok(tesseraContextSetAccuracy(ctx_, TESSERA_ACCURACY_FAST_MATH));
  ExpectFlushed(Launch(Source("denormals")), "flag set");
  Ok(tesseraContextSetAccuracy(ctx_, 0));
  ExpectIeee(Launch(Source("denormals")), "flag cleared, same source");
  Ok(tesseraContextSetAccuracy(ctx_, TESSERA_ACCURACY_FAST_MATH));
  ExpectFlushed(Launch(Source("denormals")), "flag set again");
}

INSTANTIATE_TEST_SUITE_P(Devices, FastMathTest, ::testing::Values("inproc", "local:2"), DeviceName);

}  // namespace
}  // namespace tessera::testing
