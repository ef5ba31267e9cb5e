// What comes back from devices: output regions, prints, exceptions, errors, cancellation.
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "gtest/gtest.h"
#include "launch_fixture.h"
#include "tessera/rt_ext.h"
#include "tessera/scheduler/tiling.h"

namespace tessera::test {
namespace {

float Pixel(uint64_t x, uint64_t y) { return static_cast<float>(y * 100 + x); }

// Writes Pixel(x, y) into the 2D float buffer `buffer_id` (row width `width`) for every launch
// index of every tile, one region per tile row.
FakeDevice::Answer WritePixels(uint64_t buffer_id, uint64_t width) {
  return [=](const v1::LaunchRequest& r, const std::atomic<bool>&,
             const std::function<void(v1::TileResult &&)>& on_result) {
    for (const v1::Tile& t : r.tiles()) {
      v1::TileResult result;
      result.set_launch_id(r.launch_id());
      result.set_tile_index(t.index());
      for (uint64_t y = t.origin(1); y < t.origin(1) + t.size(1); ++y) {
        std::vector<float> row;
        for (uint64_t x = t.origin(0); x < t.origin(0) + t.size(0); ++x) row.push_back(Pixel(x, y));
        v1::BufferRegion* region = result.add_regions();
        region->set_buffer_id(buffer_id);
        region->set_offset((y * width + t.origin(0)) * sizeof(float));
        region->set_data(row.data(), row.size() * sizeof(float));
      }
      on_result(std::move(result));
    }
    return absl::OkStatus();
  };
}

std::vector<float> ReadFloats(RTbuffer buffer, size_t count) {
  void* p = nullptr;
  EXPECT_EQ(rtBufferMap(buffer, &p), RT_SUCCESS);
  std::vector<float> out(static_cast<float*>(p), static_cast<float*>(p) + count);
  EXPECT_EQ(rtBufferUnmap(buffer), RT_SUCCESS);
  return out;
}

TEST_F(LaunchTest, OutputRegionsLandInHostBuffers) {
  records[0]->answer = WritePixels(Id(output), kWidth);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  std::vector<float> pixels = ReadFloats(output, kWidth * kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x)
      EXPECT_EQ(pixels[y * kWidth + x], Pixel(x, y)) << x << "," << y;
  }
}

TEST_F(LaunchTest, RegionsOutsideTheBufferFailTheLaunch) {
  records[0]->answer = [&](const v1::LaunchRequest& r, const std::atomic<bool>&,
                           const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;
    v1::BufferRegion* region = result.add_regions();
    region->set_buffer_id(Id(output));
    region->set_offset(kWidth * kHeight * sizeof(float) - 2);
    region->set_data("12345678");
    on_result(std::move(result));
    return absl::OkStatus();
  };
  EXPECT_EQ(Launch(), RT_ERROR_LAUNCH_FAILED);
  std::string message = ErrorString(ctx, RT_ERROR_LAUNCH_FAILED);
  EXPECT_NE(message.find("fake0"), std::string::npos) << message;
  EXPECT_NE(message.find("outside buffer #"), std::string::npos) << message;
}

TEST_F(LaunchTest, PrintsComeOutInLaunchIndexOrder) {
  records[0]->answer = [](const v1::LaunchRequest& r, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>& on_result) {
    // Two results, each out of order: (x,y) = (1,1) (0,1) then (1,0) (0,0) with two prints.
    auto print = [](v1::TileResult* t, uint64_t x, uint64_t y, uint64_t seq, const char* text) {
      v1::PrintRecord* p = t->add_prints();
      p->add_launch_index(x);
      p->add_launch_index(y);
      p->add_launch_index(0);
      p->set_sequence(seq);
      p->set_text(text);
    };
    v1::TileResult a;
    print(&a, 1, 1, 0, "d ");
    print(&a, 0, 1, 0, "c ");
    on_result(std::move(a));
    v1::TileResult b;
    print(&b, 0, 0, 1, "a2 ");
    print(&b, 1, 0, 0, "b ");
    print(&b, 0, 0, 0, "a1 ");
    on_result(std::move(b));
    return absl::OkStatus();
  };
  ::testing::internal::CaptureStdout();
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "a1 a2 b c d ");
}

