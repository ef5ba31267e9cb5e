// Device pointers (OptiX guide ch. 7, "Multi-GPU considerations") and the race-checking mode,
// run on every device set of kRuleDeviceCases. A "device pointer" is host memory standing for one
// device's copy: what the application writes there before a launch is that device's data.
#include <algorithm>
#include <string>
#include <vector>

#include "multi_device_fixture.h"

namespace tessera::testing {
namespace {

constexpr RTsize kCount = 64;
constexpr RTsize kTile = 8;  // 8 tiles: with pinned tiles, tile t runs on device t mod N

// base, base + 1, … : kCount values a device can be recognised by.
std::vector<unsigned> Values(unsigned base) {
  std::vector<unsigned> v(kCount);
  for (RTsize i = 0; i < kCount; ++i) v[i] = base + static_cast<unsigned>(i);
  return v;
}

class DevicePointerTest : public MultiDeviceParamTest {
 protected:
  void SetUp() override {
    MultiDeviceParamTest::SetUp();
    RayGen("copy_from_pointer");
    copied_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "copied");
    TileSize({kTile});
  }
  // A buffer for `from_pointer` and the pointer for device 0 (the first of every device set).
  unsigned* PointerOnDevice0(unsigned type) {
    input_ = Buffer(type, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
    void* p = nullptr;
    EXPECT_EQ(rtBufferGetDevicePointer(input_, 0, &p), RT_SUCCESS);
    return static_cast<unsigned*>(p);
  }
  // A pointer of `b` for every device, device d's filled with Values(1000 * (d + 1)).
  std::vector<unsigned*> PointersForEveryDevice(RTbuffer b) {
    std::vector<unsigned*> views;
    for (unsigned d = 0; d < devices(); ++d) {
      void* p = nullptr;
      EXPECT_EQ(rtBufferGetDevicePointer(b, d, &p), RT_SUCCESS);
      views.push_back(static_cast<unsigned*>(p));
      const std::vector<unsigned> values = Values(1000 * (d + 1));
      if (p != nullptr) std::copy(values.begin(), values.end(), views.back());
    }
    return views;
  }
  RTbuffer copied_ = nullptr;
  RTbuffer input_ = nullptr;
};

TEST_P(DevicePointerTest, OnePointerReachesEveryDeviceAtEveryLaunch) {
  unsigned* p = PointerOnDevice0(RT_BUFFER_INPUT);
  ASSERT_NE(p, nullptr);
  for (unsigned base : {100u, 200u}) {
    const std::vector<unsigned> values = Values(base);
    std::copy(values.begin(), values.end(), p);
    Launch1D(kCount);
    EXPECT_EQ(Contents<unsigned>(copied_), values) << "base " << base;
  }
}

// With one pointer every device runs on the pointer's contents: a map shows them, and what the
// host writes through the map reaches the pointer and every device (COPY_ON_DIRTY too).
TEST_P(DevicePointerTest, HostWritesThroughAMapReachTheDevicesOfABufferWithAPointer) {
  for (unsigned type :
       {unsigned{RT_BUFFER_INPUT}, unsigned{RT_BUFFER_INPUT | RT_BUFFER_COPY_ON_DIRTY}}) {
    SCOPED_TRACE(type);
    unsigned* p = PointerOnDevice0(type);
    const std::vector<unsigned> first = Values(500), second = Values(900);
    std::copy(first.begin(), first.end(), p);
    Launch1D(kCount);
    EXPECT_EQ(Contents<unsigned>(input_), first);
    Write(input_, second);
    Launch1D(kCount);
    EXPECT_EQ(Contents<unsigned>(copied_), second);
    EXPECT_EQ(std::vector<unsigned>(p, p + kCount), second);
  }
}

TEST_P(DevicePointerTest, CopyOnDirtyCopiesOnlyAfterThePointerOrMarkDirty) {
  PinTilesToDevices();
  unsigned* p = PointerOnDevice0(RT_BUFFER_INPUT | RT_BUFFER_COPY_ON_DIRTY);
  const std::vector<unsigned> first = Values(100), second = Values(200);
  std::copy(first.begin(), first.end(), p);
  Launch1D(kCount);  // the first launch after the pointer was taken copies
  EXPECT_EQ(Contents<unsigned>(copied_), first);

  // Not dirty: device 0 runs on its own memory, the others keep their old copy.
  std::copy(second.begin(), second.end(), p);
  Launch1D(kCount);
  std::vector<unsigned> seen = Contents<unsigned>(copied_);
  for (RTsize i = 0; i < kCount; ++i) {
    const bool device0 = (i / kTile) % devices() == 0;
    EXPECT_EQ(seen[i], device0 ? second[i] : first[i]) << "element " << i;
  }

  Ok(rtBufferMarkDirty(input_));
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied_), second);
}

