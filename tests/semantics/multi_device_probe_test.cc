// Probes of the multi-device buffer rules at their edges: device pointers of INPUT_OUTPUT buffers
// across launches, pointers across device-set changes, race checking without false positives,
// and GPU_LOCAL accumulation when a worker dies between launches.
#include <dirent.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "multi_device_fixture.h"

namespace tessera::testing {
namespace {

constexpr RTsize kCount = 64;
constexpr RTsize kTile = 8;  // 8 tiles: with pinned tiles, tile t runs on device t mod N

std::vector<unsigned> Values(unsigned base) {
  std::vector<unsigned> v(kCount);
  for (RTsize i = 0; i < kCount; ++i) v[i] = base + static_cast<unsigned>(i);
  return v;
}

class PointerProbeTest : public MultiDeviceParamTest {
 protected:
  void SetUp() override {
    MultiDeviceParamTest::SetUp();
    RayGen("copy_from_pointer");
    copied_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "copied");
    TileSize({kTile});
  }
  RTbuffer copied_ = nullptr;
};

// An INPUT_OUTPUT buffer that a launch only reads: what the application wrote through the pointer
// is still there afterwards, and rtBufferMarkDirty then copies it to every device.
TEST_P(PointerProbeTest, InputOutputPointerKeepsWhatTheLaunchDidNotWrite) {
  PinTilesToDevices();
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_COPY_ON_DIRTY, RT_FORMAT_UNSIGNED_INT,
                      {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(b, 0, &p));
  unsigned* view = static_cast<unsigned*>(p);
  const std::vector<unsigned> first = Values(100), second = Values(200);
  std::copy(first.begin(), first.end(), view);
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied_), first);

  std::copy(second.begin(), second.end(), view);
  Launch1D(kCount);  // not dirty: device 0 runs on `second`, the others on `first`
  EXPECT_EQ(std::vector<unsigned>(view, view + kCount), second)
      << "the launch only read the buffer, yet the pointer's contents changed";

  Ok(rtBufferMarkDirty(b));
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied_), second);
}

// One pointer of a GPU_LOCAL buffer without COPY_ON_DIRTY reaches every device at every launch, as
// the guide says, also when the devices' own copies have diverged from it since the last one.
TEST_P(PointerProbeTest, GpuLocalPointerIsCopiedToEveryDeviceAtEveryLaunch) {
  RayGen("bump_and_copy");
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_UNSIGNED_INT,
                      {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(b, 0, &p));
  const std::vector<unsigned> start = Values(100), bumped = Values(101);
  std::copy(start.begin(), start.end(), static_cast<unsigned*>(p));
  for (int launch = 0; launch < 3; ++launch) {
    Launch1D(kCount);
    EXPECT_EQ(Contents<unsigned>(copied_), bumped) << "launch " << launch;
  }
}

// What devices write to an INPUT_OUTPUT buffer reaches its pointer.
TEST_P(PointerProbeTest, InputOutputPointerShowsWhatDevicesWrote) {
  RayGen("io_write");
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "shared_io");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(io, devices() - 1, &p));
  const unsigned* view = static_cast<const unsigned*>(p);
  for (unsigned salt : {4u, 5u}) {
    SetUint("salt", salt);
    Launch1D(kCount);
    std::vector<unsigned> expected(kCount);
    for (RTsize i = 0; i < kCount; ++i) expected[i] = static_cast<unsigned>(i) * 3u + salt;
    EXPECT_EQ(std::vector<unsigned>(view, view + kCount), expected) << "salt " << salt;
    EXPECT_EQ(Contents<unsigned>(io), expected) << "salt " << salt;
  }
}

// Pointers for every device of an INPUT_OUTPUT buffer that a launch only reads: each keeps its
// own data.
TEST_P(PointerProbeTest, InputOutputPointersForEveryDeviceKeepTheirOwnData) {
  PinTilesToDevices();
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  std::vector<unsigned*> views;
  for (unsigned d = 0; d < devices(); ++d) {
    void* p = nullptr;
    Ok(rtBufferGetDevicePointer(b, d, &p));
    views.push_back(static_cast<unsigned*>(p));
    const std::vector<unsigned> values = Values(1000 * (d + 1));
    std::copy(values.begin(), values.end(), views.back());
  }
  Launch1D(kCount);
  std::vector<unsigned> seen = Contents<unsigned>(copied_);
  for (RTsize i = 0; i < kCount; ++i) {
    const unsigned device = static_cast<unsigned>((i / kTile) % devices());
    EXPECT_EQ(seen[i], 1000 * (device + 1) + i) << "element " << i;
  }
  for (unsigned d = 0; d < devices(); ++d) {
    EXPECT_EQ(std::vector<unsigned>(views[d], views[d] + kCount), Values(1000 * (d + 1)))
        << "device " << d;
  }
}

