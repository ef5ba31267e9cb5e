// Probes of the multi-device buffer rules at their edges: pointers across device-set changes,
// race checking without false positives, and GPU_LOCAL accumulation when a worker dies between
// launches. (Probes of device pointers themselves are in multi_device_pointers_test.cc.)
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "multi_device_fixture.h"
#include "worker_processes.h"

namespace tessera::testing {
namespace {

constexpr RTsize kCount = 64;
constexpr RTsize kTile = 8;  // 8 tiles: with pinned tiles, tile t runs on device t mod N

// ---- Race checking: no false positives, elements named by their coordinates ------------------

class RaceProbeTest : public MultiDeviceParamTest {
 protected:
  void SetUp() override {
    MultiDeviceParamTest::SetUp();
    Ok(tesseraContextSetRaceCheck(ctx_, 1));
  }
  // Launches and returns the race count; the report on stderr goes to `report`.
  RTsize Races1D(RTsize n, std::string* report) {
    ::testing::internal::CaptureStderr();
    Launch1D(n);
    *report = ::testing::internal::GetCapturedStderr();
    RTsize races = 0;
    EXPECT_EQ(tesseraContextGetRaceCount(ctx_, &races), RT_SUCCESS);
    return races;
  }
};

TEST_P(RaceProbeTest, OneValueWrittenByEveryDeviceIsNoRace) {
  RayGen("same_on_first");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "contested");
  PinTilesToDevices();
  TileSize({kTile});
  std::string report;
  for (unsigned salt : {5u, 6u}) {
    SetUint("salt", salt);
    EXPECT_EQ(Races1D(kCount, &report), 0u) << report;
    EXPECT_EQ(report.find("race check"), std::string::npos) << report;
  }
}

TEST_P(RaceProbeTest, RaceInA2DBufferNamesTheElementsCoordinates) {
  RayGen("race_on_element_3_2");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {16, 8}, "contested2");
  PinTilesToDevices();
  TileSize({4, 4});
  SetUint("salt", 3);
  ::testing::internal::CaptureStderr();
  Launch2D(16, 8);
  const std::string report = ::testing::internal::GetCapturedStderr();
  RTsize races = 0;
  Ok(tesseraContextGetRaceCount(ctx_, &races));
  if (devices() == 1) {
    EXPECT_EQ(races, 0u) << report;
    return;
  }
  EXPECT_EQ(races, 1u) << report;
  EXPECT_NE(report.find("buffer 'contested2' element (3, 2, 0)"), std::string::npos) << report;

  // The next launch without a race reports none.
  RayGen("write_every_index");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {16, 8}, "image");
  Launch2D(16, 8);
  Ok(tesseraContextGetRaceCount(ctx_, &races));
  EXPECT_EQ(races, 0u);
}

TEST_P(RaceProbeTest, GpuLocalAccumulationIsNoRace) {
  RayGen("accumulate_local");
  Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_INT, {16, 8}, "local_acc");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_INT, {16, 8}, "local_copy");
  TileSize({4, 4});
  for (int launch = 0; launch < 3; ++launch) {
    ::testing::internal::CaptureStderr();
    Launch2D(16, 8);
    const std::string report = ::testing::internal::GetCapturedStderr();
    RTsize races = 0;
    Ok(tesseraContextGetRaceCount(ctx_, &races));
    EXPECT_EQ(races, 0u) << report;
  }
}

TEST_P(RaceProbeTest, InputOutputReadModifyWriteByOneDeviceIsNoRace) {
  RayGen("io_increment_and_peek");
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "shared_io");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "neighbor");
  SetUint("stride", 9);  // peeks into another tile, which another device may own
  TileSize({kTile});
  for (int launch = 0; launch < 3; ++launch) {
    std::string report;
    EXPECT_EQ(Races1D(kCount, &report), 0u) << report;
  }
  EXPECT_EQ(Contents<unsigned>(io), std::vector<unsigned>(kCount, 3u));
}

