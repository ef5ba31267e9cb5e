// Buffer contents between host and devices: changed chunks only, INPUT_OUTPUT merges, GPU_LOCAL
// broadcasts, and acceleration dirty tracking driven by the structure below.
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "gtest/gtest.h"
#include "launch_fixture.h"

namespace tessera::test {
namespace {

constexpr size_t kMiB = size_t{1} << 20;

std::vector<const v1::BufferChunk*> ChunksOf(const v1::StateDelta& d, uint64_t id) {
  std::vector<const v1::BufferChunk*> out;
  for (const v1::BufferChunk& c : d.chunks()) {
    if (c.buffer_id() == id) out.push_back(&c);
  }
  return out;
}

class BufferSyncTest : public LaunchTest {
 protected:
  RTbuffer MakeBytes(unsigned desc, size_t size, const char* variable) {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx, desc, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_BYTE), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize1D(b, size), RT_SUCCESS);
    BindObject(ctx_var(variable), b);
    return b;
  }

  void Poke(RTbuffer b, size_t offset, unsigned char value) {
    void* p = nullptr;
    ASSERT_EQ(rtBufferMap(b, &p), RT_SUCCESS);
    static_cast<unsigned char*>(p)[offset] = value;
    ASSERT_EQ(rtBufferUnmap(b), RT_SUCCESS);
  }
};

TEST_F(BufferSyncTest, LargeBuffersTravelInHashedChunks) {
  RTbuffer big = MakeBytes(RT_BUFFER_INPUT, 9 * kMiB, "big");
  Poke(big, 5 * kMiB, 7);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  auto chunks = ChunksOf(LastDelta(), Id(big));
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[0]->offset(), 0u);
  EXPECT_EQ(chunks[1]->offset(), 4 * kMiB);
  EXPECT_EQ(chunks[2]->offset(), 8 * kMiB);
  EXPECT_EQ(chunks[0]->data().size(), 4 * kMiB);
  EXPECT_EQ(chunks[2]->data().size(), 1 * kMiB);
  EXPECT_EQ(chunks[1]->data()[kMiB], 7);
  // Identical contents hash alike; different contents do not.
  EXPECT_NE(chunks[0]->hash(), chunks[1]->hash());

  // Mapping without changing anything ships nothing.
  void* p;
  ASSERT_EQ(rtBufferMap(big, &p), RT_SUCCESS);
  ASSERT_EQ(rtBufferUnmap(big), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_TRUE(ChunksOf(LastDelta(), Id(big)).empty());

  // Changing one byte ships the one chunk that holds it.
  Poke(big, 8 * kMiB + 3, 9);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  chunks = ChunksOf(LastDelta(), Id(big));
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->offset(), 8 * kMiB);
  EXPECT_EQ(chunks[0]->data()[3], 9);
  EXPECT_EQ(LastDelta().objects_size(), 0);  // contents changed, not the buffer's description
}

TEST_F(BufferSyncTest, ResizingShipsTheDescriptionAndZeroedContents) {
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(input, 4), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(LastDelta().objects_size(), 1);
  EXPECT_EQ(LastDelta().objects(0).buffer().dims(0), 4u);
  auto chunks = ChunksOf(LastDelta(), Id(input));
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->data(), std::string(16, '\0'));
}

TEST_F(BufferSyncTest, ReshapingAtTheSameByteSizeShipsTheContentsAgain) {
  // A device zeroes its copy when the format or dimensions change, even at the same byte size;
  // the same contents written again must therefore travel again.
  RTbuffer b = MakeBytes(RT_BUFFER_INPUT, 64, "reshaped");
  Poke(b, 3, 7);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(b, RT_FORMAT_BYTE), RT_SUCCESS);
  Poke(b, 3, 7);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  auto chunks = ChunksOf(LastDelta(), Id(b));
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->data()[3], 7);
  ASSERT_EQ(rtBufferSetSize2D(b, 8, 8), RT_SUCCESS);  // 64 bytes still
  Poke(b, 3, 7);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  chunks = ChunksOf(LastDelta(), Id(b));
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->data()[3], 7);
}