TEST_P(PointerProbeTest, ResizeDropsPointersAndNewOnesWork) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(b, 0, &p));
  Ok(rtBufferSetSize1D(b, kCount));
  Ok(rtBufferGetDevicePointer(b, 0, &p));
  const std::vector<unsigned> values = Values(9);
  std::copy(values.begin(), values.end(), static_cast<unsigned*>(p));
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied_), values);
}

TEST_P(PointerProbeTest, HugeDeviceNumberIsAnError) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  RTresult r = rtBufferGetDevicePointer(b, 0xFFFFFFFFu, &p);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("4294967295"), std::string::npos) << Error(r);
  std::vector<unsigned> memory(kCount);
  r = rtBufferSetDevicePointer(b, devices(), memory.data());
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
}

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

// ---- Pointers across device-set changes (local:3) ---------------------------------------------

using DeviceSetProbeTest = MultiDeviceFixture;

TEST_F(DeviceSetProbeTest, PointerForADeviceLeftOutIsAClearErrorAtLaunch) {
  UseDevices("local:3");
  RayGen("copy_from_pointer");
  RTbuffer copied = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "copied");
  RTbuffer input = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(input, 2, &p));
  const std::vector<unsigned> values = Values(40);
  std::copy(values.begin(), values.end(), static_cast<unsigned*>(p));
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied), values);

  const int subset[2] = {0, 1};
  Ok(rtContextSetDevices(ctx_, 2, subset));
  RTresult r = rtBufferGetDevicePointer(input, 2, &p);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE) << Error(r);
  r = rtContextLaunch1D(ctx_, 0, kCount);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("device 2"), std::string::npos) << Error(r);
}

// ---- GPU_LOCAL when a worker dies between launches ---------------------------------------------

std::vector<pid_t> WorkersOf(pid_t parent) {
  std::vector<pid_t> workers;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return workers;
  while (dirent* entry = readdir(proc)) {
    char* end = nullptr;
    const long pid = std::strtol(entry->d_name, &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    std::ifstream in(std::string("/proc/") + entry->d_name + "/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos) continue;
    std::istringstream fields(stat.substr(close + 1));
    std::string state;
    long ppid = 0;
    fields >> state >> ppid;
    if (ppid == parent && state != "Z" &&
        stat.substr(open + 1, close - open - 1) == "tessera-worker") {
      workers.push_back(static_cast<pid_t>(pid));
    }
  }
  closedir(proc);
  std::sort(workers.begin(), workers.end());
  return workers;
}

TEST_F(DeviceSetProbeTest, SurvivorsKeepTheirGpuLocalPixelsWhenAWorkerDiedBetweenLaunches) {
  UseDevices("local:3");
  RayGen("accumulate_local");
  constexpr RTsize kW = 24, kH = 8;
  Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_INT, {kW, kH}, "local_acc");
  RTbuffer copy = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_INT, {kW, kH}, "local_copy");
  TileSize({4, 4});  // 6x2 tiles: tile t on device t mod 3
  Launch2D(kW, kH);
  std::vector<pid_t> workers = WorkersOf(getpid());
  ASSERT_EQ(workers.size(), 3u);
  ASSERT_EQ(kill(workers.back(), SIGKILL), 0);
  usleep(100 * 1000);
  SetUint("salt", 1);  // something new: the launch starts with a state update to every device
  ::testing::internal::CaptureStderr();
  Launch2D(kW, kH);
  const std::string warning = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("GPU_LOCAL"), std::string::npos) << warning;
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

const DeviceCase kProbeCases[] = {
    {"Inproc", "inproc", 1},
    {"Local2", "local:2", 2},
    {"Local3", "local:3", 3},
};

INSTANTIATE_TEST_SUITE_P(Devices, PointerProbeTest, ::testing::ValuesIn(kProbeCases),
                         DeviceCaseName);
INSTANTIATE_TEST_SUITE_P(Devices, RaceProbeTest, ::testing::ValuesIn(kProbeCases), DeviceCaseName);

}  // namespace
}  // namespace tessera::testing
