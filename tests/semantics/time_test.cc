// rtCurrentTime: 0 in a launch's own programs, the time rtTrace gave a ray in the programs that
// ray runs, the caller's for a ray traced without one, and a program's own again after a nested
// ray with another time returned; on an in-process device and on 1 and 3 worker processes.
#include <gtest/gtest.h>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "time_programs";

class TimeTest : public GridFixture {
 protected:
  TimeTest() : GridFixture(8, 3) {}
};

TEST_P(TimeTest, ProgramsSeeTheTimeOfTheirRay) {
  // An empty scene: every ray misses.
  RTgeometrygroup empty = nullptr;
  Ok(rtGeometryGroupCreate(ctx_, &empty));
  Ok(rtGeometryGroupSetAcceleration(empty, Accel()));
  Ok(rtVariableSetObject(ContextVar("top"), empty));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "trace_times")));
  Ok(rtContextSetMissProgram(ctx_, 0, Program(kModule, "miss_times")));
  ExpectEach(Launch(), [](unsigned x, unsigned y) {
    const float outer = x % 2 == 0 ? x * 0.125f : 0.f;
    const float inner = y == 0 ? 0.75f : outer;
    return outer + 10.f * inner;  // the ray generation program's own time is 0
  });
}

INSTANTIATE_TEST_SUITE_P(Devices, TimeTest, ::testing::Values("inproc", "local:1", "local:3"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing
