// The buffer table of docs/devices.md "Buffers across devices" (OptiX 3 guide §3.2, ch. 7) on
// inproc, local:1, local:2 and local:4: INPUT ships changed chunks only, OUTPUT brings back every
// written element (scatter writes included) and nothing else, INPUT_OUTPUT merges across devices,
// GPU_LOCAL copies stay per device and accumulate per launch index.
#include <cstdint>
#include <string>
#include <vector>

#include "multi_device_fixture.h"

namespace tessera::testing {
namespace {

constexpr unsigned long long kChunkBytes = 4ull << 20;  // the host's content-hash chunk size

class BufferRulesTest : public MultiDeviceParamTest {
 protected:
  enum class Tiles { kDynamic, kPinned };
  static const char* Describe(Tiles t) {
    return t == Tiles::kDynamic ? "tiles taken dynamically" : "tiles pinned to devices";
  }

  // Sets one element of a mapped buffer of T: a host write of that element only.
  template <typename T>
  void Poke(RTbuffer b, size_t i, const T& value) {
    void* p = nullptr;
    ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    static_cast<T*>(p)[i] = value;
    ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  }
};

// ---- Rule 1: INPUT -----------------------------------------------------------------------------

TEST_P(BufferRulesTest, InputShipsOnlyChangedChunksAndEveryDeviceSeesThem) {
  constexpr size_t kElements = (5u << 20) / sizeof(Float4);  // chunks of 4 MiB and 1 MiB
  constexpr unsigned long long kBytes = kElements * sizeof(Float4);
  constexpr size_t kLaunch = 64;
  constexpr unsigned kInFirstChunk = 1000, kInSecondChunk = kElements - 10;
  RTbuffer big = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, {kElements}, "big_input");
  RTbuffer seen = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kLaunch}, "seen");
  std::vector<Float4> values(kElements);
  for (size_t i = 0; i < kElements; ++i) {
    const float f = static_cast<float>(i);  // exact: i < 2^24
    values[i] = {f, f + 0.5f, 2.f * f, 3.f * f};
  }
  Write(big, values);
  SetUint("probe_a", kInFirstChunk);
  SetUint("probe_b", kInSecondChunk);
  RayGen("read_input");
  TileSize({4});  // 16 tiles

  // Every launch index, whichever device ran it, saw the host's current values.
  auto check_seen = [&] {
    std::vector<Float4> s = Contents<Float4>(seen);
    for (size_t i = 0; i < kLaunch; ++i) {
      const Float4 want = {values[kInFirstChunk][0], values[kInSecondChunk][0], values[i][1],
                           values[kElements - 1 - i][2]};
      ASSERT_EQ(s[i], want) << "launch index " << i;
    }
  };

  for (Tiles tiles : {Tiles::kDynamic, Tiles::kPinned}) {
    SCOPED_TRACE(Describe(tiles));
    Transfer before = Stats();
    if (tiles == Tiles::kPinned) PinTilesToDevices();
    Launch1D(kLaunch);
    Transfer first = Stats() - before;
    // The first launch ships every chunk to every device; after that only the 4-byte GPU_LOCAL
    // buffer that pins tiles is new.
    EXPECT_EQ(first.sent, devices() * (tiles == Tiles::kDynamic ? kBytes : 4));
    EXPECT_EQ(first.received, kLaunch * sizeof(Float4));
    check_seen();

    before = Stats();
    Launch1D(kLaunch);
    EXPECT_EQ((Stats() - before).sent, 0u) << "an unchanged launch shipped buffer bytes";
    check_seen();

    // One element of the 1 MiB chunk, then one of the 4 MiB chunk: that chunk alone travels, to
    // every device.
    const float salt = tiles == Tiles::kDynamic ? 1.f : 2.f;
    values[kInSecondChunk][0] = -salt;
    Poke(big, kInSecondChunk, values[kInSecondChunk]);
    before = Stats();
    Launch1D(kLaunch);
    EXPECT_EQ((Stats() - before).sent, devices() * (kBytes - kChunkBytes));
    check_seen();

    values[kInFirstChunk][0] = -10.f * salt;
    Poke(big, kInFirstChunk, values[kInFirstChunk]);
    before = Stats();
    Launch1D(kLaunch);
    EXPECT_EQ((Stats() - before).sent, devices() * kChunkBytes);
    check_seen();
  }
}

