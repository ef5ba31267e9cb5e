// Large batches of results: the host copies them into its buffers on several threads, slice by
// slice (LaunchGather::CopyRuns). What must survive that: the order of runs that overlap, runs
// that cross slice boundaries, and race reports.
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "launch_fixture.h"
#include "tessera/rt_ext.h"

namespace tessera::test {
namespace {

// 2 Mi floats, 8 MiB: above the size from which a batch is copied on several threads (4 MiB),
// and eight of its 1 MiB slices.
constexpr RTsize kLargeWidth = 1024, kLargeHeight = 2048;
constexpr uint64_t kFloats = uint64_t{kLargeWidth} * kLargeHeight;

// Adds to `result` a region of `buffer_id` holding `value` in floats [first, first + count),
// as one packed run.
void AddRun(v1::TileResult& result, uint64_t buffer_id, uint64_t first, uint64_t count,
            float value) {
  v1::BufferRegion* region = result.add_regions();
  region->set_buffer_id(buffer_id);
  region->set_offset(0);
  region->add_run_offsets(first * sizeof(float));
  region->add_run_sizes(count * sizeof(float));
  const std::vector<float> values(count, value);
  region->set_data(values.data(), count * sizeof(float));
}

std::vector<float> ReadAll(RTbuffer b) {
  void* p = nullptr;
  EXPECT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
  std::vector<float> out(static_cast<float*>(p), static_cast<float*>(p) + kFloats);
  EXPECT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  return out;
}

class GatherCopyTest : public LaunchTest {
 protected:
  void SetUp() override {
    LaunchTest::SetUp();
    ASSERT_EQ(rtBufferSetSize2D(output, kLargeWidth, kLargeHeight), RT_SUCCESS);
  }
};

// One call sends the whole buffer, then (as a later write epoch would) two runs over parts of
// it, the first across a slice boundary, then one over part of that: each element holds the last
// value sent for it.
TEST_F(GatherCopyTest, OverlappingRunsLandInTheOrderTheyCame) {
  const uint64_t id = Id(output);
  constexpr uint64_t kSlice = (uint64_t{1} << 20) / sizeof(float);
  constexpr uint64_t kAcrossBegin = kSlice - 100, kAcrossEnd = 3 * kSlice + 7;
  constexpr uint64_t kLastBegin = 2 * kSlice - 5, kLastEnd = 2 * kSlice + 5;
  constexpr uint64_t kTailBegin = kFloats - 3;
  auto calls = std::make_shared<int>(0);
  records[0]->answer = [=](const v1::LaunchRequest&, const std::atomic<bool>&,
                           const std::function<void(v1::TileResult &&)>& on_result) {
    if ((*calls)++ > 0) return absl::OkStatus();  // one call answers for the launch
    v1::TileResult whole, later, last;
    AddRun(whole, id, 0, kFloats, 1.f);
    AddRun(later, id, kAcrossBegin, kAcrossEnd - kAcrossBegin, 2.f);
    AddRun(later, id, kTailBegin, kFloats - kTailBegin, 4.f);
    AddRun(last, id, kLastBegin, kLastEnd - kLastBegin, 3.f);
    on_result(std::move(whole));
    on_result(std::move(later));
    on_result(std::move(last));
    return absl::OkStatus();
  };
  const RTresult launched = Launch(kLargeWidth, kLargeHeight);
  ASSERT_EQ(launched, RT_SUCCESS) << ErrorString(ctx, launched);
  const std::vector<float> v = ReadAll(output);
  size_t wrong = 0;
  for (uint64_t i = 0; i < kFloats; ++i) {
    float want = 1.f;
    if (i >= kAcrossBegin && i < kAcrossEnd) want = 2.f;
    if (i >= kLastBegin && i < kLastEnd) want = 3.f;
    if (i >= kTailBegin) want = 4.f;
    if (v[i] != want && wrong++ < 5) ADD_FAILURE() << "element " << i << ": " << v[i];
  }
  EXPECT_EQ(wrong, 0u);
  unsigned long long sent = 0, received = 0;
  ASSERT_EQ(tesseraContextGetTransferStats(ctx, &sent, &received), RT_SUCCESS);
  EXPECT_EQ(received,
            (kFloats + (kAcrossEnd - kAcrossBegin) + 3 + (kLastEnd - kLastBegin)) * sizeof(float));
}

// Two devices each send a large batch; both write one element in a middle slice, with different
// values: the race check reports exactly that element, as it does for small batches.
TEST_F(GatherCopyTest, RacesInLargeBatchesAreReported) {
  UseFakes(2);
  ASSERT_EQ(tesseraContextSetRaceCheck(ctx, 1), RT_SUCCESS);
  // A GPU_LOCAL buffer keeps tile i on device i mod 2, so both devices get calls (dynamic
  // assignment may hand every tile to one of two instant fakes).
  RTbuffer pin = nullptr;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, &pin), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(pin, RT_FORMAT_FLOAT), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(pin, 1), RT_SUCCESS);
  BindObject(ctx_var("pin"), pin);
  const uint64_t id = Id(output);
  constexpr uint64_t kRaced = kFloats / 2 + 12345;
  for (int d = 0; d < 2; ++d) {
    auto calls = std::make_shared<int>(0);
    records[d]->answer = [=](const v1::LaunchRequest&, const std::atomic<bool>&,
                             const std::function<void(v1::TileResult &&)>& on_result) {
      if ((*calls)++ > 0) return absl::OkStatus();
      v1::TileResult result;
      // Device 0 the first half and device 1 the second, each 4 MiB; both write kRaced.
      const uint64_t begin = d == 0 ? 0 : kFloats / 2;
      AddRun(result, id, begin, kFloats / 2, 10.f + d);
      if (d == 0) AddRun(result, id, kRaced, 1, 20.f);
      on_result(std::move(result));
      return absl::OkStatus();
    };
  }
  ::testing::internal::CaptureStderr();
  const RTresult launched = Launch(kLargeWidth, kLargeHeight);
  ASSERT_EQ(launched, RT_SUCCESS) << ErrorString(ctx, launched);
  const std::string report = ::testing::internal::GetCapturedStderr();
  RTsize races = 0;
  ASSERT_EQ(tesseraContextGetRaceCount(ctx, &races), RT_SUCCESS);
  EXPECT_EQ(races, 1u) << report;
  const std::string element = "element (" + std::to_string(kRaced % kLargeWidth) + ", " +
                              std::to_string(kRaced / kLargeWidth) + ", 0)";
  EXPECT_NE(report.find(element), std::string::npos) << report;
  const std::vector<float> v = ReadAll(output);
  EXPECT_EQ(v[0], 10.f);
  EXPECT_EQ(v[kFloats - 1], 11.f);
  EXPECT_TRUE(v[kRaced] == 20.f || v[kRaced] == 11.f) << v[kRaced];
}

}  // namespace
}  // namespace tessera::test