TEST_F(LaunchTest, TileErrorsFailTheLaunchWithTheirCode) {
  records[0]->answer = [](const v1::LaunchRequest& r, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;
    result.set_tile_index(0);
    result.set_error("program 'ray_gen' of program #1 crashed");
    on_result(std::move(result));
    return absl::OkStatus();
  };
  EXPECT_EQ(Launch(), RT_ERROR_LAUNCH_FAILED);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_LAUNCH_FAILED).find("crashed"), std::string::npos);

  records[0]->answer = [](const v1::LaunchRequest& r, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;
    result.set_error("module not found");
    result.set_error_code(RT_ERROR_INVALID_SOURCE);
    on_result(std::move(result));
    return absl::OkStatus();
  };
  EXPECT_EQ(Launch(), RT_ERROR_INVALID_SOURCE);
}

TEST_F(LaunchTest, DeviceLaunchFailureNamesTheDevice) {
  records[0]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>&) {
    return absl::InternalError("worker fell over");
  };
  EXPECT_EQ(Launch(), RT_ERROR_LAUNCH_FAILED);
  std::string message = ErrorString(ctx, RT_ERROR_LAUNCH_FAILED);
  EXPECT_NE(message.find("fake0"), std::string::npos) << message;
  EXPECT_NE(message.find("worker fell over"), std::string::npos) << message;
}

TEST_F(LaunchTest, RejectedDeltaIsResentWhole) {
  records[0]->apply_status = absl::InvalidArgumentError("program #9 unknown");
  EXPECT_EQ(Launch(), RT_ERROR_LAUNCH_FAILED);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_LAUNCH_FAILED).find("program #9 unknown"), std::string::npos);
  EXPECT_TRUE(records[0]->launches.empty());
  records[0]->apply_status = absl::OkStatus();
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 2u);
  EXPECT_EQ(LastDelta().sequence(), 1u);  // the failed delta did not count
  EXPECT_EQ(LastDelta().objects_size(), records[0]->deltas.front().objects_size());
  EXPECT_EQ(LastDelta().chunks_size(), 1);
}

// Devices take their deltas on threads of their own: what one throws becomes the launch's
// error, not std::terminate.
TEST_F(LaunchTest, ADeviceThatThrowsTakingItsDeltaFailsTheLaunch) {
  records[0]->apply_throws = true;
  EXPECT_EQ(Launch(), RT_ERROR_MEMORY_ALLOCATION_FAILED);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_MEMORY_ALLOCATION_FAILED).find("fake0"), std::string::npos);
  records[0]->apply_throws = false;
  EXPECT_EQ(Launch(), RT_SUCCESS);
}

int g_timeout_calls = 0;
int g_running_during_callback = -1;
RTcontext g_callback_context = nullptr;

// Cancels once the device runs tiles: a cancel while the launch still ships its state ends the
// launch before any tile (on a loaded machine the first poll can come that early).
std::atomic<bool> g_device_started{false};
int StopOnceTheDeviceRuns() {
  ++g_timeout_calls;
  if (!g_device_started.load()) return 0;
  rtContextGetRunningState(g_callback_context, &g_running_during_callback);
  return 1;
}

TEST_F(LaunchTest, TimeoutCallbackCancelsTheLaunch) {
  g_timeout_calls = 0;
  g_callback_context = ctx;
  std::atomic<bool> saw_cancel{false};
  g_device_started = false;
  records[0]->answer = [&](const v1::LaunchRequest&, const std::atomic<bool>& cancel,
                           const std::function<void(v1::TileResult &&)>&) {
    g_device_started = true;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!cancel.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    saw_cancel = cancel.load();
    return absl::OkStatus();
  };
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, &StopOnceTheDeviceRuns, 0.01), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_TIMEOUT_CALLBACK);
  EXPECT_TRUE(saw_cancel.load());
  EXPECT_GE(g_timeout_calls, 1);
  EXPECT_EQ(g_running_during_callback, 1);
  int running = -1;
  ASSERT_EQ(rtContextGetRunningState(ctx, &running), RT_SUCCESS);
  EXPECT_EQ(running, 0);
  EXPECT_NE(ErrorString(ctx, RT_TIMEOUT_CALLBACK).find("timeout callback"), std::string::npos);
  // Without a callback the same device finishes normally.
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, nullptr, 0), RT_SUCCESS);
  records[0]->answer = nullptr;
  EXPECT_EQ(Launch(), RT_SUCCESS);
}

RTbuffer g_shrink_output = nullptr;
RTresult g_set_devices_result = RT_SUCCESS;
int g_meddling_calls = 0;