// ---- Rule 2: OUTPUT ----------------------------------------------------------------------------

TEST_P(BufferRulesTest, OutputWriteOfEveryLaunchIndexReachesTheHost) {
  constexpr size_t kW = 37, kH = 23;  // tiles of 8x4 leave partial tiles on both edges
  RTbuffer image = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kW, kH}, "image");
  RayGen("write_every_index");
  TileSize({8, 4});
  for (unsigned salt : {5u, 6u}) {
    SCOPED_TRACE(salt);
    SetUint("salt", salt);
    Transfer before = Stats();
    Launch2D(kW, kH);
    Transfer moved = Stats() - before;
    EXPECT_EQ(moved.sent, 0u);
    EXPECT_EQ(moved.received, kW * kH * sizeof(Float4));
    std::vector<Float4> v = Contents<Float4>(image);
    for (size_t y = 0; y < kH; ++y) {
      for (size_t x = 0; x < kW; ++x) {
        ASSERT_EQ(v[y * kW + x], (Float4{float(x), float(y), float(salt), 1.f}))
            << "launch index (" << x << ", " << y << ")";
      }
    }
  }
}

// Reallocating a buffer (rtBufferSetSize, even to the same size; rtBufferSetFormat) zeroes it on
// the host and on every device; contents the host writes afterwards reach every device, even
// when they are the bytes the devices held before.
TEST_P(BufferRulesTest, AReallocatedBufferStartsFromZeroEverywhere) {
  constexpr size_t kN = 96;
  RTbuffer counts = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "out_counts");
  RayGen("output_increment");
  TileSize({8});
  for (int i = 0; i < 3; ++i) Launch1D(kN);
  ASSERT_EQ(rtBufferSetSize1D(counts, kN), RT_SUCCESS);
  EXPECT_EQ(Contents<unsigned>(counts), std::vector<unsigned>(kN, 0u));
  Launch1D(kN);
  EXPECT_EQ(Contents<unsigned>(counts), std::vector<unsigned>(kN, 1u))
      << "a device kept counting on its copy from before the reallocation";

  constexpr size_t kElements = 4096, kLaunch = 64;
  RTbuffer big = Buffer(RT_BUFFER_INPUT, RT_FORMAT_FLOAT4, {kElements}, "big_input");
  RTbuffer seen = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4, {kLaunch}, "seen");
  std::vector<Float4> values(kElements);
  for (size_t i = 0; i < kElements; ++i) {
    const float f = static_cast<float>(i);
    values[i] = {f, f + 0.5f, 2.f * f, 3.f * f};
  }
  SetUint("probe_a", 7);
  SetUint("probe_b", kElements - 3);
  RayGen("read_input");
  TileSize({4});
  for (int pass = 0; pass < 2; ++pass) {
    SCOPED_TRACE(pass == 0 ? "first fill" : "the same bytes after rtBufferSetFormat");
    if (pass == 1) {
      ASSERT_EQ(rtBufferSetFormat(big, RT_FORMAT_USER), RT_SUCCESS);
      ASSERT_EQ(rtBufferSetElementSize(big, sizeof(Float4)), RT_SUCCESS);
      ASSERT_EQ(rtBufferSetSize1D(big, kElements), RT_SUCCESS);
    }
    Write(big, values);
    Launch1D(kLaunch);
    std::vector<Float4> s = Contents<Float4>(seen);
    for (size_t i = 0; i < kLaunch; ++i) {
      const Float4 want = {values[7][0], values[kElements - 3][0], values[i][1],
                           values[kElements - 1 - i][2]};
      ASSERT_EQ(s[i], want) << "launch index " << i;
    }
  }
}

