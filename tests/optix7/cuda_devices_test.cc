// CUDA devices as an application sees them from libtessera.so (docs/optix7.md, "Devices"): one by
// default, one per Tessera device with TESSERA_CUDA_DEVICES=each; the current device per thread;
// peer access and peer copies; the driver API's contexts naming their device.
#include <cuda.h>
#include <cuda_runtime.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

class CudaDevicesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("TESSERA_DEVICES", "inproc,inproc,inproc", 1);
    setenv("TESSERA_CUDA_DEVICES", "each", 1);
  }
  void TearDown() override {
    cudaSetDevice(0);
    (void)cudaGetLastError();
    unsetenv("TESSERA_CUDA_DEVICES");
    unsetenv("TESSERA_DEVICES");
  }
};

TEST_F(CudaDevicesTest, OneDeviceByDefaultAndEachTesseraDeviceWhenAsked) {
  int count = 0;
  ASSERT_EQ(cudaGetDeviceCount(&count), cudaSuccess);
  EXPECT_EQ(count, 3);
  cudaDeviceProp prop;
  ASSERT_EQ(cudaGetDeviceProperties(&prop, 2), cudaSuccess);
  EXPECT_NE(std::string(prop.name).find("inproc"), std::string::npos) << prop.name;
  EXPECT_GE(prop.multiProcessorCount, 1);
  EXPECT_EQ(cudaGetDeviceProperties(&prop, 3), cudaErrorInvalidDevice);

  setenv("TESSERA_CUDA_DEVICES", "one", 1);
  ASSERT_EQ(cudaGetDeviceCount(&count), cudaSuccess);
  EXPECT_EQ(count, 1);
  EXPECT_EQ(cudaSetDevice(1), cudaErrorInvalidDevice);
  unsetenv("TESSERA_CUDA_DEVICES");
  ASSERT_EQ(cudaGetDeviceCount(&count), cudaSuccess);
  EXPECT_EQ(count, 1);
}

TEST_F(CudaDevicesTest, TheCurrentDeviceIsPerThreadAndCheckedAsCudaChecksIt) {
  ASSERT_EQ(cudaSetDevice(2), cudaSuccess);
  int device = -1;
  ASSERT_EQ(cudaGetDevice(&device), cudaSuccess);
  EXPECT_EQ(device, 2);
  int other = -1;
  std::thread([&] { cudaGetDevice(&other); }).join();
  EXPECT_EQ(other, 0);  // a new thread starts on device 0
  EXPECT_EQ(cudaSetDevice(3), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaSetDevice(-1), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidDevice);
  ASSERT_EQ(cudaGetDevice(&device), cudaSuccess);
  EXPECT_EQ(device, 2);  // a refused ordinal changes nothing
}

TEST_F(CudaDevicesTest, PeerAccessAndPeerCopies) {
  int can = -1;
  ASSERT_EQ(cudaDeviceCanAccessPeer(&can, 0, 2), cudaSuccess);
  EXPECT_EQ(can, 1);
  ASSERT_EQ(cudaDeviceCanAccessPeer(&can, 1, 1), cudaSuccess);
  EXPECT_EQ(can, 0);
  EXPECT_EQ(cudaDeviceCanAccessPeer(&can, 0, 3), cudaErrorInvalidDevice);

  ASSERT_EQ(cudaSetDevice(1), cudaSuccess);
  EXPECT_EQ(cudaDeviceEnablePeerAccess(1, 0), cudaErrorInvalidDevice);  // itself
  EXPECT_EQ(cudaDeviceEnablePeerAccess(2, 1), cudaErrorInvalidValue);   // flags must be 0
  ASSERT_EQ(cudaDeviceEnablePeerAccess(2, 0), cudaSuccess);
  EXPECT_EQ(cudaDeviceEnablePeerAccess(2, 0), cudaErrorPeerAccessAlreadyEnabled);
  ASSERT_EQ(cudaDeviceDisablePeerAccess(2), cudaSuccess);
  EXPECT_EQ(cudaDeviceDisablePeerAccess(2), cudaErrorPeerAccessNotEnabled);
  (void)cudaGetLastError();

  void* on1 = nullptr;
  ASSERT_EQ(cudaMalloc(&on1, 1000), cudaSuccess);
  ASSERT_EQ(cudaSetDevice(2), cudaSuccess);
  void* on2 = nullptr;
  ASSERT_EQ(cudaMalloc(&on2, 1000), cudaSuccess);
  EXPECT_NE(on1, on2);  // one address range: pointers are unique across devices
  std::vector<unsigned char> in(1000), out(1000);
  for (size_t i = 0; i < in.size(); ++i) in[i] = static_cast<unsigned char>(i * 7);
  ASSERT_EQ(cudaMemcpy(on1, in.data(), in.size(), cudaMemcpyHostToDevice), cudaSuccess);
  ASSERT_EQ(cudaMemcpyPeer(on2, 2, on1, 1, in.size()), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(out.data(), on2, out.size(), cudaMemcpyDeviceToHost), cudaSuccess);
  EXPECT_EQ(in, out);
  EXPECT_EQ(cudaMemcpyPeer(on2, 3, on1, 1, 10), cudaErrorInvalidDevice);
  EXPECT_EQ(cudaMemcpyPeerAsync(on2, 2, on1, 1, 10, nullptr), cudaSuccess);
  EXPECT_EQ(cudaMemcpyPeer(on2, 2, in.data(), 1, 10), cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaFree(on1), cudaSuccess);
  EXPECT_EQ(cudaFree(on2), cudaSuccess);
}