class DeviceSetProbeTest : public MultiDeviceFixture {
 protected:
  // accumulate_local on `devices` over a w x h launch in 4x4 tiles: each launch adds 1 to every
  // pixel's GPU_LOCAL count on its device, and the returned OUTPUT buffer shows the counts.
  RTbuffer AccumulateLocally(const char* devices, RTsize w, RTsize h) {
    UseDevices(devices);
    RayGen("accumulate_local");
    Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_INT, {w, h}, "local_acc");
    RTbuffer copy = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_INT, {w, h}, "local_copy");
    TileSize({4, 4});
    return copy;
  }
};

// ---- GPU_LOCAL when a worker dies between launches ---------------------------------------------

// Selecting the set the context already runs on changes nothing: it used to restart every worker
// and silently reset per-device accumulation.
TEST_F(DeviceSetProbeTest, SelectingTheSameDevicesKeepsGpuLocalState) {
  constexpr RTsize kW = 16, kH = 8;
  RTbuffer copy = AccumulateLocally("local:2", kW, kH);
  for (int launch = 1; launch <= 3; ++launch) {
    Launch2D(kW, kH);
    EXPECT_EQ(Contents<int>(copy), std::vector<int>(kW * kH, launch)) << "launch " << launch;
    unsigned count = 0;
    Ok(rtContextGetDeviceCount(ctx_, &count));
    std::vector<int> devices(count);
    Ok(rtContextGetDevices(ctx_, devices.data()));
    Ok(rtContextSetDevices(ctx_, count, devices.data()));
  }
}

// A launch that fails before devices take its state (every worker died) copies nothing: a
// COPY_ON_DIRTY pointer stays dirty, and the next launch copies what the application wrote
// since. It used to count as copied, leaving the other devices on what the failed launch saw.
TEST_F(DeviceSetProbeTest, CopyOnDirtyPointerStaysDirtyThroughAFailedLaunch) {
  UseDevices("local:3");
  RayGen("copy_from_pointer");
  constexpr RTsize kCount = 64;
  RTbuffer copied = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "copied");
  RTbuffer input = Buffer(RT_BUFFER_INPUT | RT_BUFFER_COPY_ON_DIRTY, RT_FORMAT_UNSIGNED_INT,
                          {kCount}, "from_pointer");
  TileSize({8});
  PinTilesToDevices();  // every device runs tiles
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(input, 0, &p));
  Launch1D(kCount);
  Ok(rtBufferMarkDirty(input));
  SetUint("salt", 1);  // a state update for every device, which finds them gone
  for (pid_t worker : WorkersOf(getpid())) ASSERT_EQ(kill(worker, SIGKILL), 0);
  usleep(100 * 1000);
  // Nor can they be started again within the launch (which tries once when it lost them all).
  const char* worker_env = std::getenv("TESSERA_WORKER");
  const std::string saved_worker = worker_env != nullptr ? worker_env : "";
  setenv("TESSERA_WORKER", "/nonexistent/tessera-worker", 1);
  ::testing::internal::CaptureStderr();
  RTresult r = rtContextLaunch1D(ctx_, 0, kCount);
  ::testing::internal::GetCapturedStderr();
  if (worker_env != nullptr) {
    setenv("TESSERA_WORKER", saved_worker.c_str(), 1);
  } else {
    unsetenv("TESSERA_WORKER");
  }
  EXPECT_EQ(r, RT_ERROR_CONNECTION_FAILED) << Error(r);
  std::vector<unsigned> values(kCount);
  for (RTsize i = 0; i < kCount; ++i) values[i] = 1000 + static_cast<unsigned>(i);
  std::copy(values.begin(), values.end(), static_cast<unsigned*>(p));
  ::testing::internal::CaptureStderr();
  Launch1D(kCount);  // on respawned workers
  ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(Contents<unsigned>(copied), values);
}