RTbuffer g_poked_during_launch = nullptr;
std::atomic<bool> g_host_poked{false};

int PokeDuringLaunch() {
  if (!g_host_poked.load()) {
    void* p = nullptr;
    if (rtBufferMap(g_poked_during_launch, &p) == RT_SUCCESS) {
      static_cast<char*>(p)[1] = 'h';
      rtBufferUnmap(g_poked_during_launch);
    }
    g_host_poked = true;
  }
  return 0;
}

TEST_F(BufferSyncTest, HostWritesDuringALaunchReachTheDeviceThatWroteTheChunk) {
  RTbuffer io = MakeBytes(RT_BUFFER_INPUT_OUTPUT, 64, "accum");
  const uint64_t id = Id(io);
  g_poked_during_launch = io;
  g_host_poked = false;
  records[0]->answer = [id](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>& on_result) {
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!g_host_poked.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    v1::TileResult result;
    result.set_tile_index(kFinalTileIndex);
    v1::BufferRegion* region = result.add_regions();
    region->set_buffer_id(id);
    region->set_data(std::string(1, 'x'));  // byte 0 only
    on_result(std::move(result));
    return absl::OkStatus();
  };
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, &PokeDuringLaunch, 0.001), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_TRUE(g_host_poked.load());
  ASSERT_EQ(rtContextSetTimeoutCallback(ctx, nullptr, 0), RT_SUCCESS);
  records[0]->answer = nullptr;
  // The device holds its own 'x' but not the host's 'h': the chunk travels again.
  ASSERT_EQ(Launch(), RT_SUCCESS);
  auto chunks = ChunksOf(LastDelta(), id);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->data()[0], 'x');
  EXPECT_EQ(chunks[0]->data()[1], 'h');
}