TEST_P(BufferRulesTest, ScatterWritesOutsideTheWritersTileReachTheHost) {
  constexpr size_t kN = 1000;  // 7919 is prime: i -> (i * 7919) % 1000 is a permutation
  RTbuffer out = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "scattered");
  RayGen("scatter_writes");
  TileSize({10});
  size_t outside_own_tile = 0;
  for (size_t i = 0; i < kN; ++i) outside_own_tile += (i * 7919) % kN / 10 != i / 10;
  ASSERT_GT(outside_own_tile, kN * 9 / 10);
  for (Tiles tiles : {Tiles::kDynamic, Tiles::kPinned}) {
    SCOPED_TRACE(Describe(tiles));
    if (tiles == Tiles::kPinned) PinTilesToDevices();
    const unsigned salt = tiles == Tiles::kDynamic ? 11 : 12;
    SetUint("salt", salt);
    Transfer before = Stats();
    Launch1D(kN);
    EXPECT_EQ((Stats() - before).received, kN * sizeof(unsigned));
    std::vector<unsigned> v = Contents<unsigned>(out);
    for (size_t i = 0; i < kN; ++i) {
      ASSERT_EQ(v[(i * 7919) % kN], 3 * i + salt) << "write of launch index " << i;
    }
  }
}

TEST_P(BufferRulesTest, OnlyWrittenElementsTravelBack) {
  constexpr size_t kN = 1000;
  RTbuffer out = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "scattered");
  TileSize({16});
  RayGen("scatter_writes");
  SetUint("salt", 1);
  Launch1D(kN);
  std::vector<unsigned> want(kN);
  for (size_t i = 0; i < kN; ++i) want[(i * 7919) % kN] = 3 * i + 1;
  ASSERT_EQ(Contents<unsigned>(out), want);

  RayGen("write_even_elements");
  SetUint("salt", 100);
  Transfer before = Stats();
  Launch1D(kN);
  Transfer moved = Stats() - before;
  EXPECT_EQ(moved.received, kN / 2 * sizeof(unsigned)) << "half the elements, half the bytes";
  EXPECT_EQ(moved.sent, 0u);
  // Written elements changed; the others keep what the host had (nothing else came back).
  for (size_t i = 0; i < kN; i += 2) want[i] = i + 100;
  EXPECT_EQ(Contents<unsigned>(out), want);
}

// A buffer of many 4096-element mark blocks: a device collects a call's last regions from groups
// of blocks in parallel (Replica::TakeWrittenRegions). Scattered writes of every element, then
// every other element: runs of one element across every group boundary, each exactly once.
TEST_P(BufferRulesTest, LargeBuffersCollectExactlyTheWrittenElements) {
  constexpr size_t kN =
      300000;  // 74 blocks; not a multiple of 7919, so the scatter is a permutation
  RTbuffer out = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "scattered");
  TileSize({kN / 4});  // few pieces: much of a call is left for its last collection
  RayGen("scatter_writes");
  SetUint("salt", 5);
  Transfer before = Stats();
  Launch1D(kN);
  EXPECT_EQ((Stats() - before).received, kN * sizeof(unsigned));
  std::vector<unsigned> want(kN);
  for (size_t i = 0; i < kN; ++i) want[(i * 7919) % kN] = 3 * i + 5;
  ASSERT_EQ(Contents<unsigned>(out), want);

  RayGen("write_even_elements");
  SetUint("salt", 100);
  before = Stats();
  Launch1D(kN);
  EXPECT_EQ((Stats() - before).received, kN / 2 * sizeof(unsigned));
  for (size_t i = 0; i < kN; i += 2) want[i] = i + 100;
  EXPECT_EQ(Contents<unsigned>(out), want);
}

