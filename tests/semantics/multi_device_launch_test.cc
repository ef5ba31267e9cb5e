// What else a launch carries across devices, on inproc, local:1, local:2 and local:4: variable,
// program and node-graph changes travel as deltas and every device sees them at the next launch;
// rtPrintf output and exception reports from all devices come out complete and in launch-index
// order before the launch returns.
#include <array>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "multi_device_fixture.h"

namespace tessera::testing {
namespace {

using Color = std::array<float, 3>;

class LaunchRulesTest : public MultiDeviceParamTest {
 protected:
  static std::vector<std::string> Lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
  static std::string Format(const char* format, unsigned a, unsigned b, unsigned c = 0) {
    char buffer[128];
    std::snprintf(buffer, sizeof(buffer), format, a, b, c);
    return buffer;
  }
};

// ---- Rule 5: variables, programs and the graph travel as deltas --------------------------------

TEST_P(LaunchRulesTest, VariableProgramAndGraphChangesReachEveryDevice) {
  constexpr size_t kW = 16, kH = 8;
  RTbuffer frame = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kW, kH}, "frame");
  TileSize({4, 2});  // 16 tiles
  RTprogram scaled = Program("ray_gen_scaled"), trace = Program("ray_gen_trace");
  RTprogram shade = Program("shade_color"), inverted = Program("shade_inverted");
  Ok(rtContextSetMissProgram(ctx_, 0, Program("miss_with_color")));
  // One slab perpendicular to z, hit by the rays at x < slab_max_x.
  Instance slab = MakeInstance(Program("slab_intersect"), Program("slab_bounds"), 1, shade);
  RTmaterial red = slab.material, green = nullptr;
  Ok(rtMaterialCreate(ctx_, &green));
  RTvariable red_color = nullptr, green_color = nullptr, slab_z = nullptr, slab_max_x = nullptr;
  Ok(rtMaterialDeclareVariable(red, "color", &red_color));
  Ok(rtMaterialDeclareVariable(green, "color", &green_color));
  Ok(rtGeometryDeclareVariable(slab.geometry, "slab_z", &slab_z));
  Ok(rtGeometryDeclareVariable(slab.geometry, "slab_max_x", &slab_max_x));
  Ok(rtVariableSet3f(green_color, 0.f, 1.f, 0.f));
  Ok(rtVariableSetObject(ContextVar("top_object"), slab.group));

  // What the host set, and the frame it implies for every launch index.
  struct Model {
    bool tracing = false;
    float scale = 2.f;
    Color red = {1.f, 0.f, 0.f}, green = {0.f, 1.f, 0.f}, miss = {0.f, 0.f, 1.f};
    bool green_bound = false, green_inverted = false;
    float z = 5.f, max_x = 8.f;
    Float4 At(size_t x, size_t y) const {
      if (!tracing) return {scale * float(x), scale * float(y), 0.f, 0.f};
      if (float(x) >= max_x) return {miss[0], miss[1], miss[2], -1.f};
      Color c = green_bound ? green : red;
      if (green_bound && green_inverted) c = {1.f - c[0], 1.f - c[1], 1.f - c[2]};
      return {c[0], c[1], c[2], z + 10.f};  // rays start at z = -10
    }
  } model;
  auto set3 = [&](RTvariable v, const Color& c) { Ok(rtVariableSet3f(v, c[0], c[1], c[2])); };
  auto reset = [&] {
    model = Model();
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, scaled));
    Ok(rtVariableSet1f(ContextVar("scale"), model.scale));
    set3(red_color, model.red);
    set3(ContextVar("miss_color"), model.miss);
    Ok(rtGeometryInstanceSetMaterial(slab.instance, 0, red));
    Ok(rtMaterialSetClosestHitProgram(green, 0, shade));
    Ok(rtVariableSet1f(slab_z, model.z));
    Ok(rtVariableSet1f(slab_max_x, model.max_x));
  };
  const std::vector<std::pair<const char*, std::function<void()>>> steps = {
      {"context variable", [&] { Ok(rtVariableSet1f(ContextVar("scale"), model.scale = 3.f)); }},
      {"ray generation program",
       [&] {
         Ok(rtContextSetRayGenerationProgram(ctx_, 0, trace));
         model.tracing = true;
       }},
      {"material variable",
       [&] {
         set3(red_color, model.red = {1.f, 1.f, 0.f});
       }},
      {"instance's material",
       [&] {
         Ok(rtGeometryInstanceSetMaterial(slab.instance, 0, green));
         model.green_bound = true;
       }},
      {"geometry variables",
       [&] {
         Ok(rtVariableSet1f(slab_z, model.z = 2.f));
         Ok(rtVariableSet1f(slab_max_x, model.max_x = 12.f));
       }},
      {"miss variable in context",
       [&] {
         set3(ContextVar("miss_color"), model.miss = {1.f, 1.f, 1.f});
       }},
      {"material's closest hit program",
       [&] {
         Ok(rtMaterialSetClosestHitProgram(green, 0, inverted));
         model.green_inverted = true;
       }},
      {"ray generation program back",
       [&] {
         Ok(rtContextSetRayGenerationProgram(ctx_, 0, scaled));
         model.tracing = false;
       }},
  };
  auto launch_and_check = [&](const char* what) {
    SCOPED_TRACE(what);
    Transfer before = Stats();
    Launch2D(kW, kH);
    EXPECT_EQ((Stats() - before).sent, 0u) << "no buffer changed";
    std::vector<Float4> v = Contents<Float4>(frame);
    for (size_t y = 0; y < kH; ++y) {
      for (size_t x = 0; x < kW; ++x) {
        ASSERT_EQ(v[y * kW + x], model.At(x, y)) << "launch index (" << x << ", " << y << ")";
      }
    }
  };

  for (bool pinned : {false, true}) {
    SCOPED_TRACE(pinned ? "tiles pinned to devices" : "tiles taken dynamically");
    reset();
    if (pinned) {
      PinTilesToDevices();
      Launch2D(kW, kH);  // ships the pinning buffer
    }
    launch_and_check("initial state");
    for (const auto& [what, change] : steps) {
      change();
      launch_and_check(what);
    }
  }
}