TEST_F(BufferSyncTest, OutputBuffersNeverShipContents) {
  void* p;
  ASSERT_EQ(rtBufferMap(output, &p), RT_SUCCESS);
  static_cast<float*>(p)[0] = 1.0f;
  ASSERT_EQ(rtBufferUnmap(output), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_TRUE(ChunksOf(LastDelta(), Id(output)).empty());
}

TEST_F(BufferSyncTest, InputOutputContentsComeBackAndAreNotResent) {
  RTbuffer io = MakeBytes(RT_BUFFER_INPUT_OUTPUT, 64, "accum");
  const uint64_t id = Id(io);
  records[0]->answer = [id](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;
    result.set_tile_index(kFinalTileIndex);
    v1::BufferRegion* region = result.add_regions();
    region->set_buffer_id(id);
    region->set_data(std::string(64, 'x'));
    on_result(std::move(result));
    return absl::OkStatus();
  };
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(ChunksOf(LastDelta(), id).size(), 1u);
  void* p;
  ASSERT_EQ(rtBufferMap(io, &p), RT_SUCCESS);
  EXPECT_EQ(std::string(static_cast<char*>(p), 64), std::string(64, 'x'));
  ASSERT_EQ(rtBufferUnmap(io), RT_SUCCESS);
  // The device already holds what it sent back: nothing to resend...
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_TRUE(ChunksOf(LastDelta(), id).empty());
  // ...until the host changes it.
  Poke(io, 0, 'y');
  records[0]->answer = nullptr;
  ASSERT_EQ(Launch(), RT_SUCCESS);
  auto chunks = ChunksOf(LastDelta(), id);
  ASSERT_EQ(chunks.size(), 1u);
  EXPECT_EQ(chunks[0]->data()[0], 'y');
}

TEST_F(BufferSyncTest, GpuLocalBuffersBroadcastHostWritesOnly) {
  RTbuffer local = MakeBytes(RT_BUFFER_INPUT_OUTPUT | RT_BUFFER_GPU_LOCAL, 32, "seeds");
  const uint64_t id = Id(local);
  records[0]->answer = [id](const v1::LaunchRequest&, const std::atomic<bool>&,
                            const std::function<void(v1::TileResult &&)>& on_result) {
    v1::TileResult result;  // devices must not send GPU_LOCAL data; if one does, it is ignored
    v1::BufferRegion* region = result.add_regions();
    region->set_buffer_id(id);
    region->set_data(std::string(32, 'd'));
    on_result(std::move(result));
    return absl::OkStatus();
  };
  Poke(local, 1, 'h');
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(ChunksOf(LastDelta(), id).size(), 1u);
  void* p;
  ASSERT_EQ(rtBufferMap(local, &p), RT_SUCCESS);
  EXPECT_EQ(static_cast<char*>(p)[0], '\0');
  EXPECT_EQ(static_cast<char*>(p)[1], 'h');
  ASSERT_EQ(rtBufferUnmap(local), RT_SUCCESS);  // a map is a host write: broadcast again
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(ChunksOf(LastDelta(), id).size(), 1u);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_TRUE(ChunksOf(LastDelta(), id).empty());
}

TEST_F(BufferSyncTest, StructureChangesMarkAccelerationsDirty) {
  RTbuffer vertices = nullptr;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &vertices), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(vertices, RT_FORMAT_FLOAT3), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(vertices, 3), RT_SUCCESS);
  RTvariable vb;
  ASSERT_EQ(rtGeometryDeclareVariable(geometry, "vertex_buffer", &vb), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(vb, vertices), RT_SUCCESS);
  RTbuffer colors = MakeBytes(RT_BUFFER_INPUT, 4, "colors");
  RTvariable cv;
  ASSERT_EQ(rtMaterialDeclareVariable(material, "colors", &cv), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(cv, colors), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);

  auto dirty = [](RTacceleration a) {
    int d = -1;
    EXPECT_EQ(rtAccelerationIsDirty(a, &d), RT_SUCCESS);
    return d;
  };
  EXPECT_EQ(dirty(geometry_accel), 0);
  EXPECT_EQ(dirty(group_accel), 0);

  // A buffer only materials use does not move geometry.
  Poke(colors, 0, 1);
  EXPECT_EQ(dirty(geometry_accel), 0);
  // Mapping a vertex buffer does, all the way up.
  void* p;
  ASSERT_EQ(rtBufferMap(vertices, &p), RT_SUCCESS);
  ASSERT_EQ(rtBufferUnmap(vertices), RT_SUCCESS);
  EXPECT_EQ(dirty(geometry_accel), 1);
  EXPECT_EQ(dirty(group_accel), 1);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(dirty(geometry_accel), 0);
  // The delta carried the new epochs.
  int accels = 0;
  for (const v1::Object& o : LastDelta().objects()) accels += o.has_acceleration();
  EXPECT_EQ(accels, 2);

  // Primitive count, programs and rtGeometryMarkDirty.
  ASSERT_EQ(rtGeometrySetPrimitiveCount(geometry, 2), RT_SUCCESS);
  EXPECT_EQ(dirty(geometry_accel), 1);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtGeometryMarkDirty(geometry), RT_SUCCESS);
  int gdirty = 0;
  ASSERT_EQ(rtGeometryIsDirty(geometry, &gdirty), RT_SUCCESS);
  EXPECT_EQ(gdirty, 1);
  EXPECT_EQ(dirty(geometry_accel), 1);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtGeometryIsDirty(geometry, &gdirty), RT_SUCCESS);
  EXPECT_EQ(gdirty, 0);

  // A transform's matrix moves its subtree within the group, not the geometry itself.
  const float m[16] = {1, 0, 0, 5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ASSERT_EQ(rtTransformSetMatrix(transform, 0, m, nullptr), RT_SUCCESS);
  EXPECT_EQ(dirty(geometry_accel), 0);
  EXPECT_EQ(dirty(group_accel), 1);
  ASSERT_EQ(Launch(), RT_SUCCESS);

  // Explicit MarkDirty bumps the build epoch the device sees.
  ASSERT_EQ(rtAccelerationMarkDirty(geometry_accel), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(LastDelta().objects_size(), 1);
  EXPECT_TRUE(LastDelta().objects(0).has_acceleration());
  EXPECT_GT(LastDelta().objects(0).acceleration().build_epoch(), 1u);
}

}  // namespace
}  // namespace tessera::test
