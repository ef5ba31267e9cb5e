// The CUDA runtime subset of the OptiX 7 layer over Tessera's device memory: allocations at the
// arena's addresses with cudaMalloc's alignment, copies in every direction with the pointers
// checked against their kind, sticky-until-read errors, streams and events as checked handles,
// and the chunks host writes mark for the next launch to ship.
#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "host_device_memory.h"

namespace {

using tessera::optix7::HostDeviceMemory;

uintptr_t Address(const void* p) { return reinterpret_cast<uintptr_t>(p); }

HostDeviceMemory& Memory() {
  auto m = HostDeviceMemory::Get();
  EXPECT_TRUE(m.ok()) << m.status();
  return **m;
}

class CudaRuntimeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    (void)cudaGetLastError();
    (void)Memory().TakeWrittenChunks();
  }
  void* Malloc(size_t bytes) {
    void* p = nullptr;
    EXPECT_EQ(cudaMalloc(&p, bytes), cudaSuccess);
    return p;
  }
};

// With one CUDA device per Tessera device, a device's launches ship its own allocations and those
// of the devices it enabled peer access to (launch_target.cc asks Allocations(device)).
TEST_F(CudaRuntimeTest, ADeviceReachesItsOwnAllocationsAndThoseOfItsPeers) {
  HostDeviceMemory& m = Memory();
  auto a = m.Allocate(1000, /*owner=*/5);
  auto b = m.Allocate(1000, /*owner=*/6);
  ASSERT_TRUE(a.ok() && b.ok());
  auto has = [&](int device, uintptr_t address) {
    for (const auto& [at, size] : m.Allocations(device)) {
      if (at == address) return true;
    }
    return false;
  };
  EXPECT_TRUE(has(5, *a));
  EXPECT_FALSE(has(5, *b));
  EXPECT_TRUE(has(HostDeviceMemory::kAllDevices, *a) && has(HostDeviceMemory::kAllDevices, *b));
  EXPECT_EQ(m.OwnerOf(*b + 10), 6);
  const uint64_t generation = m.allocation_generation();
  ASSERT_TRUE(m.SetPeerAccess(5, 6, true));
  EXPECT_FALSE(m.SetPeerAccess(5, 6, true));
  EXPECT_NE(m.allocation_generation(), generation);  // devices take the new list
  EXPECT_TRUE(has(5, *b));
  EXPECT_FALSE(has(6, *a));  // access is one way
  ASSERT_TRUE(m.SetPeerAccess(5, 6, false));
  EXPECT_FALSE(has(5, *b));
  EXPECT_TRUE(m.Free(*a).ok());
  EXPECT_TRUE(m.Free(*b).ok());
  EXPECT_EQ(m.OwnerOf(*a), -1);
}

// What programs of one launch target wrote reaches another target's devices by chunk, as host
// writes do; the writing target's own devices take it as runs instead (launch_target.cc).
TEST_F(CudaRuntimeTest, ChunksWrittenByAnotherTargetsProgramsAreItsToShip) {
  HostDeviceMemory& m = Memory();
  void* p = Malloc(1000);
  const uint64_t since = m.epoch();
  m.MarkWritten(Address(p), 100, /*device_writer=*/41);
  auto chunks = [&](uint64_t except) {
    std::vector<uintptr_t> out;
    for (const auto& [chunk, epoch] : m.ChunksWrittenSince(since, except)) out.push_back(chunk);
    return out;
  };
  EXPECT_TRUE(chunks(41).empty());  // the writer's own devices got runs
  EXPECT_EQ(chunks(42), std::vector<uintptr_t>{m.ChunkOf(Address(p))});
  EXPECT_EQ(chunks(0), std::vector<uintptr_t>{m.ChunkOf(Address(p))});
  const uint64_t later = m.epoch();
  m.MarkWritten(Address(p), 100, 42);  // a later write by another target does not hide 41's
  EXPECT_EQ(m.ChunksWrittenSince(later, 41).size(), 1u);
  EXPECT_TRUE(m.ChunksWrittenSince(later, 42).empty());
  EXPECT_EQ(cudaFree(p), cudaSuccess);
}

