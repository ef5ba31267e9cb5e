// An application's view of the CUDA runtime subset: cudaMalloc and friends come from
// libtessera.so, with the headers of the OptiX 7 include root.
#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <vector>

namespace {

TEST(CudaExportsTest, LibtesseraGivesTheCudaRuntime) {
  ASSERT_EQ(cudaFree(nullptr), cudaSuccess);  // the usual initialization
  int count = 0;
  ASSERT_EQ(cudaGetDeviceCount(&count), cudaSuccess);
  EXPECT_EQ(count, 1);
  void* d = nullptr;
  ASSERT_EQ(cudaMalloc(&d, 1000), cudaSuccess);
  std::vector<int> in(250), out(250);
  for (int i = 0; i < 250; ++i) in[i] = i * i;
  ASSERT_EQ(cudaMemcpy(d, in.data(), 1000, cudaMemcpyHostToDevice), cudaSuccess);
  ASSERT_EQ(cudaMemcpy(out.data(), d, 1000, cudaMemcpyDeviceToHost), cudaSuccess);
  EXPECT_EQ(in, out);
  ASSERT_EQ(cudaFree(d), cudaSuccess);
  EXPECT_EQ(cudaFree(d), cudaErrorInvalidDevicePointer);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidDevicePointer);
  EXPECT_EQ(cudaGetLastError(), cudaSuccess);
}

}  // namespace