TEST_P(DevicePointerTest, PointersForEveryDeviceGiveEachItsOwnData) {
  input_ = Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_UNSIGNED_INT, {kCount},
                  "from_pointer");
  PointersForEveryDevice(input_);
  Launch1D(kCount);  // GPU_LOCAL: tile t stays on device t mod N
  std::vector<unsigned> seen = Contents<unsigned>(copied_);
  for (RTsize i = 0; i < kCount; ++i) {
    const unsigned device = static_cast<unsigned>((i / kTile) % devices());
    EXPECT_EQ(seen[i], 1000 * (device + 1) + i) << "element " << i;
  }
}

TEST_P(DevicePointerTest, DeviceNumbersMustBeDevicesOfTheContext) {
  input_ = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  RTresult r = rtBufferGetDevicePointer(input_, 99, &p);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("device number 99"), std::string::npos) << Error(r);
}

TEST_P(DevicePointerTest, BufferForCudaRunsOnTheApplicationsMemory) {
  RTbuffer b = nullptr;
  Ok(rtBufferCreateForCUDA(ctx_, RT_BUFFER_INPUT, &b));
  Ok(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_INT));
  Ok(rtBufferSetSize1D(b, kCount));
  Ok(rtVariableSetObject(ContextVar("from_pointer"), b));
  RTresult r = rtContextLaunch1D(ctx_, 0, kCount);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("rtBufferSetDevicePointer"), std::string::npos) << Error(r);

  std::vector<unsigned> memory = Values(7);
  Ok(rtBufferSetDevicePointer(b, 0, memory.data()));
  Launch1D(kCount);
  EXPECT_EQ(Contents<unsigned>(copied_), memory);
}

TEST_P(DevicePointerTest, OutputPointerShowsTheMergedResultAfterALaunch) {
  input_ = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  Write(input_, Values(5));
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(copied_, 0, &p));
  Launch1D(kCount);
  const unsigned* out = static_cast<const unsigned*>(p);
  EXPECT_EQ(std::vector<unsigned>(out, out + kCount), Values(5));
}

// An OUTPUT buffer's device pointer is that device's copy too: programs see what the application
// put there (it used to be ignored, and the application's data overwritten with zeros).
TEST_P(DevicePointerTest, OutputPointerContentsAreTheDevicesCopy) {
  RayGen("output_increment");
  RTbuffer counts = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "out_counts");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(counts, 0, &p));
  unsigned* u = static_cast<unsigned*>(p);
  const std::vector<unsigned> start = Values(100);
  std::copy(start.begin(), start.end(), u);
  Launch1D(kCount);
  EXPECT_EQ(std::vector<unsigned>(u, u + kCount), Values(101));
  EXPECT_EQ(Contents<unsigned>(counts), Values(101));
}