// A callback that meddles: shrinks the buffer devices are writing and tries to swap devices.
int MeddleThenStop() {
  if (++g_meddling_calls == 1) {
    rtBufferSetSize2D(g_shrink_output, 1, 1);
    const int device = 0;
    g_set_devices_result = rtContextSetDevices(g_callback_context, 1, &device);
    return 0;
  }
  return 1;
}

TEST_F(LaunchTest, TimeoutCallbackCannotPullTheRugFromDevices) {
  g_callback_context = ctx;
  g_shrink_output = output;
  g_meddling_calls = 0;
  const uint64_t id = Id(output);
  records[0]->answer = [id](const v1::LaunchRequest& r, const std::atomic<bool>& cancel,
                            const std::function<void(v1::TileResult &&)>& on_result) {
    while (!cancel.load()) {
      v1::TileResult result;
      v1::BufferRegion* region = result.add_regions();
      region->set_buffer_id(id);
      region->set_offset(64);
      region->set_data(std::string(64, 'z'));
      on_result(std::move(result));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return absl::OkStatus();
  };
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, &MeddleThenStop, 0.005), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_TIMEOUT_CALLBACK);
  EXPECT_EQ(g_set_devices_result, RT_ERROR_INVALID_CONTEXT);
  EXPECT_GE(g_meddling_calls, 2);
  RTsize w = 0, h = 0;
  ASSERT_EQ(rtBufferGetSize2D(output, &w, &h), RT_SUCCESS);
  EXPECT_EQ(w * h, 1u);
}

RTbuffer g_grow_output = nullptr;
std::atomic<bool> g_grown{false};
int GrowOutput() {
  if (!g_grown.load()) {
    rtBufferSetSize2D(g_grow_output, 64, 64);  // bigger than the fixture's 8x4
    g_grown = true;
  }
  return 0;
}

// A buffer the timeout callback grows mid-launch has a new layout: what devices wrote for the old
// one would land on the wrong elements, so the launch drops it and says so.
TEST_F(LaunchTest, BufferGrownByTheTimeoutCallbackFailsTheLaunchNamingIt) {
  g_grow_output = output;
  g_grown = false;
  const uint64_t id = Id(output);
  records[0]->answer = [id](const v1::LaunchRequest&, const std::atomic<bool>& cancel,
                            const std::function<void(v1::TileResult &&)>& on_result) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!g_grown.load() && !cancel.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    v1::TileResult result;
    v1::BufferRegion* region = result.add_regions();
    region->set_buffer_id(id);
    region->set_offset(0);
    region->set_data(std::string(4 * kWidth, 'z'));  // the old first row
    on_result(std::move(result));
    return absl::OkStatus();
  };
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, &GrowOutput, 0.001), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE)
                .find("was resized or reformatted during the launch (by the timeout callback)"),
            std::string::npos)
      << ErrorString(ctx, RT_ERROR_INVALID_VALUE);
  void* p = nullptr;
  ASSERT_EQ(rtBufferMap(output, &p), RT_SUCCESS);
  EXPECT_EQ(static_cast<const float*>(p)[0], 0.f);  // the grown buffer's zeros, not 'zzzz'
  ASSERT_EQ(rtBufferUnmap(output), RT_SUCCESS);
}

// What the timeout callback does to a buffer after two devices' results were applied.
enum class Meddle { kShrink, kEmpty, kDestroy, kReformatAndGrow };
Meddle g_meddle = Meddle::kShrink;
RTbuffer g_meddle_buffer = nullptr;
std::atomic<int> g_devices_done{0};
int g_calls_after_done = 0;
constexpr uint64_t kMeddleFloats = 2 * (uint64_t{4} << 20) / sizeof(float);  // two 4 MiB chunks

int MeddleAfterResults() {
  if (g_devices_done.load() < 2) return 0;
  if (++g_calls_after_done == 3) {  // the finished devices' batches are applied by now
    switch (g_meddle) {
      case Meddle::kShrink:
        rtBufferSetSize1D(g_meddle_buffer, 1);
        break;
      case Meddle::kEmpty:
        rtBufferSetSize1D(g_meddle_buffer, 0);
        break;
      case Meddle::kDestroy:
        rtBufferDestroy(g_meddle_buffer);
        break;
      case Meddle::kReformatAndGrow:  // more, smaller elements, the same bytes and more
        rtBufferSetFormat(g_meddle_buffer, RT_FORMAT_BYTE);
        rtBufferSetSize1D(g_meddle_buffer, 2 * kMeddleFloats * sizeof(float));
        break;
    }
    return 0;
  }
  return g_calls_after_done > 3;
}