// ---- Rule 3: INPUT_OUTPUT ----------------------------------------------------------------------

TEST_P(BufferRulesTest, InputOutputNextLaunchSeesTheMergeOnEveryDevice) {
  constexpr size_t kN = 256, kTile = 8;
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "shared_io");
  RTbuffer neighbor = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "neighbor");
  Write(io, std::vector<unsigned>(kN, 7u));
  TileSize({kTile});
  SetUint("stride", kTile);  // the element read lies in the next tile: on another device when
                             // tiles are pinned and there are several
  RTprogram write = Program("io_write"), read = Program("io_read_neighbor");
  auto expect_neighbors_of = [&](const std::vector<unsigned>& io_now) {
    std::vector<unsigned> v = Contents<unsigned>(neighbor);
    for (size_t i = 0; i < kN; ++i) {
      ASSERT_EQ(v[i], io_now[(i + kTile) % kN]) << "launch index " << i;
    }
  };
  for (Tiles tiles : {Tiles::kDynamic, Tiles::kPinned}) {
    SCOPED_TRACE(Describe(tiles));
    if (tiles == Tiles::kPinned) PinTilesToDevices();
    std::vector<unsigned> want(kN);
    for (unsigned round = 1; round <= 3; ++round) {
      SCOPED_TRACE(round);
      const unsigned salt = round * 1000 + (tiles == Tiles::kPinned ? 50000 : 0);
      SetUint("salt", salt);
      Ok(rtContextSetRayGenerationProgram(ctx_, 0, write));
      Launch1D(kN);
      for (size_t i = 0; i < kN; ++i) want[i] = 3 * i + salt;
      ASSERT_EQ(Contents<unsigned>(io), want) << "the host map sees the merge";
      Ok(rtContextSetRayGenerationProgram(ctx_, 0, read));
      Launch1D(kN);
      expect_neighbors_of(want);
      ASSERT_EQ(Contents<unsigned>(io), want) << "reads changed nothing";
    }
    // Host writes between launches reach every device.
    for (size_t i = 0; i < kN; i += 5) want[i] = 900000 + i;
    Write(io, want);
    Launch1D(kN);
    expect_neighbors_of(want);
  }
}

// In OptiX a read never changes an INPUT_OUTPUT element. A device sends back every element its
// programs accessed (operator[] cannot tell reads from writes), so an element that device A only
// read (its stale copy) and device B incremented in the same launch comes back from both; the
// host applies regions in arrival order and may keep A's stale value over B's write.
TEST_P(BufferRulesTest, ReadingAnElementDoesNotUndoAnotherDevicesWrite) {
  constexpr size_t kN = 256, kTile = 8;
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "shared_io");
  Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "neighbor");
  Write(io, std::vector<unsigned>(kN, 0u));
  TileSize({kTile});
  SetUint("stride", kTile);
  PinTilesToDevices();  // the element read belongs to the next tile: another device's
  RayGen("io_increment_and_peek");
  constexpr unsigned kLaunches = 5;
  for (unsigned k = 0; k < kLaunches; ++k) Launch1D(kN);
  std::vector<unsigned> v = Contents<unsigned>(io);
  size_t lost = 0;
  for (size_t i = 0; i < kN; ++i) lost += v[i] != kLaunches;
  EXPECT_EQ(lost, 0u) << "increments lost: element 0 = " << v[0] << ", element " << kN - 1 << " = "
                      << v[kN - 1] << ", expected " << kLaunches;
}