TEST_P(DevicePointerTest, RaceCheckNamesTheBufferTheElementAndTheDevices) {
  RayGen("race_on_first");
  RTbuffer contested = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "contested");
  (void)contested;
  PinTilesToDevices();  // every device runs tiles, so each writes element 0
  RTsize races = 0;
  SetUint("salt", 1);
  Launch1D(kCount);  // checking off: the race goes unreported
  Ok(tesseraContextGetRaceCount(ctx_, &races));
  EXPECT_EQ(races, 0u);

  Ok(tesseraContextSetRaceCheck(ctx_, 1));
  SetUint("salt", 2);
  ::testing::internal::CaptureStderr();
  Launch1D(kCount);
  const std::string report = ::testing::internal::GetCapturedStderr();
  Ok(tesseraContextGetRaceCount(ctx_, &races));
  if (devices() == 1) {
    EXPECT_EQ(races, 0u);  // one device cannot race with itself
    EXPECT_EQ(report, "");
    return;
  }
  EXPECT_EQ(races, 1u) << report;  // element 0, reported once
  EXPECT_NE(report.find("buffer 'contested' element (0, 0, 0)"), std::string::npos) << report;
  EXPECT_NE(report.find("Tessera local worker"), std::string::npos) << report;

  // Writes that do not collide report nothing.
  RayGen("copy_from_pointer");
  input_ = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  Launch1D(kCount);
  Ok(tesseraContextGetRaceCount(ctx_, &races));
  EXPECT_EQ(races, 0u);
}

// Needs three devices or more: one of several, or all, is fine; two of three is not.
using DevicePointerCountTest = MultiDeviceFixture;
TEST_F(DevicePointerCountTest, PointersForSomeButNotAllDevicesAreAnError) {
  UseDevices("local:3");
  RayGen("copy_from_pointer");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "copied");
  RTbuffer input = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(input, 0, &p));
  Launch1D(kCount);  // one pointer: fine
  Ok(rtBufferGetDevicePointer(input, 1, &p));
  RTresult r = rtContextLaunch1D(ctx_, 0, kCount);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("buffer #"), std::string::npos) << Error(r);
  EXPECT_NE(Error(r).find(" ('from_pointer') has device pointers for 2 of the context's 3 devices"),
            std::string::npos)
      << Error(r);
  Ok(rtBufferGetDevicePointer(input, 2, &p));
  Launch1D(kCount);  // every device: fine again
}

// An INPUT_OUTPUT buffer that a launch only reads: what the application wrote through the pointer
// is still there afterwards, and rtBufferMarkDirty then copies it to every device.
TEST_P(DevicePointerTest, InputOutputPointerKeepsWhatTheLaunchDidNotWrite) {
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
// the guide says, also when the devices' own copies have diverged from it since the last one. The
// pointer is device 0's copy: it shows device 0's writes, which the other devices then receive.
TEST_P(DevicePointerTest, GpuLocalPointerIsCopiedToEveryDeviceAtEveryLaunch) {
  RayGen("bump_and_copy");
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_UNSIGNED_INT,
                      {kCount}, "from_pointer");
  void* p = nullptr;
  Ok(rtBufferGetDevicePointer(b, 0, &p));
  const unsigned* view = static_cast<const unsigned*>(p);
  const std::vector<unsigned> start = Values(100);
  std::copy(start.begin(), start.end(), static_cast<unsigned*>(p));
  for (unsigned launch = 1; launch <= 3; ++launch) {
    Launch1D(kCount);
    std::vector<unsigned> seen = Contents<unsigned>(copied_);
    for (RTsize i = 0; i < kCount; ++i) {
      // Device 0 accumulates on its own copy; the others start from it (where device 0 never
      // writes) at every launch.
      const bool device0 = (i / kTile) % devices() == 0;
      EXPECT_EQ(seen[i], device0 ? start[i] + launch : start[i] + 1)
          << "launch " << launch << ", element " << i;
      EXPECT_EQ(view[i], device0 ? start[i] + launch : start[i])
          << "launch " << launch << ", element " << i;
    }
  }
}