// Devices 0 and 1 race on element 0 (device 0 also writes the second chunk alone) and finish;
// device 2 runs until cancelled, then writes past the buffer's original bytes. In between the
// timeout callback meddles with the buffer: the launch reports, never reads the old layout.
class MeddleTest : public LaunchTest {
 protected:
  void LaunchAndMeddle(Meddle meddle) {
    UseFakes(3);
    ASSERT_EQ(tesseraContextSetRaceCheck(ctx, 1), RT_SUCCESS);
    RTbuffer b = nullptr;
    ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT_OUTPUT, &b), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT), RT_SUCCESS);
    ASSERT_EQ(rtBufferSetSize1D(b, kMeddleFloats), RT_SUCCESS);
    BindObject(ctx_var("meddled"), b);
    const uint64_t id = Id(b);
    g_meddle = meddle;
    g_meddle_buffer = b;
    g_devices_done = 0;
    g_calls_after_done = 0;
    auto region = [id](v1::TileResult& r, uint64_t offset, float value) {
      v1::BufferRegion* region = r.add_regions();
      region->set_buffer_id(id);
      region->set_offset(offset);
      region->set_data(&value, sizeof(value));
    };
    for (int d = 0; d < 3; ++d) {
      auto calls = std::make_shared<int>(0);
      records[d]->answer = [=](const v1::LaunchRequest&, const std::atomic<bool>& cancel,
                               const std::function<void(v1::TileResult &&)>& on_result) {
        v1::TileResult result;
        if (d < 2 && (*calls)++ == 0) {
          region(result, 0, 1.f + d);
          if (d == 0) region(result, uint64_t{4} << 20, 5.f);
          on_result(std::move(result));
          ++g_devices_done;
          return absl::OkStatus();
        }
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (!cancel.load() && std::chrono::steady_clock::now() < deadline) {
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        if (d == 2) region(result, kMeddleFloats * sizeof(float) + 64, 7.f);  // past the old bytes
        on_result(std::move(result));
        return absl::OkStatus();
      };
    }
    ASSERT_EQ(rtContextSetTimeoutCallback(ctx, &MeddleAfterResults, 0.005), RT_SUCCESS);
    EXPECT_EQ(Launch(64, 64), RT_TIMEOUT_CALLBACK);
    EXPECT_GE(g_calls_after_done, 4);
  }
};

TEST_F(MeddleTest, TimeoutCallbackMayShrinkAWrittenBuffer) { LaunchAndMeddle(Meddle::kShrink); }
TEST_F(MeddleTest, TimeoutCallbackMayEmptyARacedBuffer) { LaunchAndMeddle(Meddle::kEmpty); }
TEST_F(MeddleTest, TimeoutCallbackMayDestroyARacedBuffer) { LaunchAndMeddle(Meddle::kDestroy); }
TEST_F(MeddleTest, TimeoutCallbackMayReformatARaceCheckedBuffer) {
  LaunchAndMeddle(Meddle::kReformatAndGrow);
}

TEST_F(LaunchTest, ExceptionReportsAreCounted) {
  records[0]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;
    for (int i = 0; i < 3; ++i) {
      v1::ExceptionReport* e = result.add_exceptions();
      e->set_code(RT_EXCEPTION_STACK_OVERFLOW);
    }
    on_result(std::move(result));
    return absl::OkStatus();
  };
  ASSERT_EQ(Launch(), RT_SUCCESS);
  RTsize count = 0;
  ASSERT_EQ(tesseraContextGetExceptionReportCount(ctx, &count), RT_SUCCESS);
  EXPECT_EQ(count, 3u);
}

