// The OptiX 3 guide's table "Which OptiX calls are supported where?", cell by cell: each device
// call is made from each program kind; allowed cells launch, forbidden ones fail with
// RT_ERROR_LAUNCH_FAILED and a message naming the call.
#include <string>

#include "rt_fixture.h"

namespace tessera::testing {
namespace {

constexpr char kModule[] = "calls_programs";

enum Kind {
  kRayGen,
  kException,
  kClosestHit,
  kAnyHit,
  kMiss,
  kIntersection,
  kBounds,
  kVisit,
  kKinds
};
const char* const kKindNames[] = {"RayGeneration", "Exception",    "ClosestHit",  "AnyHit",
                                  "Miss",          "Intersection", "BoundingBox", "Visit"};

struct Row {
  const char* call;      // program name prefix in calls_programs.cu
  const char* api_name;  // what the error message names
  bool allowed[kKinds];  // RG, Exc, CH, AH, Miss, IS, BB, Visit
};

// The guide's table.
const Row kTable[] = {
    {"transform", "rtTransform", {false, false, true, true, true, true, true, true}},
    {"trace", "rtTrace", {true, false, true, false, true, false, false, false}},
    {"throw", "rtThrow", {true, false, true, true, true, true, true, true}},
    {"print", "rtPrintf", {true, true, true, true, true, true, true, true}},
    {"terminate", "rtTerminateRay", {false, false, false, true, true, false, false, false}},
    {"ignore", "rtIgnoreIntersection", {false, false, false, true, false, false, false, false}},
    {"intersect_child",
     "rtIntersectChild",
     {false, false, false, false, false, false, false, true}},
    {"potential",
     "rtPotentialIntersection",
     {false, false, false, false, false, true, false, false}},
    {"report", "rtReportIntersection", {false, false, false, false, false, true, false, false}},
};

class CallsWhereTest : public RtFixture,
                       public ::testing::WithParamInterface<std::tuple<int, int>> {};

TEST_P(CallsWhereTest, CallIsAllowedExactlyWhereTheTableSays) {
  const Row& row = kTable[std::get<0>(GetParam())];
  const Kind kind = static_cast<Kind>(std::get<1>(GetParam()));
  std::string prefix = row.call;
  auto probe = [&](Kind k, const char* filler) {
    if (k != kind) return Program(kModule, filler);
    const char* suffix = k == kIntersection ? "_intersect"
                         : k == kBounds     ? "_bounds"
                         : k == kVisit      ? "_visit"
                                            : "_plain";
    return Program(kModule, prefix + suffix);
  };
  Ok(rtContextSetEntryPointCount(ctx_, 1));
  Ok(rtContextSetRayTypeCount(ctx_, 1));
  Ok(rtContextSetExceptionEnabled(ctx_, RT_EXCEPTION_USER, kind == kException ? 1 : 0));
  Ok(rtContextSetRayGenerationProgram(ctx_, 0,
                                      kind == kRayGen      ? probe(kRayGen, "")
                                      : kind == kException ? Program(kModule, "throw_camera")
                                                           : Program(kModule, "camera")));
  Ok(rtContextSetExceptionProgram(ctx_, 0, probe(kException, "nothing")));
  Ok(rtContextSetMissProgram(ctx_, 0, probe(kMiss, "nothing")));
  // The probe ray hits the unit box unless the probe is the miss program.
  Instance i = MakeInstance(probe(kIntersection, "plain_intersect"), probe(kBounds, "plain_bounds"),
                            1, probe(kClosestHit, "nothing"), probe(kAnyHit, "nothing"));
  if (kind == kMiss) Ok(rtGeometrySetPrimitiveCount(i.geometry, 0));
  // The probe ray reaches the geometry through a selector of one child.
  RTselector selector = nullptr;
  Ok(rtSelectorCreate(ctx_, &selector));
  Ok(rtSelectorSetVisitProgram(selector, probe(kVisit, "visit_plain")));
  Ok(rtSelectorSetChildCount(selector, 1));
  Ok(rtSelectorSetChild(selector, 0, i.group));
  RTvariable top = nullptr;
  Ok(rtContextDeclareVariable(ctx_, "top_object", &top));
  Ok(rtVariableSetObject(top, selector));
  RTresult r = rtContextLaunch1D(ctx_, 0, 1);
  if (row.allowed[kind]) {
    EXPECT_EQ(r, RT_SUCCESS) << row.api_name << " in " << kKindNames[kind] << ": " << Error(r);
  } else {
    EXPECT_EQ(r, RT_ERROR_LAUNCH_FAILED) << row.api_name << " in " << kKindNames[kind];
    EXPECT_NE(Error(r).find(row.api_name), std::string::npos) << Error(r);
  }
}

INSTANTIATE_TEST_SUITE_P(Table, CallsWhereTest,
                         ::testing::Combine(::testing::Range(0,
                                                             static_cast<int>(std::size(kTable))),
                                            ::testing::Range(0, static_cast<int>(kKinds))),
                         [](const ::testing::TestParamInfo<std::tuple<int, int>>& info) {
                           return std::string(kTable[std::get<0>(info.param)].call) + "_in_" +
                                  kKindNames[std::get<1>(info.param)];
                         });

}  // namespace
}  // namespace tessera::testing