TEST_F(CudaDevicesTest, DriverContextsNameTheirDeviceAndMakeItCurrent) {
  ASSERT_EQ(cuInit(0), CUDA_SUCCESS);
  int count = 0;
  ASSERT_EQ(cuDeviceGetCount(&count), CUDA_SUCCESS);
  EXPECT_EQ(count, 3);
  CUdevice dev = -1;
  ASSERT_EQ(cuDeviceGet(&dev, 2), CUDA_SUCCESS);
  EXPECT_EQ(cuDeviceGet(&dev, 3), CUDA_ERROR_INVALID_DEVICE);
  char name[64];
  ASSERT_EQ(cuDeviceGetName(name, sizeof(name), 1), CUDA_SUCCESS);
  EXPECT_NE(std::string(name).find("inproc"), std::string::npos);

  // Without a context of its own the thread's current one is its device's primary context.
  ASSERT_EQ(cudaSetDevice(1), cudaSuccess);
  CUcontext primary1 = nullptr, again = nullptr;
  ASSERT_EQ(cuCtxGetCurrent(&primary1), CUDA_SUCCESS);
  ASSERT_EQ(cuCtxGetCurrent(&again), CUDA_SUCCESS);
  EXPECT_NE(primary1, nullptr);
  EXPECT_EQ(primary1, again);

  CUcontext created = nullptr;
  ASSERT_EQ(cuCtxCreate(&created, 0, 2), CUDA_SUCCESS);
  int device = -1;
  ASSERT_EQ(cudaGetDevice(&device), cudaSuccess);
  EXPECT_EQ(device, 2);  // the runtime follows the current context
  CUcontext popped = nullptr;
  ASSERT_EQ(cuCtxPopCurrent(&popped), CUDA_SUCCESS);
  EXPECT_EQ(popped, created);
  EXPECT_EQ(cuCtxPopCurrent(&popped), CUDA_ERROR_INVALID_CONTEXT);
  ASSERT_EQ(cuCtxPushCurrent(created), CUDA_SUCCESS);
  ASSERT_EQ(cuCtxDestroy(created), CUDA_SUCCESS);
  EXPECT_EQ(cuCtxDestroy(created), CUDA_ERROR_INVALID_CONTEXT);
  EXPECT_EQ(cuCtxDestroy(primary1), CUDA_ERROR_INVALID_CONTEXT);  // primary contexts stay
  EXPECT_EQ(cuCtxSetCurrent(reinterpret_cast<CUcontext>(&count)), CUDA_ERROR_INVALID_CONTEXT);
  const char* text = nullptr;
  ASSERT_EQ(cuGetErrorName(CUDA_ERROR_INVALID_CONTEXT, &text), CUDA_SUCCESS);
  EXPECT_STREQ(text, "CUDA_ERROR_INVALID_CONTEXT");
}

}  // namespace