// Writes Pixel(x, y) + offset like WritePixels, but as a real device does: one region per
// tile row in the call's final result, after the tiles.
FakeDevice::Answer WritePixelsFinal(uint64_t buffer_id, uint64_t width,
                                    std::shared_ptr<std::atomic<int>> launch) {
  return [=](const v1::LaunchRequest& r, const std::atomic<bool>&,
             const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult final_result;
    final_result.set_tile_index(kFinalTileIndex);
    for (const v1::Tile& t : r.tiles()) {
      for (uint64_t y = t.origin(1); y < t.origin(1) + t.size(1); ++y) {
        std::vector<float> row;
        for (uint64_t x = t.origin(0); x < t.origin(0) + t.size(0); ++x) {
          row.push_back(Pixel(x, y) + 1000.0f * launch->load());
        }
        v1::BufferRegion* region = final_result.add_regions();
        region->set_buffer_id(buffer_id);
        region->set_offset((y * width + t.origin(0)) * sizeof(float));
        region->set_data(row.data(), row.size() * sizeof(float));
      }
    }
    on_result(std::move(final_result));
    return absl::OkStatus();
  };
}

int WrongPixels(const std::vector<float>& pixels, RTsize width, RTsize height, int launch) {
  int wrong = 0;
  for (RTsize y = 0; y < height; ++y) {
    for (RTsize x = 0; x < width; ++x) {
      wrong += pixels[y * width + x] != Pixel(x, y) + 1000.0f * launch;
    }
  }
  return wrong;
}

TEST_F(LaunchTest, TwoDevicesSplitTilesAndMergeOutputs) {
  UseFakes(2);
  const RTsize width = 128;
  const RTsize height = 64;
  ASSERT_EQ(rtBufferSetSize2D(output, width, height), RT_SUCCESS);
  auto launch = std::make_shared<std::atomic<int>>(0);
  for (int d = 0; d < 2; ++d) records[d]->answer = WritePixelsFinal(Id(output), width, launch);
  for (int l = 0; l < 3; ++l) {
    launch->store(l);
    ASSERT_EQ(Launch(width, height), RT_SUCCESS);
    EXPECT_EQ(WrongPixels(ReadFloats(output, width * height), width, height, l), 0)
        << "launch " << l;
  }
  // Every tile ran exactly once per launch, on one device or the other.
  size_t tiles = 0;
  for (int d = 0; d < 2; ++d) {
    for (const v1::LaunchRequest& r : records[d]->launches) tiles += r.tiles_size();
  }
  EXPECT_EQ(tiles % 3, 0u);
  EXPECT_EQ(tiles / 3, scheduler::MakeTiles({width, height}, {16, 16}).size());
  // Both devices received the full state, each in its own session.
  EXPECT_EQ(records[0]->deltas.front().objects_size(), records[1]->deltas.front().objects_size());
  EXPECT_NE(records[0]->deltas.front().session_id(), records[1]->deltas.front().session_id());
}

TEST_F(LaunchTest, TileSizeCanBeSet) {
  const RTsize size[2] = {4, 2};
  ASSERT_EQ(tesseraContextSetTileSize(ctx, 2, size), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  size_t tiles = 0;
  for (const v1::LaunchRequest& r : records[0]->launches) {
    for (const v1::Tile& t : r.tiles()) {
      EXPECT_LE(t.size(0), 4u);
      EXPECT_LE(t.size(1), 2u);
      ++tiles;
    }
  }
  EXPECT_EQ(tiles, ((kWidth + 3) / 4) * ((kHeight + 1) / 2));
  const RTsize zero[2] = {0, 1};
  EXPECT_EQ(tesseraContextSetTileSize(ctx, 2, zero), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraContextSetTileSize(ctx, 4, size), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraContextSetTileSize(ctx, 0, nullptr), RT_SUCCESS);
}

// Three fakes, the middle one instant and the others slow (dynamic assignment gives the instant
// one tiles of the others), a 64x64 launch in 8x8 tiles; returns whether every tile i ran on
// device i mod 3, over two launches.
bool TilesStayOnTheirDevices(RTcontext ctx,
                             std::vector<std::shared_ptr<FakeDevice::Record>>& records) {
  const RTsize tile[2] = {8, 8};
  EXPECT_EQ(tesseraContextSetTileSize(ctx, 2, tile), RT_SUCCESS);
  for (int d : {0, 2}) {
    records[d]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      return absl::OkStatus();
    };
  }
  bool stayed = true;
  for (int l = 0; l < 2; ++l) {
    for (int d = 0; d < 3; ++d) records[d]->launches.clear();
    EXPECT_EQ(rtContextLaunch2D(ctx, 0, 64, 64), RT_SUCCESS);
    for (int d = 0; d < 3; ++d) {
      for (const v1::LaunchRequest& r : records[d]->launches) {
        for (const v1::Tile& t : r.tiles()) stayed &= t.index() % 3 == static_cast<uint32_t>(d);
      }
    }
  }
  return stayed;
}

