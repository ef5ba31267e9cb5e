// BuildQuality: which Embree build each OptiX builder gets.
#include <gtest/gtest.h>

#include "plan.h"

namespace tessera::worker {
namespace {

// No builder gets Embree's LOW quality: its multi-threaded Morton build orders primitives
// differently from run to run, so exact ties in t resolved differently between runs and devices
// (outputs must be identical on every device set).
TEST(BuildQualityTest, EveryBuilderBuildsTheSameHierarchyEveryRun) {
  for (const char* builder :
       {"NoAccel", "Lbvh", "MedianBvh", "Bvh", "Sbvh", "Trbvh", "TriangleKdTree"}) {
    for (bool has_filter : {false, true}) {
      AccelRec a;
      a.builder = builder;
      EXPECT_NE(BuildQuality(a, has_filter), RTC_BUILD_QUALITY_LOW) << builder;
    }
  }
  AccelRec refit;
  refit.builder = "Lbvh";
  refit.properties["refit"] = "1";
  EXPECT_EQ(BuildQuality(refit, false), RTC_BUILD_QUALITY_REFIT);
  // Spatial splits (HIGH) could show an any-hit program one candidate twice.
  AccelRec sbvh;
  sbvh.builder = "Sbvh";
  EXPECT_EQ(BuildQuality(sbvh, false), RTC_BUILD_QUALITY_HIGH);
  EXPECT_EQ(BuildQuality(sbvh, true), RTC_BUILD_QUALITY_MEDIUM);
}

}  // namespace
}  // namespace tessera::worker