TEST_F(CudaRuntimeTest, AllocationsLieInTheArenaAlignedLikeCudaMallocs) {
  void* a = Malloc(3);
  void* b = Malloc(1000);
  EXPECT_GE(Address(a), tessera::memory::kDefaultArenaBase);
  EXPECT_EQ(Address(a) % 256, 0u);
  EXPECT_EQ(Address(b) % 256, 0u);
  EXPECT_NE(a, b);
  std::memset(b, 7, 1000);  // committed: the host reaches its copy directly
  void* none = reinterpret_cast<void*>(1);
  EXPECT_EQ(cudaMalloc(&none, 0), cudaSuccess);  // as CUDA: nothing, a null pointer
  EXPECT_EQ(none, nullptr);
  size_t free = 0, total = 0;
  ASSERT_EQ(cudaMemGetInfo(&free, &total), cudaSuccess);
  EXPECT_EQ(total, tessera::memory::kDefaultArenaSize);
  EXPECT_LE(free, total - 1024);
  EXPECT_EQ(cudaFree(a), cudaSuccess);
  EXPECT_EQ(cudaFree(b), cudaSuccess);
  void* huge = nullptr;
  EXPECT_EQ(cudaMalloc(&huge, tessera::memory::kDefaultArenaSize + 1), cudaErrorMemoryAllocation);
  EXPECT_EQ(huge, nullptr);
}

TEST_F(CudaRuntimeTest, CopiesInEveryDirectionAndByWhereThePointersPoint) {
  std::vector<float> in(64), out(64, -1.f);
  for (int i = 0; i < 64; ++i) in[i] = i * 0.5f;
  void* d = Malloc(256);
  void* e = Malloc(256);
  ASSERT_EQ(cudaMemcpy(d, in.data(), 256, cudaMemcpyHostToDevice), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(e, d, 256, cudaMemcpyDeviceToDevice), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(out.data(), e, 256, cudaMemcpyDeviceToHost), cudaSuccess);
  EXPECT_EQ(in, out);
  std::fill(out.begin(), out.end(), 0.f);
  ASSERT_EQ(cudaMemcpy(out.data(), d, 256, cudaMemcpyDefault), cudaSuccess);
  EXPECT_EQ(in, out);
  ASSERT_EQ(cudaMemcpyAsync(e, in.data(), 128, cudaMemcpyDefault, nullptr), cudaSuccess);
  ASSERT_EQ(cudaMemset(d, 0xFF, 16), cudaSuccess);
  EXPECT_EQ(static_cast<unsigned char*>(d)[15], 0xFF);
  EXPECT_EQ(static_cast<unsigned char*>(d)[16], static_cast<unsigned char*>(e)[16]);

  // 2D: rows of 12 bytes out of a 32-byte pitch.
  size_t pitch = 0;
  void* p = nullptr;
  ASSERT_EQ(cudaMallocPitch(&p, &pitch, 12, 4), cudaSuccess);
  EXPECT_EQ(pitch % 256, 0u);
  std::vector<unsigned char> rows(32 * 4);
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<unsigned char>(i);
  ASSERT_EQ(cudaMemcpy2D(p, pitch, rows.data(), 32, 12, 4, cudaMemcpyHostToDevice), cudaSuccess);
  EXPECT_EQ(static_cast<unsigned char*>(p)[pitch * 3 + 11], rows[32 * 3 + 11]);
  EXPECT_EQ(cudaMemcpy2D(p, 8, rows.data(), 32, 12, 4, cudaMemcpyHostToDevice),
            cudaErrorInvalidPitchValue);
  for (void* q : {d, e, p}) EXPECT_EQ(cudaFree(q), cudaSuccess);
}