RTbuffer MakeGpuLocal(RTcontext ctx) {
  RTbuffer local = nullptr;
  EXPECT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, &local), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetFormat(local, RT_FORMAT_FLOAT), RT_SUCCESS);
  EXPECT_EQ(rtBufferSetSize1D(local, 1), RT_SUCCESS);
  return local;
}

TEST_F(LaunchTest, GpuLocalBuffersKeepTilesOnTheirDevice) {
  UseFakes(3);
  BindObject(ctx_var("local"), MakeGpuLocal(ctx));
  EXPECT_TRUE(TilesStayOnTheirDevices(ctx, records));
}

// Programs reach a buffer by id too: once the application took a GPU_LOCAL buffer's id, launches
// keep their tiles on their devices even though no variable names the buffer.
TEST_F(LaunchTest, AGpuLocalBufferReachedByIdKeepsTilesOnTheirDevice) {
  UseFakes(3);
  Id(MakeGpuLocal(ctx));
  EXPECT_TRUE(TilesStayOnTheirDevices(ctx, records));
}

// A GPU_LOCAL buffer that no launch can reach (no variable names it, its id was never taken)
// leaves launches to dynamic assignment: the instant device takes tiles of the slow ones.
TEST_F(LaunchTest, AnUnreachableGpuLocalBufferLeavesTilesToDynamicAssignment) {
  UseFakes(3);
  MakeGpuLocal(ctx);
  EXPECT_FALSE(TilesStayOnTheirDevices(ctx, records));
}

TEST_F(LaunchTest, LostDeviceTilesRunOnTheOthers) {
  UseFakes(2);
  const RTsize width = 128;
  const RTsize height = 64;
  ASSERT_EQ(rtBufferSetSize2D(output, width, height), RT_SUCCESS);
  auto launch = std::make_shared<std::atomic<int>>(0);
  FakeDevice::Answer write = WritePixelsFinal(Id(output), width, launch);
  records[0]->answer = [write](const v1::LaunchRequest& r, const std::atomic<bool>& cancel,
                               const std::function<void(v1::TileResult &&)>& on_result) {
    // Slow enough that the other device's thread surely takes a batch (and fails it).
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return write(r, cancel, on_result);
  };
  records[1]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>&) {
    return absl::UnavailableError("worker 127.0.0.1:1 went away");
  };
  testing::internal::CaptureStderr();
  ASSERT_EQ(Launch(width, height), RT_SUCCESS);
  std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("fake1"), std::string::npos) << warning;
  EXPECT_NE(warning.find("went away"), std::string::npos) << warning;
  // No GPU_LOCAL buffer here, so none is said to be gone.
  EXPECT_EQ(warning.find("GPU_LOCAL"), std::string::npos) << warning;
  EXPECT_EQ(WrongPixels(ReadFloats(output, width * height), width, height, 0), 0);
  // The lost device is gone for good here (a real one would be started again).
  EXPECT_TRUE(records[1]->destroyed);
  launch->store(1);
  ASSERT_EQ(Launch(width, height), RT_SUCCESS);
  EXPECT_EQ(WrongPixels(ReadFloats(output, width * height), width, height, 1), 0);
}

TEST_F(LaunchTest, EveryDeviceLostIsConnectionFailed) {
  UseFakes(2);
  for (int d = 0; d < 2; ++d) {
    records[d]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>&) {
      return absl::DeadlineExceededError("worker sent nothing for 10s");
    };
  }
  testing::internal::CaptureStderr();
  EXPECT_EQ(Launch(), RT_ERROR_CONNECTION_FAILED);
  testing::internal::GetCapturedStderr();
  std::string message = ErrorString(ctx, RT_ERROR_CONNECTION_FAILED);
  EXPECT_NE(message.find("every device was lost"), std::string::npos) << message;
  // Nothing is left to launch on: a clear error again, not a hang.
  EXPECT_EQ(Launch(), RT_ERROR_CONNECTION_FAILED);
}