TEST_F(DeviceSetProbeTest, SurvivorsKeepTheirGpuLocalPixelsWhenAWorkerDiedBetweenLaunches) {
  constexpr RTsize kW = 24, kH = 8;
  RTbuffer copy = AccumulateLocally("local:3", kW, kH);  // 6x2 tiles: tile t on device t mod 3
  Launch2D(kW, kH);
  std::vector<pid_t> workers = WorkersOf(getpid());
  ASSERT_EQ(workers.size(), 3u);
  ASSERT_EQ(kill(workers.back(), SIGKILL), 0);
  usleep(100 * 1000);
  SetUint("salt", 1);  // something new: the launch starts with a state update to every device
  ::testing::internal::CaptureStderr();
  Launch2D(kW, kH);
  const std::string warning = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("its copies of GPU_LOCAL buffers (buffer #"), std::string::npos)
      << warning;
  EXPECT_NE(warning.find("('local_acc')) are gone"), std::string::npos) << warning;
  const size_t at = warning.find("Tessera local worker ");
  ASSERT_NE(at, std::string::npos) << warning;
  const unsigned lost = static_cast<unsigned>(warning[at + 21] - '0');
  Launch2D(kW, kH);
  // Pixels of the two devices that stayed have accumulated three launches.
  std::vector<int> seen = Contents<int>(copy);
  for (RTsize y = 0; y < kH; ++y) {
    for (RTsize x = 0; x < kW; ++x) {
      const unsigned tile = static_cast<unsigned>((y / 4) * (kW / 4) + x / 4);
      if (tile % 3 == lost) continue;
      EXPECT_EQ(seen[y * kW + x], 3)
          << "(" << x << ", " << y << ") on device " << tile % 3 << ", lost " << lost << "\n"
          << warning;
    }
  }
}

// Stable ownership keeps tile i on device i mod N; a new tile size at the same launch size moves
// launch indices to devices that hold other GPU_LOCAL contents. Said, not silent.
TEST_F(DeviceSetProbeTest, ChangingTheTileSizeUnderGpuLocalStateIsSaid) {
  UseDevices("local:3");
  RayGen("accumulate_local");
  Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_INT, {24, 8}, "local_acc");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_INT, {24, 8}, "local_copy");
  TileSize({4, 4});
  Launch2D(24, 8);
  TileSize({8, 2});
  ::testing::internal::CaptureStderr();
  Launch2D(24, 8);
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("the tile size changed from 4x4 to 8x2 at the same launch size 24x8"),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("GPU_LOCAL"), std::string::npos) << said;
}

// A device pointer for every device: each device runs on its own data, so a lost device's launch
// indices read another device's data. The warning names the buffer.
TEST_F(DeviceSetProbeTest, LosingADeviceNamesBuffersWithAPointerForEveryDevice) {
  UseDevices("local:3");
  RayGen("copy_from_pointer");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {64}, "copied");
  PinTilesToDevices();
  TileSize({8});
  RTbuffer in = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {64}, "from_pointer");
  for (int d = 0; d < 3; ++d) {
    void* p = nullptr;
    Ok(rtBufferGetDevicePointer(in, d, &p));
  }
  Launch1D(64);
  std::vector<pid_t> workers = WorkersOf(getpid());
  ASSERT_EQ(workers.size(), 3u);
  ASSERT_EQ(kill(workers.back(), SIGKILL), 0);
  usleep(100 * 1000);
  SetUint("salt", 1);  // a state update to every device: the dead one is found
  ::testing::internal::CaptureStderr();
  Launch1D(64);
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("device pointers for every device"), std::string::npos) << said;
}

const DeviceCase kProbeCases[] = {
    {"Inproc", "inproc", 1},
    {"Local2", "local:2", 2},
    {"Local3", "local:3", 3},
};

INSTANTIATE_TEST_SUITE_P(Devices, RaceProbeTest, ::testing::ValuesIn(kProbeCases), DeviceCaseName);

}  // namespace
}  // namespace tessera::testing