TEST_F(CudaRuntimeTest, PointersThatAreNotWhereTheKindSaysAreRefused) {
  std::vector<char> host(512);
  void* d = Malloc(256);
  // A host pointer as the device side, a device pointer as the host side, a copy past the end
  // of the allocation, a freed allocation: errors, and nothing is written.
  EXPECT_EQ(cudaMemcpy(host.data(), host.data() + 256, 16, cudaMemcpyHostToDevice),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy(d, host.data(), 16, cudaMemcpyDeviceToHost),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy(d, host.data(), 257, cudaMemcpyHostToDevice),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy(d, host.data(), 16, static_cast<cudaMemcpyKind>(9)),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy(nullptr, host.data(), 16, cudaMemcpyHostToDevice), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMemset(static_cast<char*>(d) + 200, 0, 100), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMemset(host.data(), 0, 1), cudaErrorInvalidValue);
  EXPECT_EQ(cudaFree(static_cast<char*>(d) + 8), cudaErrorInvalidDevicePointer);
  EXPECT_EQ(cudaFree(host.data()), cudaErrorInvalidDevicePointer);
  ASSERT_EQ(cudaFree(d), cudaSuccess);
  EXPECT_EQ(cudaMemcpy(d, host.data(), 16, cudaMemcpyHostToDevice),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaFree(d), cudaErrorInvalidDevicePointer);
}

TEST_F(CudaRuntimeTest, TheLastErrorStaysUntilRead) {
  EXPECT_EQ(cudaSetDevice(3), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaSetDevice(0), cudaSuccess);  // a success does not clear it
  EXPECT_EQ(cudaPeekAtLastError(), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaGetLastError(), cudaSuccess);
  EXPECT_STREQ(cudaGetErrorName(cudaErrorInvalidDevice), "cudaErrorInvalidDevice");
  EXPECT_STREQ(cudaGetErrorString(cudaSuccess), "no error");
  EXPECT_NE(std::string(cudaGetErrorString(cudaErrorInvalidMemcpyDirection)).find("cudaMalloc"),
            std::string::npos);
  EXPECT_STREQ(cudaGetErrorName(static_cast<cudaError_t>(12345)), "cudaErrorUnknown");
}

TEST_F(CudaRuntimeTest, DevicePropertiesDescribeTheCpuDevice) {
  cudaDeviceProp prop;
  ASSERT_EQ(cudaGetDeviceProperties(&prop, 0), cudaSuccess);
  EXPECT_STREQ(prop.name, "Tessera CPU device");
  EXPECT_EQ(prop.totalGlobalMem, tessera::memory::kDefaultArenaSize);
  EXPECT_GE(prop.multiProcessorCount, 1);
  EXPECT_EQ(cudaGetDeviceProperties(&prop, 1), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaGetDeviceProperties(nullptr, 0), cudaErrorInvalidValue);
  int device = -1;
  ASSERT_EQ(cudaGetDevice(&device), cudaSuccess);
  EXPECT_EQ(device, 0);
  EXPECT_EQ(cudaDeviceSynchronize(), cudaSuccess);
  (void)cudaGetLastError();
}