// ---- Rule 6: rtPrintf and exception reports ----------------------------------------------------

constexpr unsigned kPrintW = 7, kPrintH = 5;  // tiles of 2x2: 12 tiles, partial on both edges

TEST_P(LaunchRulesTest, PrintsFromEveryLaunchIndexComeOutInLaunchIndexOrder) {
  RayGen("print_indices");
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  TileSize({2, 2});
  auto expected = [](int only_x, int only_y) {
    std::string text;
    for (unsigned y = 0; y < kPrintH; ++y) {
      for (unsigned x = 0; x < kPrintW; ++x) {
        if ((only_x >= 0 && x != unsigned(only_x)) || (only_y >= 0 && y != unsigned(only_y))) {
          continue;
        }
        text += Format("[%u,%u] first\n", x, y) + Format("[%u,%u] second\n", x, y);
      }
    }
    return text;
  };
  for (bool pinned : {false, true}) {
    SCOPED_TRACE(pinned ? "tiles pinned to devices" : "tiles taken dynamically");
    if (pinned) PinTilesToDevices();
    for (std::array<int, 2> only : {std::array<int, 2>{-1, -1}, {3, -1}, {-1, 2}, {6, 4}}) {
      SCOPED_TRACE("print launch index (" + std::to_string(only[0]) + ", " +
                   std::to_string(only[1]) + ")");
      Ok(rtContextSetPrintLaunchIndex(ctx_, only[0], only[1], -1));
      ::testing::internal::CaptureStdout();
      RTresult r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
      std::string out = ::testing::internal::GetCapturedStdout();
      ASSERT_EQ(r, RT_SUCCESS) << Error(r);
      EXPECT_EQ(out, expected(only[0], only[1]));
    }
    Ok(rtContextSetPrintLaunchIndex(ctx_, -1, -1, -1));
  }
}

// rtContextSetPrintBufferSize bounds a launch's output: whole prints in launch-index order while
// they fit, the same on every device set, and stderr says what was dropped.
TEST_P(LaunchRulesTest, PrintsBeyondThePrintBufferSizeAreDroppedAndSaidSo) {
  RayGen("print_indices");
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  TileSize({2, 2});
  const std::string kept = "[0,0] first\n[0,0] second\n[1,0] first\n[1,0] second\n[2,0] first\n";
  Ok(rtContextSetPrintBufferSize(ctx_, kept.size() + 5));  // [2,0] second (13 bytes) is cut
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
  std::string err = ::testing::internal::GetCapturedStderr();
  std::string out = ::testing::internal::GetCapturedStdout();
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  EXPECT_EQ(out, kept);
  EXPECT_NE(err.find("print buffer size"), std::string::npos) << err;
  EXPECT_NE(err.find("65 prints"), std::string::npos) << err;  // 70 prints, 5 kept
}