// A launch that fails hands back only the batches that finished; what the others wrote stays in
// the devices' copies. The host's next writes must still reach every device, even where they
// restore the contents the host last sent.
TEST_P(BufferRulesTest, HostWritesAfterAFailedLaunchReachEveryDevice) {
  constexpr size_t kN = 1000;
  RTbuffer io = Buffer(RT_BUFFER_INPUT_OUTPUT, RT_FORMAT_UNSIGNED_INT, {kN}, "shared_io");
  const std::vector<unsigned> zeros(kN, 0u);
  Write(io, zeros);
  TileSize({8});
  RayGen("io_increment_or_fail");
  SetUint("fail_at", kN - 1);
  EXPECT_NE(rtContextLaunch1D(ctx_, 0, kN), RT_SUCCESS);
  Write(io, zeros);
  SetUint("fail_at", kN);  // no index fails
  Launch1D(kN);
  EXPECT_EQ(Contents<unsigned>(io), std::vector<unsigned>(kN, 1u));
}

// ---- Rule 4: GPU_LOCAL -------------------------------------------------------------------------

TEST_P(BufferRulesTest, GpuLocalAccumulatesPerLaunchIndexAndNeverReachesTheHost) {
  constexpr size_t kW = 24, kH = 10, kN = kW * kH;
  RTbuffer acc =
      Buffer(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, RT_FORMAT_INT, {kW, kH}, "local_acc");
  RTbuffer copy = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_INT, {kW, kH}, "local_copy");
  std::vector<int> host(kN);
  for (size_t i = 0; i < kN; ++i) host[i] = 10 * static_cast<int>(i);
  Write(acc, host);
  RayGen("accumulate_local");
  TileSize({5, 3});  // 5x4 tiles, partial ones on both edges
  auto expect_copy = [&](int added) {
    std::vector<int> v = Contents<int>(copy);
    for (size_t i = 0; i < kN; ++i) {
      ASSERT_EQ(v[i], host[i] + added) << "launch index (" << i % kW << ", " << i / kW << ")";
    }
  };
  for (int k = 1; k <= 4; ++k) {
    SCOPED_TRACE(k);
    Transfer before = Stats();
    Launch2D(kW, kH);
    Transfer moved = Stats() - before;
    // Host writes are broadcast once; device copies never come back.
    EXPECT_EQ(moved.sent, k == 1 ? devices() * kN * sizeof(int) : 0u);
    EXPECT_EQ(moved.received, kN * sizeof(int));
    expect_copy(k);
  }
  EXPECT_EQ(Contents<int>(acc), host) << "device writes reached the host copy";

  // New host contents reach every device and restart the accumulation there.
  for (size_t i = 0; i < kN; ++i) host[i] = 1000 + static_cast<int>(i);
  Write(acc, host);
  Transfer before = Stats();
  Launch2D(kW, kH);
  EXPECT_EQ((Stats() - before).sent, devices() * kN * sizeof(int));
  expect_copy(1);
  Launch2D(kW, kH);
  expect_copy(2);
}

INSTANTIATE_TEST_SUITE_P(Devices, BufferRulesTest, ::testing::ValuesIn(kRuleDeviceCases),
                         DeviceCaseName);

// ---- One device: atomics on shared elements are well defined (on several they race, in OptiX
// too)
// ---------------------------------------------------------------------------------------------

class OneDeviceBufferTest : public MultiDeviceParamTest {};

TEST_P(OneDeviceBufferTest, AccumulationComesBackWhole) {
  RTbuffer bins = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_INT, {4}, "bins");
  RayGen("count_into_bins");
  constexpr unsigned kN = 1u << 16;
  Launch1D(kN);
  // A worker with several threads sends what closed write epochs hold while it traces (the whole
  // launch is one call here); totals every piece keeps touching go out with the last epoch, and
  // any sent earlier are applied before it: the complete totals stay.
  EXPECT_EQ(Contents<unsigned>(bins), std::vector<unsigned>(4, kN / 4));
}

const DeviceCase kOneDeviceCases[] = {{"Inproc", "inproc", 1}, {"Local1", "local:1", 1}};
INSTANTIATE_TEST_SUITE_P(Devices, OneDeviceBufferTest, ::testing::ValuesIn(kOneDeviceCases),
                         DeviceCaseName);

}  // namespace
}  // namespace tessera::testing