TEST_F(CudaRuntimeTest, StreamsAndEventsAreCheckedHandles) {
  cudaStream_t s = nullptr;
  ASSERT_EQ(cudaStreamCreate(&s), cudaSuccess);
  cudaEvent_t start = nullptr, end = nullptr;
  ASSERT_EQ(cudaEventCreate(&start), cudaSuccess);
  ASSERT_EQ(cudaEventCreateWithFlags(&end, 0), cudaSuccess);
  float ms = -1.f;
  EXPECT_EQ(cudaEventElapsedTime(&ms, start, end), cudaErrorInvalidResourceHandle);  // unrecorded
  ASSERT_EQ(cudaEventRecord(start, s), cudaSuccess);
  ASSERT_EQ(cudaStreamWaitEvent(s, start, 0), cudaSuccess);
  ASSERT_EQ(cudaEventRecord(end, nullptr), cudaSuccess);
  ASSERT_EQ(cudaEventSynchronize(end), cudaSuccess);
  ASSERT_EQ(cudaEventElapsedTime(&ms, start, end), cudaSuccess);
  EXPECT_GE(ms, 0.f);
  EXPECT_EQ(cudaStreamSynchronize(s), cudaSuccess);
  EXPECT_EQ(cudaStreamSynchronize(cudaStreamLegacy), cudaSuccess);
  EXPECT_EQ(cudaStreamDestroy(s), cudaSuccess);
  EXPECT_EQ(cudaStreamDestroy(s), cudaErrorInvalidResourceHandle);  // twice
  EXPECT_EQ(cudaStreamDestroy(cudaStreamLegacy), cudaErrorInvalidResourceHandle);
  EXPECT_EQ(cudaStreamSynchronize(s), cudaErrorInvalidResourceHandle);
  EXPECT_EQ(cudaEventDestroy(start), cudaSuccess);
  EXPECT_EQ(cudaEventRecord(start, nullptr), cudaErrorInvalidResourceHandle);
  EXPECT_EQ(cudaEventDestroy(end), cudaSuccess);
  (void)cudaGetLastError();
}

// Host writes mark the chunks a launch will ship, and only those.
TEST_F(CudaRuntimeTest, HostWritesMarkTheChunksTheyTouch) {
  constexpr size_t kChunk = HostDeviceMemory::kChunkBytes;
  void* big = Malloc(4 * kChunk);
  std::vector<char> data(kChunk + 10, 1);
  ASSERT_EQ(cudaMemcpy(static_cast<char*>(big) + kChunk - 5, data.data(), kChunk + 10,
                       cudaMemcpyHostToDevice),
            cudaSuccess);
  const uintptr_t base = tessera::memory::kDefaultArenaBase;
  const uintptr_t first = base + (Address(big) - base) / kChunk * kChunk;
  std::vector<uintptr_t> chunks = Memory().TakeWrittenChunks();
  // The write spans the end of the allocation's first chunk, the whole second, the start of the
  // third.
  std::vector<uintptr_t> expected;
  for (uintptr_t c = base + (Address(big) + kChunk - 5 - base) / kChunk * kChunk;
       c < Address(big) + 2 * kChunk + 5; c += kChunk) {
    expected.push_back(c);
  }
  EXPECT_EQ(chunks, expected);
  EXPECT_GE(chunks.front(), first);
  EXPECT_TRUE(Memory().TakeWrittenChunks().empty());  // taken once
  std::vector<char> back(16);
  ASSERT_EQ(cudaMemcpy(back.data(), big, 16, cudaMemcpyDeviceToHost), cudaSuccess);
  EXPECT_TRUE(Memory().TakeWrittenChunks().empty());  // reads mark nothing
  ASSERT_EQ(cudaMemset(static_cast<char*>(big) + 3 * kChunk, 0, 1), cudaSuccess);
  EXPECT_EQ(Memory().TakeWrittenChunks().size(), 1u);
  ASSERT_EQ(cudaFree(big), cudaSuccess);
}

}  // namespace

namespace {

// cudaDeviceReset frees the current device's allocations, as CUDA destroys its context.
TEST(CudaDeviceResetTest, FreesTheDevicesAllocations) {
  void* a = nullptr;
  void* b = nullptr;
  ASSERT_EQ(cudaMalloc(&a, 1000), cudaSuccess);
  ASSERT_EQ(cudaMallocManaged(&b, 3000), cudaSuccess);
  EXPECT_TRUE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), 1000));
  EXPECT_EQ(cudaDeviceReset(), cudaSuccess);
  EXPECT_FALSE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), 1));
  EXPECT_FALSE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(b), 1));
  EXPECT_EQ(cudaFree(a), cudaErrorInvalidDevicePointer);  // gone already
  (void)cudaGetLastError();
  void* c = nullptr;
  EXPECT_EQ(cudaMalloc(&c, 16), cudaSuccess);  // the device works on
  EXPECT_EQ(cudaFree(c), cudaSuccess);
}

}  // namespace
