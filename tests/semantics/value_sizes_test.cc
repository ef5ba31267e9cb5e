// Payloads and attributes of unusual sizes reach programs and come back intact, also across a
// nested trace into the same module (value_sizes_programs.cu), on an in-process device and on
// worker processes.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "rt_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "value_sizes_programs";

class ValueSizesTest : public RtFixture, public ::testing::WithParamInterface<const char*> {};

TEST_P(ValueSizesTest, PayloadsAndAttributesOfEverySizeRoundTrip) {
  Ok(tesseraContextSetDeviceSpec(ctx_, GetParam()));
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  // One payload size each, then a program that traces its own payload variable (8) into a miss
  // (9), then a payload size no variable has (10), then one that traces a part of its own payload
  // variable (11) into a miss (12).
  constexpr unsigned kRayTypes = 13;
  Ok(rtContextSetRayTypeCount(ctx_, kRayTypes));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program(kModule, "check_sizes")));
  Ok(rtContextSetMissProgram(ctx_, 9, Program(kModule, "miss_self")));
  Ok(rtContextSetMissProgram(ctx_, 12, Program(kModule, "miss_member")));
  const char* closest_hit[kRayTypes] = {
      "ch_1",   "ch_3",    "ch_6",  "ch_20_nested",  "ch_128",    "ch_130", "ch_132",
      "ch_260", "ch_self", nullptr, "ch_other_size", "ch_member", nullptr};
  Instance scene =
      MakeInstance(Program(kModule, "intersect"), Program(kModule, "bounds"), 1, nullptr);
  for (unsigned t = 0; t < kRayTypes; ++t) {
    if (closest_hit[t] == nullptr) continue;
    Ok(rtMaterialSetClosestHitProgram(scene.material, t, Program(kModule, closest_hit[t])));
  }
  Ok(rtVariableSetObject(ContextVar("top_object"), scene.group));
  constexpr unsigned kWidth = 16, kHeight = 8;
  RTbuffer failures =
      Buffer2D("failures", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, kWidth, kHeight);
  Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
  const std::vector<unsigned> values = ReadAs<unsigned>(failures);
  // Bit b set: the payload of ray type b did not come back as its closest-hit program made it
  // (bit 8: the self-traced payload, bit 9: the 8-byte one, bit 10: the self-traced part).
  for (unsigned i = 0; i < kWidth * kHeight; ++i) {
    EXPECT_EQ(values[i], 0u) << "launch index (" << i % kWidth << ", " << i / kWidth << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, ValueSizesTest, ::testing::Values("inproc", "local:2"),
                         DeviceName);

}  // namespace
}  // namespace tessera::testing