// A print longer than the print buffer is dropped where it falls, on every device set: worker
// devices send its length only (70 MB would not fit in a message and failed the launch there).
TEST_P(LaunchRulesTest, APrintLongerThanThePrintBufferIsDroppedOnEveryDeviceSet) {
  RayGen("print_huge");
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtContextSetPrintBufferSize(ctx_, 1 << 20));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, 2, 1);
  const std::string err = ::testing::internal::GetCapturedStderr();
  const std::string out = ::testing::internal::GetCapturedStdout();
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  // Once a print is dropped, every later one in launch-index order is too, as before.
  EXPECT_EQ(out, "") << out.substr(0, 200);
  EXPECT_NE(err.find("3 prints (70000013 bytes) were dropped"), std::string::npos) << err;
}

// The launch indices throw_some throws at (every third, row-major) and their codes.
std::vector<std::array<unsigned, 3>> Throwers() {
  std::vector<std::array<unsigned, 3>> t;
  for (unsigned y = 0; y < kPrintH; ++y) {
    for (unsigned x = 0; x < kPrintW; ++x) {
      const unsigned linear = y * kPrintW + x;
      if (linear % 3 == 0) t.push_back({x, y, RT_EXCEPTION_USER + linear % 16});
    }
  }
  return t;
}

// Exceptions that printing does not show (another launch index selected) are still said on
// stderr, as with printing off.
TEST_P(LaunchRulesTest, ExceptionsAtUnprintedLaunchIndicesAreSaid) {
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, {kPrintW, kPrintH}, "exception_log");
  RayGen("throw_some");
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  Ok(rtContextSetPrintLaunchIndex(ctx_, 5000, 0, -1));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
  const std::string err = ::testing::internal::GetCapturedStderr();
  const std::string out = ::testing::internal::GetCapturedStdout();
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  EXPECT_EQ(out, "");
  const std::string said = std::to_string(Throwers().size()) +
                           " launch index(es) raised an exception that no exception program "
                           "handled and printing did not show";
  EXPECT_NE(err.find(said), std::string::npos) << err;
}

TEST_P(LaunchRulesTest, ExceptionProgramRunsAtEveryThrowingIndexAndPrintsInOrder) {
  RTbuffer log =
      Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, {kPrintW, kPrintH}, "exception_log");
  RayGen("throw_some");
  Ok(rtContextSetExceptionProgram(ctx_, 0, Program("log_and_print_exception")));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  TileSize({2, 2});
  const std::vector<std::array<unsigned, 3>> throwers = Throwers();
  for (bool pinned : {false, true}) {
    SCOPED_TRACE(pinned ? "tiles pinned to devices" : "tiles taken dynamically");
    if (pinned) PinTilesToDevices();
    ::testing::internal::CaptureStdout();
    RTresult r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
    std::vector<std::string> lines = Lines(::testing::internal::GetCapturedStdout());
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
    // Per throwing index, in launch-index order: the program's rtPrintf line, then the details
    // rtPrintExceptionDetails printed, which name the launch index.
    ASSERT_EQ(lines.size(), 2 * throwers.size());
    for (size_t i = 0; i < throwers.size(); ++i) {
      const auto& [x, y, code] = throwers[i];
      EXPECT_EQ(lines[2 * i], Format("exception 0x%X at [%u,%u]", code, x, y));
      EXPECT_NE(lines[2 * i + 1].find(Format("(%u, %u, 0)", x, y)), std::string::npos)
          << lines[2 * i + 1];
      EXPECT_NE(lines[2 * i + 1].find(Format("0x%X", code, 0u)), std::string::npos)
          << lines[2 * i + 1];
    }
    std::vector<std::array<unsigned, 4>> v = Contents<std::array<unsigned, 4>>(log);
    size_t next = 0;
    for (unsigned y = 0; y < kPrintH; ++y) {
      for (unsigned x = 0; x < kPrintW; ++x) {
        const bool threw =
            next < throwers.size() && throwers[next][0] == x && throwers[next][1] == y;
        const std::array<unsigned, 4> want = {threw ? throwers[next][2] : 0u, x, y,
                                              threw ? 1u : 2u};
        EXPECT_EQ(v[y * kPrintW + x], want) << "launch index (" << x << ", " << y << ")";
        next += threw;
      }
    }
  }
}

// rtPrintf output is bytes: text that is not UTF-8 comes out as it is, from every device.
TEST_P(LaunchRulesTest, PrintsThatAreNotUtf8ComeOutAsTheyAre) {
  RayGen("print_latin1");
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  TileSize({1, 1});
  ::testing::internal::CaptureStdout();
  RTresult r = rtContextLaunch2D(ctx_, 0, 3, 1);
  const std::string out = ::testing::internal::GetCapturedStdout();
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  EXPECT_EQ(out, "caf\xe9 \xff 0\ncaf\xe9 \xff 1\ncaf\xe9 \xff 2\n");
}