// A GPU_LOCAL buffer's pointer for every device is that device's copy: after each launch it shows
// what its device wrote (tile t on device t mod N), and the next launch goes on from there.
TEST_P(DevicePointerTest, GpuLocalPointersShowWhatTheirDeviceWrote) {
  RayGen("bump_and_copy");
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_UNSIGNED_INT,
                      {kCount}, "from_pointer");
  std::vector<unsigned*> views = PointersForEveryDevice(b);
  for (unsigned launch = 1; launch <= 3; ++launch) {
    Launch1D(kCount);
    std::vector<unsigned> seen = Contents<unsigned>(copied_);
    for (unsigned d = 0; d < devices(); ++d) {
      for (RTsize i = 0; i < kCount; ++i) {
        const bool own = (i / kTile) % devices() == d;
        const unsigned start = 1000 * (d + 1) + static_cast<unsigned>(i);
        EXPECT_EQ(views[d][i], own ? start + launch : start)
            << "launch " << launch << ", device " << d << ", element " << i;
        if (own) {
          EXPECT_EQ(seen[i], start + launch) << "launch " << launch << ", element " << i;
        }
      }
    }
  }
}

// One COPY_ON_DIRTY pointer of a GPU_LOCAL buffer: every device starts from it, then runs on its
// own copy; the pointer shows its device's copy as that device's programs change it.
TEST_P(DevicePointerTest, GpuLocalCopyOnDirtyPointerFollowsItsDevice) {
  RayGen("bump_and_copy");
  unsigned* view =
      PointerOnDevice0(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL | RT_BUFFER_COPY_ON_DIRTY);
  const std::vector<unsigned> start = Values(100);
  std::copy(start.begin(), start.end(), view);
  RTsize device0_elements = 0;
  for (RTsize i = 0; i < kCount; ++i) device0_elements += (i / kTile) % devices() == 0;
  for (unsigned launch = 1; launch <= 2; ++launch) {
    const Transfer before = Stats();
    Launch1D(kCount);
    // Back come `copied` and what device 0 wrote to its copy: the other devices have no pointer,
    // so their writes stay with them.
    EXPECT_EQ((Stats() - before).received, (kCount + device0_elements) * sizeof(unsigned))
        << "launch " << launch;
    std::vector<unsigned> seen = Contents<unsigned>(copied_);
    for (RTsize i = 0; i < kCount; ++i) {
      const bool device0 = (i / kTile) % devices() == 0;
      EXPECT_EQ(view[i], device0 ? start[i] + launch : start[i])
          << "launch " << launch << ", element " << i;
      EXPECT_EQ(seen[i], start[i] + launch) << "launch " << launch << ", element " << i;
    }
  }
}

// What devices write to an INPUT_OUTPUT buffer reaches its pointer.
TEST_P(DevicePointerTest, InputOutputPointerShowsWhatDevicesWrote) {
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
TEST_P(DevicePointerTest, InputOutputPointersForEveryDeviceKeepTheirOwnData) {
  PinTilesToDevices();
  RTbuffer b = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  std::vector<unsigned*> views = PointersForEveryDevice(b);
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

TEST_P(DevicePointerTest, ResizeDropsPointersAndNewOnesWork) {
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

TEST_P(DevicePointerTest, HugeDeviceNumberIsAnError) {
  RTbuffer b = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_INT, {kCount}, "from_pointer");
  void* p = nullptr;
  RTresult r = rtBufferGetDevicePointer(b, 0xFFFFFFFFu, &p);
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
  EXPECT_NE(Error(r).find("4294967295"), std::string::npos) << Error(r);
  std::vector<unsigned> memory(kCount);
  r = rtBufferSetDevicePointer(b, devices(), memory.data());
  EXPECT_EQ(r, RT_ERROR_INVALID_VALUE);
}

// ---- Pointers across device-set changes (local:3) ---------------------------------------------

using DeviceSetPointerTest = MultiDeviceFixture;

TEST_F(DeviceSetPointerTest, PointerForADeviceLeftOutIsAClearErrorAtLaunch) {
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

INSTANTIATE_TEST_SUITE_P(Devices, DevicePointerTest, ::testing::ValuesIn(kRuleDeviceCases),
                         DeviceCaseName);

}  // namespace
}  // namespace tessera::testing