TEST_F(LaunchTest, CrashedDeviceFailsTheLaunchNamingDeviceAndProgram) {
  UseFakes(2);
  for (int d = 0; d < 2; ++d) {
    records[d]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>&) {
      return absl::AbortedError(
          "worker process unix:/w.sock crashed: signal 11 (SIGSEGV) in closest hit program 'f'");
    };
  }
  testing::internal::CaptureStderr();
  EXPECT_EQ(Launch(), RT_ERROR_LAUNCH_FAILED);
  testing::internal::GetCapturedStderr();
  std::string message = ErrorString(ctx, RT_ERROR_LAUNCH_FAILED);
  EXPECT_NE(message.find("device 'fake"), std::string::npos) << message;
  EXPECT_NE(message.find("closest hit program 'f'"), std::string::npos) << message;
}

// Batching by measurement (api/src/auto_batching.h), through the launch path: each call reports
// one rtTrace per launch index and, when it ran batched, how many first rays packets answered.
// With TESSERA_BATCHING=auto the entry point starts on single rays, tries packets after a launch
// of one ray per index and keeps them while packets answer; 1 batches every launch, 0 or unset
// none.
FakeDevice::Answer ReportTraces(double rays_per_index, bool packets_answer) {
  return [=](const v1::LaunchRequest& r, const std::atomic<bool>&,
             const std::function<void(v1::TileResult &&)>& on_result) {
    uint64_t indices = 0;
    for (const v1::Tile& t : r.tiles()) {
      uint64_t n = 1;
      for (uint64_t s : t.size()) n *= s;
      indices += n;
    }
    v1::TileResult result;
    result.set_launch_id(r.launch_id());
    result.set_tile_index(0xFFFFFFFFu);
    result.set_traces(static_cast<uint64_t>(rays_per_index * static_cast<double>(indices)));
    result.set_packet_answers(r.batched() && packets_answer ? indices : 0);
    on_result(std::move(result));
    return absl::OkStatus();
  };
}

class BatchingChoiceTest : public LaunchTest {
 protected:
  const test::ScopedEnv batching_{"TESSERA_BATCHING", "auto"};
  // Whether each of `launches` launches was sent batched.
  std::vector<bool> Batched(int launches) {
    const size_t before = records[0]->launches.size();
    for (int k = 0; k < launches; ++k) EXPECT_EQ(Launch(), RT_SUCCESS);
    std::vector<bool> out;
    for (size_t i = before; i < records[0]->launches.size(); ++i) {
      out.push_back(records[0]->launches[i].batched());
    }
    return out;
  }
};

TEST_F(BatchingChoiceTest, PrimaryRaysThatPacketsAnswerAreBatchedFromTheSecondLaunch) {
  records[0]->answer = ReportTraces(1.0, true);
  EXPECT_EQ(Batched(4), (std::vector<bool>{false, true, true, true}));
}

TEST_F(BatchingChoiceTest, ATryThatPacketsDoNotAnswerGoesBackToSingleRaysForGood) {
  records[0]->answer = ReportTraces(1.0, false);
  EXPECT_EQ(Batched(4), (std::vector<bool>{false, true, false, false}));
  records[0]->answer = ReportTraces(1.0, true);
  EXPECT_EQ(Batched(2), (std::vector<bool>{false, false}));
}

TEST_F(BatchingChoiceTest, ManyRaysPerIndexStayOnSingleRays) {
  records[0]->answer = ReportTraces(8.0, true);
  EXPECT_EQ(Batched(3), (std::vector<bool>{false, false, false}));
}

TEST_F(BatchingChoiceTest, TheVariableOverridesTheChoice) {
  records[0]->answer = ReportTraces(1.0, true);
  setenv("TESSERA_BATCHING", "0", 1);
  EXPECT_EQ(Batched(3), (std::vector<bool>{false, false, false}));
  setenv("TESSERA_BATCHING", "1", 1);
  EXPECT_EQ(Batched(2), (std::vector<bool>{true, true}));
  unsetenv("TESSERA_BATCHING");  // single rays, as before there was a choice
  EXPECT_EQ(Batched(2), (std::vector<bool>{false, false}));
}

// A launch that fails teaches nothing: the next launch is chosen as if it had not run.
TEST_F(BatchingChoiceTest, AFailedLaunchDoesNotCount) {
  records[0]->answer = [](const v1::LaunchRequest&, const std::atomic<bool>&,
                          const std::function<void(v1::TileResult &&)>&) {
    return absl::InternalError("device broke");
  };
  EXPECT_NE(Launch(), RT_SUCCESS);
  records[0]->answer = ReportTraces(1.0, true);
  EXPECT_EQ(Batched(2), (std::vector<bool>{false, true}));
}

}  // namespace
}  // namespace tessera::test