// A report of an exception no exception program handles is its launch index's last output: in
// launch-index order among the prints, and counted against the print buffer like them.
TEST_P(LaunchRulesTest, ExceptionReportsTakeTheirPlaceAmongPrints) {
  RayGen("print_then_throw_some");
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  Ok(rtContextSetPrintEnabled(ctx_, 1));
  TileSize({2, 2});
  ::testing::internal::CaptureStdout();
  RTresult r = rtContextLaunch2D(ctx_, 0, 4, 2);
  std::vector<std::string> lines = Lines(::testing::internal::GetCapturedStdout());
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  size_t at = 0;
  for (unsigned y = 0; y < 2; ++y) {
    for (unsigned x = 0; x < 4; ++x) {
      ASSERT_LT(at, lines.size());
      EXPECT_EQ(lines[at++], Format("[%u,%u]", x, y));
      if ((y * 4 + x) % 3 == 0) {
        ASSERT_LT(at, lines.size());
        EXPECT_NE(lines[at++].find(Format("(%u, %u, 0)", x, y)), std::string::npos);
      }
    }
  }
  EXPECT_EQ(at, lines.size());
  // A small print buffer bounds the reports too.
  Ok(rtContextSetPrintBufferSize(ctx_, 16));
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  r = rtContextLaunch2D(ctx_, 0, 4, 2);
  const std::string out = ::testing::internal::GetCapturedStdout();
  ::testing::internal::GetCapturedStderr();
  ASSERT_EQ(r, RT_SUCCESS) << Error(r);
  EXPECT_LE(out.size(), 16u) << out;
  // Reports past the print buffer are counted, not sent: the count stays whole (0, 3 and 6).
  RTsize count = 0;
  Ok(tesseraContextGetExceptionReportCount(ctx_, &count));
  EXPECT_EQ(count, 3u);
}

TEST_P(LaunchRulesTest, ExceptionsWithoutAProgramAreCountedAndReportedInOrder) {
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT4, {kPrintW, kPrintH}, "exception_log");
  RayGen("throw_some");
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, 1));
  TileSize({2, 2});
  const std::vector<std::array<unsigned, 3>> throwers = Throwers();
  for (bool pinned : {false, true}) {
    SCOPED_TRACE(pinned ? "tiles pinned to devices" : "tiles taken dynamically");
    if (pinned) PinTilesToDevices();
    // With printing on, each report is printed, in launch-index order.
    Ok(rtContextSetPrintEnabled(ctx_, 1));
    ::testing::internal::CaptureStdout();
    RTresult r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
    std::vector<std::string> lines = Lines(::testing::internal::GetCapturedStdout());
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
    RTsize count = 0;
    Ok(tesseraContextGetExceptionReportCount(ctx_, &count));
    EXPECT_EQ(count, throwers.size());
    ASSERT_EQ(lines.size(), throwers.size());
    for (size_t i = 0; i < throwers.size(); ++i) {
      const auto& [x, y, code] = throwers[i];
      EXPECT_NE(lines[i].find(Format("(%u, %u, 0)", x, y)), std::string::npos) << lines[i];
      EXPECT_NE(lines[i].find(Format("0x%X", code, 0u)), std::string::npos) << lines[i];
    }

    // With printing off, nothing reaches stdout, the count stays complete, and stderr says so.
    Ok(rtContextSetPrintEnabled(ctx_, 0));
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    r = rtContextLaunch2D(ctx_, 0, kPrintW, kPrintH);
    std::string err = ::testing::internal::GetCapturedStderr();
    std::string out = ::testing::internal::GetCapturedStdout();
    ASSERT_EQ(r, RT_SUCCESS) << Error(r);
    EXPECT_EQ(out, "");
    Ok(tesseraContextGetExceptionReportCount(ctx_, &count));
    EXPECT_EQ(count, throwers.size());
    EXPECT_NE(err.find(std::to_string(throwers.size())), std::string::npos) << err;
    EXPECT_NE(err.find("exception"), std::string::npos) << err;
  }
}

INSTANTIATE_TEST_SUITE_P(Devices, LaunchRulesTest, ::testing::ValuesIn(kRuleDeviceCases),
                         DeviceCaseName);

}  // namespace
}  // namespace tessera::testing
