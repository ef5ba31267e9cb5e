// CUDA arrays, copies into them and texture objects (api/optix7/cuda_arrays.cc,
// cuda_array_copies.cc, cuda_textures.cc) as the host sees them: shapes and formats CUDA takes
// and refuses with its error codes, bytes where copies put them and marked for shipping, and the
// descriptor a texture object is in device memory. tests/optix7_textures samples them in programs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <vector>

#include "cuda_arrays.h"
#include "cuda_runtime.h"
#include "host_device_memory.h"
#include "tessera/detail/texture_fast.h"
#include "tessera/detail/texture_modes.h"
#include "tessera/optix7_texture_abi.h"

namespace tessera::optix7 {
namespace {

namespace tx = tessera::texture;

HostDeviceMemory& Memory() { return **HostDeviceMemory::Get(); }

class CudaTextureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(HostDeviceMemory::Get().ok());
    (void)cudaGetLastError();
  }
  void TearDown() override {
    for (cudaTextureObject_t t : textures_) EXPECT_EQ(cudaDestroyTextureObject(t), cudaSuccess);
    for (cudaArray_t a : arrays_) EXPECT_EQ(cudaFreeArray(a), cudaSuccess);
  }
  cudaArray_t Array(cudaChannelFormatDesc desc, cudaExtent e, unsigned flags = 0) {
    cudaArray_t a = nullptr;
    EXPECT_EQ(cudaMalloc3DArray(&a, &desc, e, flags), cudaSuccess);
    if (a != nullptr) arrays_.push_back(a);
    return a;
  }
  cudaTextureObject_t Texture(const cudaResourceDesc& r, const cudaTextureDesc& t) {
    cudaTextureObject_t o = 0;
    EXPECT_EQ(cudaCreateTextureObject(&o, &r, &t, nullptr), cudaSuccess);
    if (o != 0) textures_.push_back(o);
    return o;
  }
  static const TesseraCudaTextureObject& Descriptor(cudaTextureObject_t o) {
    return *reinterpret_cast<const TesseraCudaTextureObject*>(o);
  }
  static cudaResourceDesc ArrayResource(cudaArray_t a) {
    cudaResourceDesc r = {};
    r.resType = cudaResourceTypeArray;
    r.res.array.array = a;
    return r;
  }
  std::vector<cudaArray_t> arrays_;
  std::vector<cudaTextureObject_t> textures_;
};

TEST_F(CudaTextureTest, ChannelDescriptorsGiveTheSamplersFormats) {
  struct Case {
    cudaChannelFormatDesc desc;
    unsigned format, size;
  } cases[] = {
      {cudaCreateChannelDesc<uchar1>(), tx::kFormatUnsignedByte, 1},
      {cudaCreateChannelDesc<uchar2>(), tx::kFormatUnsignedByte2, 2},
      {cudaCreateChannelDesc<uchar4>(), tx::kFormatUnsignedByte4, 4},
      {cudaCreateChannelDesc<char4>(), tx::kFormatByte4, 4},
      {cudaCreateChannelDesc<ushort2>(), tx::kFormatUnsignedShort2, 4},
      {cudaCreateChannelDesc<short4>(), tx::kFormatShort4, 8},
      {cudaCreateChannelDesc<int>(), tx::kFormatInt, 4},
      {cudaCreateChannelDesc<uint4>(), tx::kFormatUnsignedInt4, 16},
      {cudaCreateChannelDesc<float2>(), tx::kFormatFloat2, 8},
      {cudaCreateChannelDesc<float4>(), tx::kFormatFloat4, 16},
      {cudaCreateChannelDesc(16, 0, 0, 0, cudaChannelFormatKindFloat), tx::kFormatHalf, 2},
      {cudaCreateChannelDesc(16, 16, 16, 16, cudaChannelFormatKindFloat), tx::kFormatHalf4, 8},
  };
  for (const Case& c : cases) {
    const std::optional<TexelFormat> f = FormatOf(c.desc);
    ASSERT_TRUE(f.has_value()) << c.desc.x << " " << c.desc.f;
    EXPECT_EQ(f->format, c.format);
    EXPECT_EQ(f->element_size, c.size);
  }
}

TEST_F(CudaTextureTest, ArraysRefuseChannelDescriptorsCudaHasNoTexelFor) {
  const cudaChannelFormatDesc bad[] = {
      cudaCreateChannelDesc(8, 8, 8, 0, cudaChannelFormatKindUnsigned),  // 3 channels
      cudaCreateChannelDesc(8, 16, 0, 0, cudaChannelFormatKindUnsigned),
      cudaCreateChannelDesc(8, 0, 0, 0, cudaChannelFormatKindFloat),
      cudaCreateChannelDesc(24, 0, 0, 0, cudaChannelFormatKindSigned),
      cudaCreateChannelDesc(0, 0, 0, 0, cudaChannelFormatKindNone),
      cudaCreateChannelDesc<double>(),  // no specialization: kind none
  };
  for (const cudaChannelFormatDesc& d : bad) {
    cudaArray_t a = reinterpret_cast<cudaArray_t>(1);
    EXPECT_EQ(cudaMallocArray(&a, &d, 4, 4), cudaErrorInvalidChannelDescriptor);
    EXPECT_EQ(a, nullptr);
    EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidChannelDescriptor);
    EXPECT_EQ(cudaGetLastError(), cudaSuccess);
  }
}

TEST_F(CudaTextureTest, ArrayShapesFollowCudaMalloc3DArray) {
  const cudaChannelFormatDesc f = cudaCreateChannelDesc<float>();
  struct Case {
    cudaExtent e;
    unsigned flags;
    unsigned ndims;
    size_t w, h, d;
  } cases[] = {
      {{8, 0, 0}, 0, 1, 8, 1, 1},
      {{8, 3, 0}, 0, 2, 8, 3, 1},
      {{8, 3, 2}, 0, 3, 8, 3, 2},
      {{8, 0, 5}, cudaArrayLayered, 1, 8, 1, 5},
      {{8, 3, 5}, cudaArrayLayered, 2, 8, 3, 5},
      {{4, 4, 6}, cudaArrayCubemap, 2, 4, 4, 6},
      {{4, 4, 12}, cudaArrayCubemap | cudaArrayLayered, 2, 4, 4, 12},
  };
  for (const Case& c : cases) {
    cudaArray_t a = Array(f, c.e, c.flags);
    ASSERT_NE(a, nullptr);
    const std::optional<CudaArray> info = TextureHandles::Get().FindArray(a);
    ASSERT_TRUE(info.has_value());
    EXPECT_EQ(info->ndims, c.ndims);
    EXPECT_EQ(info->width, c.w);
    EXPECT_EQ(info->height, c.h);
    EXPECT_EQ(info->depth, c.d);
    EXPECT_TRUE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), c.w * c.h * c.d * 4));
    cudaExtent e;
    unsigned flags = 99;
    cudaChannelFormatDesc desc;
    ASSERT_EQ(cudaArrayGetInfo(&desc, &e, &flags, a), cudaSuccess);
    EXPECT_EQ(e.width, c.e.width);
    EXPECT_EQ(e.height, c.e.height);
    EXPECT_EQ(e.depth, c.e.depth);
    EXPECT_EQ(flags, c.flags);
    EXPECT_EQ(desc.x, 32);
    EXPECT_EQ(desc.f, cudaChannelFormatKindFloat);
  }
}

TEST_F(CudaTextureTest, ArraysRefuseShapesCudaRefuses) {
  const cudaChannelFormatDesc f = cudaCreateChannelDesc<uchar4>();
  struct Case {
    cudaExtent e;
    unsigned flags;
  } cases[] = {
      {{0, 4, 0}, 0},                                     // no width
      {{4, 0, 3}, 0},                                     // depth without height, not layered
      {{131073, 0, 0}, 0},                                // past maxTexture1D
      {{16385, 4, 4}, 0},                                 // past maxTexture3D
      {{4, 4, 0}, cudaArrayLayered},                      // no layers
      {{4, 4, 2049}, cudaArrayLayered},                   // past the layer limit
      {{4, 5, 6}, cudaArrayCubemap},                      // faces are square
      {{4, 4, 5}, cudaArrayCubemap},                      // 6 faces
      {{4, 4, 13}, cudaArrayCubemap | cudaArrayLayered},  // 6 per layer
      {{4, 4, 0}, 0x100},                                 // an unknown flag
  };
  for (const Case& c : cases) {
    cudaArray_t a = reinterpret_cast<cudaArray_t>(1);
    EXPECT_EQ(cudaMalloc3DArray(&a, &f, c.e, c.flags), cudaErrorInvalidValue)
        << c.e.width << "x" << c.e.height << "x" << c.e.depth << " flags " << c.flags;
    EXPECT_EQ(a, nullptr);
  }
  cudaArray_t a = nullptr;
  EXPECT_EQ(cudaMallocArray(&a, &f, 4, 4, cudaArrayLayered), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMallocArray(nullptr, &f, 4, 4), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMallocArray(&a, nullptr, 4, 4), cudaErrorInvalidValue);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidValue);
}

TEST_F(CudaTextureTest, FreeingChecksTheHandle) {
  const cudaChannelFormatDesc f = cudaCreateChannelDesc<float>();
  cudaArray_t a = nullptr;
  ASSERT_EQ(cudaMallocArray(&a, &f, 16, 16), cudaSuccess);
  EXPECT_EQ(cudaFree(a), cudaErrorInvalidDevicePointer);  // arrays are freed with cudaFreeArray
  EXPECT_EQ(cudaFreeArray(a), cudaSuccess);
  EXPECT_EQ(cudaFreeArray(a), cudaErrorInvalidValue);
  EXPECT_FALSE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), 1));
  EXPECT_EQ(cudaFreeArray(nullptr), cudaSuccess);
  void* plain = nullptr;
  ASSERT_EQ(cudaMalloc(&plain, 64), cudaSuccess);
  EXPECT_EQ(cudaFreeArray(reinterpret_cast<cudaArray_t>(plain)), cudaErrorInvalidValue);
  EXPECT_EQ(cudaFree(plain), cudaSuccess);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidValue);
}

TEST_F(CudaTextureTest, Copy2DToArrayPlacesRowsAndMarksThemWritten) {
  const int w = 5, h = 3;
  cudaArray_t a = Array(cudaCreateChannelDesc<uchar4>(), {w, h, 0});
  std::vector<unsigned char> host(8 * 4 * h);  // rows of 8 texels, 5 used
  std::iota(host.begin(), host.end(), 1);
  (void)Memory().TakeWrittenChunks();
  ASSERT_EQ(cudaMemcpy2DToArray(a, 0, 0, host.data(), 8 * 4, w * 4, h, cudaMemcpyHostToDevice),
            cudaSuccess);
  const auto* texels = reinterpret_cast<const unsigned char*>(a);
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(std::memcmp(texels + y * w * 4, host.data() + y * 32, w * 4), 0) << "row " << y;
  }
  const std::vector<uintptr_t> written = Memory().TakeWrittenChunks();
  const uintptr_t chunk = reinterpret_cast<uintptr_t>(a) / HostDeviceMemory::kChunkBytes *
                          HostDeviceMemory::kChunkBytes;
  EXPECT_NE(std::find(written.begin(), written.end(), chunk), written.end());

  // A sub-rectangle, from device memory; and back out of the array.
  void* dev = nullptr;
  ASSERT_EQ(cudaMalloc(&dev, 8), cudaSuccess);
  const unsigned char two[8] = {9, 9, 9, 9, 8, 8, 8, 8};
  ASSERT_EQ(cudaMemcpy(dev, two, 8, cudaMemcpyHostToDevice), cudaSuccess);
  ASSERT_EQ(cudaMemcpy2DToArray(a, 4 * 4, 1, dev, 4, 4, 2, cudaMemcpyDeviceToDevice), cudaSuccess);
  EXPECT_EQ(texels[(1 * w + 4) * 4], 9);
  EXPECT_EQ(texels[(2 * w + 4) * 4], 8);
  unsigned char back[4 * 5 * 3];
  ASSERT_EQ(cudaMemcpy2DFromArray(back, w * 4, a, 0, 0, w * 4, h, cudaMemcpyDeviceToHost),
            cudaSuccess);
  EXPECT_EQ(std::memcmp(back, texels, sizeof back), 0);
  EXPECT_EQ(cudaFree(dev), cudaSuccess);
}

TEST_F(CudaTextureTest, Copy2DToArrayRefusesWhatCudaRefuses) {
  cudaArray_t a = Array(cudaCreateChannelDesc<float>(), {4, 4, 0});
  std::vector<float> host(32);
  // Past the right edge, past the bottom.
  EXPECT_EQ(cudaMemcpy2DToArray(a, 4, 0, host.data(), 16, 16, 4, cudaMemcpyHostToDevice),
            cudaErrorInvalidValue);
  EXPECT_EQ(cudaMemcpy2DToArray(a, 0, 1, host.data(), 16, 16, 4, cudaMemcpyHostToDevice),
            cudaErrorInvalidValue);
  // A row wider than its pitch; directions that do not end in device memory.
  EXPECT_EQ(cudaMemcpy2DToArray(a, 0, 0, host.data(), 8, 16, 4, cudaMemcpyHostToDevice),
            cudaErrorInvalidPitchValue);
  EXPECT_EQ(cudaMemcpy2DToArray(a, 0, 0, host.data(), 16, 16, 4, cudaMemcpyDeviceToHost),
            cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy2DToArray(a, 0, 0, host.data(), 16, 16, 4, cudaMemcpyDeviceToDevice),
            cudaErrorInvalidMemcpyDirection);  // host memory named as device memory
  EXPECT_EQ(cudaMemcpy2DToArray(nullptr, 0, 0, host.data(), 16, 16, 4, cudaMemcpyHostToDevice),
            cudaErrorInvalidValue);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidValue);
  EXPECT_EQ(cudaMemcpy2DToArray(a, 0, 0, host.data(), 16, 16, 4, cudaMemcpyDefault), cudaSuccess);
}

TEST_F(CudaTextureTest, MemcpyToArrayContinuesRowAfterRow) {
  cudaArray_t a = Array(cudaCreateChannelDesc<unsigned short>(), {4, 3, 0});
  const unsigned short run[6] = {1, 2, 3, 4, 5, 6};
  ASSERT_EQ(cudaMemcpyToArray(a, 2 * 2, 1, run, sizeof run, cudaMemcpyHostToDevice), cudaSuccess);
  const auto* t = reinterpret_cast<const unsigned short*>(a);
  EXPECT_EQ(t[1 * 4 + 2], 1);
  EXPECT_EQ(t[1 * 4 + 3], 2);
  EXPECT_EQ(t[2 * 4 + 0], 3);
  EXPECT_EQ(t[2 * 4 + 3], 6);
  EXPECT_EQ(cudaMemcpyToArray(a, 2 * 2, 2, run, sizeof run, cudaMemcpyHostToDevice),
            cudaErrorInvalidValue);  // past the end
}

TEST_F(CudaTextureTest, Memcpy3DBetweenHostArraysAndPitchedMemory) {
  const size_t w = 4, h = 3, d = 2;
  cudaArray_t a = Array(cudaCreateChannelDesc<float>(), {w, h, d});
  std::vector<float> host(w * h * d);
  std::iota(host.begin(), host.end(), 0.f);
  cudaMemcpy3DParms p = {};
  p.srcPtr = {host.data(), w * sizeof(float), w, h};
  p.dstArray = a;
  p.extent = {w, h, d};
  p.kind = cudaMemcpyHostToDevice;
  ASSERT_EQ(cudaMemcpy3D(&p), cudaSuccess);
  EXPECT_EQ(std::memcmp(reinterpret_cast<const void*>(a), host.data(), host.size() * 4), 0);

  // A 2x2x1 box at (1, 1, 1) of the array into pitched device memory at (x 8 bytes, y 1).
  void* pitched = nullptr;
  size_t pitch = 0;
  ASSERT_EQ(cudaMallocPitch(&pitched, &pitch, 16, 4), cudaSuccess);
  cudaMemcpy3DParms q = {};
  q.srcArray = a;
  q.srcPos = {1, 1, 1};
  q.dstPtr = {pitched, pitch, 4, 4};
  q.dstPos = {8, 1, 0};
  q.extent = {2, 2, 1};
  q.kind = cudaMemcpyDeviceToDevice;
  ASSERT_EQ(cudaMemcpy3D(&q), cudaSuccess);
  const auto* rows = static_cast<const unsigned char*>(pitched);
  float v[2];
  std::memcpy(v, rows + pitch + 8, 8);
  EXPECT_EQ(v[0], host[(1 * h + 1) * w + 1]);
  EXPECT_EQ(v[1], host[(1 * h + 1) * w + 2]);
  std::memcpy(v, rows + 2 * pitch + 8, 8);
  EXPECT_EQ(v[0], host[(1 * h + 2) * w + 1]);

  // Array to array, and back to the host.
  cudaArray_t b = Array(cudaCreateChannelDesc<float>(), {w, h, d});
  cudaMemcpy3DParms r = {};
  r.srcArray = a;
  r.dstArray = b;
  r.extent = {w, h, d};
  r.kind = cudaMemcpyDeviceToDevice;
  ASSERT_EQ(cudaMemcpy3D(&r), cudaSuccess);
  std::vector<float> back(host.size());
  cudaMemcpy3DParms s = {};
  s.srcArray = b;
  s.dstPtr = {back.data(), w * sizeof(float), w, h};
  s.extent = {w, h, d};
  s.kind = cudaMemcpyDeviceToHost;
  ASSERT_EQ(cudaMemcpy3D(&s), cudaSuccess);
  EXPECT_EQ(back, host);

  // Two sources; a box past the array; a host array kind.
  cudaMemcpy3DParms bad = p;
  bad.srcArray = b;
  EXPECT_EQ(cudaMemcpy3D(&bad), cudaErrorInvalidValue);
  bad = p;
  bad.dstPos = {1, 0, 0};
  EXPECT_EQ(cudaMemcpy3D(&bad), cudaErrorInvalidValue);
  bad = p;
  bad.kind = cudaMemcpyHostToHost;
  EXPECT_EQ(cudaMemcpy3D(&bad), cudaErrorInvalidMemcpyDirection);
  EXPECT_EQ(cudaMemcpy3D(nullptr), cudaErrorInvalidValue);
  EXPECT_EQ(cudaFree(pitched), cudaSuccess);
}

TEST_F(CudaTextureTest, ATextureObjectIsTheSamplersViewInDeviceMemory) {
  cudaArray_t a = Array(cudaCreateChannelDesc<uchar4>(), {16, 8, 0});
  cudaTextureDesc t = {};
  t.addressMode[0] = cudaAddressModeWrap;
  t.addressMode[1] = cudaAddressModeWrap;
  t.filterMode = cudaFilterModeLinear;
  t.readMode = cudaReadModeNormalizedFloat;
  t.normalizedCoords = 1;
  const cudaTextureObject_t o = Texture(ArrayResource(a), t);
  ASSERT_NE(o, 0u);
  EXPECT_TRUE(Memory().IsAllocated(o, sizeof(TesseraCudaTextureObject)));
  const TesseraCudaTextureObject& d = Descriptor(o);
  EXPECT_EQ(d.magic, TESSERA_CUDA_TEXTURE_MAGIC);
  const TesseraTextureView& v = d.view;
  EXPECT_EQ(v.levels[0].data, static_cast<const void*>(a));
  EXPECT_EQ(v.levels[0].width, 16u);
  EXPECT_EQ(v.levels[0].height, 8u);
  EXPECT_EQ(v.levels[0].depth, 1u);
  EXPECT_EQ(v.levels[0].pitch, 0u);
  EXPECT_EQ(v.level_count, 1u);
  EXPECT_EQ(v.dimensionality, 2u);
  EXPECT_EQ(v.format, tx::kFormatUnsignedByte4);
  EXPECT_EQ(v.element_size, 4u);
  EXPECT_EQ(v.wrap[0], tx::kWrapRepeat);
  EXPECT_EQ(v.min_filter, tx::kFilterLinear);
  EXPECT_EQ(v.mag_filter, tx::kFilterLinear);
  EXPECT_EQ(v.mip_filter, tx::kFilterNone);
  EXPECT_EQ(v.read_mode, tx::kReadNormalizedFloat);
  EXPECT_EQ(v.index_mode, tx::kIndexNormalizedCoordinates);
  EXPECT_EQ(v.fast, tx::kFastBilinearRgba8Repeat);  // the OptiX 3 engine's fast lookup too

  // The other modes.
  t.addressMode[0] = cudaAddressModeMirror;
  t.addressMode[1] = cudaAddressModeClamp;
  t.addressMode[2] = cudaAddressModeBorder;
  t.filterMode = cudaFilterModePoint;
  t.sRGB = 1;
  t.normalizedCoords = 0;
  t.maxAnisotropy = 40;
  const TesseraTextureView& w = Descriptor(Texture(ArrayResource(a), t)).view;
  EXPECT_EQ(w.wrap[0], tx::kWrapMirror);
  EXPECT_EQ(w.wrap[1], tx::kWrapClampToEdge);
  EXPECT_EQ(w.wrap[2], tx::kWrapClampToBorder);
  EXPECT_EQ(w.min_filter, tx::kFilterNearest);
  EXPECT_EQ(w.read_mode, tx::kReadNormalizedFloatSrgb);
  EXPECT_EQ(w.index_mode, tx::kIndexArrayIndex);
  EXPECT_EQ(w.max_anisotropy, 16.f);
  EXPECT_EQ(w.fast, tx::kFastNone);
}

TEST_F(CudaTextureTest, PitchedAndLinearMemory) {
  void* p = nullptr;
  size_t pitch = 0;
  ASSERT_EQ(cudaMallocPitch(&p, &pitch, 10 * 8, 6), cudaSuccess);
  cudaResourceDesc r = {};
  r.resType = cudaResourceTypePitch2D;
  r.res.pitch2D.devPtr = p;
  r.res.pitch2D.desc = cudaCreateChannelDesc<ushort4>();
  r.res.pitch2D.width = 10;
  r.res.pitch2D.height = 6;
  r.res.pitch2D.pitchInBytes = pitch;
  cudaTextureDesc t = {};
  t.readMode = cudaReadModeNormalizedFloat;
  const TesseraTextureView& v = Descriptor(Texture(r, t)).view;
  EXPECT_EQ(v.levels[0].data, p);
  EXPECT_EQ(v.levels[0].width, 10u);
  EXPECT_EQ(v.levels[0].pitch, pitch / 8);
  EXPECT_EQ(v.format, tx::kFormatUnsignedShort4);

  cudaTextureObject_t o = 0;
  cudaResourceDesc bad = r;
  bad.res.pitch2D.pitchInBytes = 10 * 8;  // not a multiple of texturePitchAlignment (32)
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);
  bad.res.pitch2D.pitchInBytes = 64;  // shorter than a row
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);
  bad = r;
  bad.res.pitch2D.height = 7;  // past the allocation
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);
  bad = r;
  bad.res.pitch2D.devPtr = static_cast<char*>(p) + 16;  // not textureAlignment-aligned
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);
  bad = r;
  bad.res.pitch2D.desc = cudaCreateChannelDesc(16, 16, 16, 0, cudaChannelFormatKindUnsigned);
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidChannelDescriptor);

  cudaResourceDesc lin = {};
  lin.resType = cudaResourceTypeLinear;
  lin.res.linear.devPtr = p;
  lin.res.linear.desc = cudaCreateChannelDesc<unsigned int>();
  lin.res.linear.sizeInBytes = pitch * 6;
  cudaTextureDesc element = {};
  const TesseraTextureView& l = Descriptor(Texture(lin, element)).view;
  EXPECT_EQ(l.levels[0].width, pitch * 6 / 4);
  EXPECT_EQ(l.dimensionality, 1u);
  lin.res.linear.sizeInBytes = pitch * 6 + 4;  // past the allocation
  EXPECT_EQ(cudaCreateTextureObject(&o, &lin, &element, nullptr), cudaErrorInvalidValue);
  for (cudaTextureObject_t x : textures_) EXPECT_EQ(cudaDestroyTextureObject(x), cudaSuccess);
  textures_.clear();
  EXPECT_EQ(cudaFree(p), cudaSuccess);
}

TEST_F(CudaTextureTest, MipmappedArraysHoldTheirLevelsInOneAllocation) {
  const cudaChannelFormatDesc f = cudaCreateChannelDesc<float2>();
  cudaMipmappedArray_t m = nullptr;
  ASSERT_EQ(cudaMallocMipmappedArray(&m, &f, {8, 4, 0}, 10), cudaSuccess);  // 4 levels exist
  cudaArray_t levels[4] = {};
  for (unsigned i = 0; i < 4; ++i) {
    ASSERT_EQ(cudaGetMipmappedArrayLevel(&levels[i], m, i), cudaSuccess);
  }
  cudaArray_t past = nullptr;
  EXPECT_EQ(cudaGetMipmappedArrayLevel(&past, m, 4), cudaErrorInvalidValue);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(levels[0]), reinterpret_cast<uintptr_t>(m));
  EXPECT_EQ(reinterpret_cast<uintptr_t>(levels[1]) - reinterpret_cast<uintptr_t>(levels[0]),
            8u * 4 * 8);
  EXPECT_EQ(reinterpret_cast<uintptr_t>(levels[3]) - reinterpret_cast<uintptr_t>(levels[2]),
            2u * 1 * 8);
  cudaExtent e;
  ASSERT_EQ(cudaArrayGetInfo(nullptr, &e, nullptr, levels[2]), cudaSuccess);
  EXPECT_EQ(e.width, 2u);
  EXPECT_EQ(e.height, 1u);
  EXPECT_EQ(cudaFreeArray(levels[1]), cudaErrorInvalidValue);  // a level is not the application's

  cudaResourceDesc r = {};
  r.resType = cudaResourceTypeMipmappedArray;
  r.res.mipmap.mipmap = m;
  cudaTextureDesc t = {};
  t.filterMode = cudaFilterModeLinear;
  t.mipmapFilterMode = cudaFilterModeLinear;
  t.maxMipmapLevelClamp = 3;
  t.mipmapLevelBias = 0.5f;
  t.normalizedCoords = 1;
  const TesseraTextureView& v = Descriptor(Texture(r, t)).view;
  EXPECT_EQ(v.level_count, 4u);
  EXPECT_EQ(v.mip_filter, tx::kFilterLinear);
  EXPECT_EQ(v.mip_level_bias, 0.5f);
  EXPECT_EQ(v.mip_level_clamp[1], 3.f);
  EXPECT_EQ(v.levels[3].data, static_cast<const void*>(levels[3]));
  EXPECT_EQ(v.levels[3].width, 1u);
  EXPECT_EQ(v.levels[3].height, 1u);
  for (cudaTextureObject_t x : textures_) EXPECT_EQ(cudaDestroyTextureObject(x), cudaSuccess);
  textures_.clear();
  EXPECT_EQ(cudaFreeMipmappedArray(m), cudaSuccess);
  EXPECT_EQ(cudaFreeMipmappedArray(m), cudaErrorInvalidValue);
}

TEST_F(CudaTextureTest, TextureObjectsRefuseWhatCudaRefuses) {
  cudaArray_t bytes = Array(cudaCreateChannelDesc<uchar4>(), {4, 4, 0});
  cudaArray_t ints = Array(cudaCreateChannelDesc<int>(), {4, 4, 0});
  cudaArray_t cube = Array(cudaCreateChannelDesc<float>(), {4, 4, 6}, cudaArrayCubemap);
  const cudaResourceDesc r = ArrayResource(bytes);
  cudaTextureDesc t = {};
  cudaTextureObject_t o = 0;
  EXPECT_EQ(cudaCreateTextureObject(nullptr, &r, &t, nullptr), cudaErrorInvalidValue);
  EXPECT_EQ(cudaCreateTextureObject(&o, nullptr, &t, nullptr), cudaErrorInvalidValue);
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, nullptr, nullptr), cudaErrorInvalidValue);
  const cudaResourceViewDesc view = {};
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, &t, &view), cudaErrorNotSupported);
  EXPECT_EQ(cudaGetLastError(), cudaErrorNotSupported);
  cudaResourceDesc bad = ArrayResource(reinterpret_cast<cudaArray_t>(0x1234));
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);
  bad.resType = static_cast<cudaResourceType>(7);
  EXPECT_EQ(cudaCreateTextureObject(&o, &bad, &t, nullptr), cudaErrorInvalidValue);

  cudaTextureDesc modes = t;
  modes.addressMode[1] = static_cast<cudaTextureAddressMode>(4);
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, &modes, nullptr), cudaErrorInvalidValue);
  modes = t;
  modes.filterMode = static_cast<cudaTextureFilterMode>(2);
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, &modes, nullptr), cudaErrorInvalidValue);
  modes = t;
  modes.filterMode = cudaFilterModeLinear;  // integers read as they are cannot be blended
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, &modes, nullptr), cudaErrorInvalidValue);
  modes.readMode = cudaReadModeNormalizedFloat;  // as floats they can
  EXPECT_NE(Texture(r, modes), 0u);
  const cudaResourceDesc ri = ArrayResource(ints);
  EXPECT_EQ(cudaCreateTextureObject(&o, &ri, &modes, nullptr), cudaErrorInvalidValue);  // 32 bit
  modes = t;
  modes.addressMode[0] = cudaAddressModeBorder;
  modes.borderColor[3] = 1.f;  // the sampler's border is 0
  EXPECT_EQ(cudaCreateTextureObject(&o, &r, &modes, nullptr), cudaErrorNotSupported);
  modes.addressMode[0] = cudaAddressModeClamp;
  EXPECT_NE(Texture(r, modes), 0u);  // a colour no address mode uses
  const cudaResourceDesc rc = ArrayResource(cube);
  modes = t;
  modes.filterMode = cudaFilterModeLinear;
  modes.seamlessCubemap = 1;
  EXPECT_EQ(cudaCreateTextureObject(&o, &rc, &modes, nullptr), cudaErrorNotSupported);
  EXPECT_EQ(o, 0u);
}

TEST_F(CudaTextureTest, TexturesKeepTheirArraysMemoryAndAreDestroyedOnce) {
  cudaArray_t a = nullptr;
  const cudaChannelFormatDesc f = cudaCreateChannelDesc<float>();
  ASSERT_EQ(cudaMallocArray(&a, &f, 64, 64), cudaSuccess);
  cudaTextureDesc t = {};
  cudaTextureObject_t o = 0;
  const cudaResourceDesc r = ArrayResource(a);
  ASSERT_EQ(cudaCreateTextureObject(&o, &r, &t, nullptr), cudaSuccess);
  EXPECT_EQ(cudaFree(reinterpret_cast<void*>(o)), cudaErrorInvalidDevicePointer);
  ASSERT_EQ(cudaFreeArray(a), cudaSuccess);
  // The handle is gone, the memory stays while the texture object reads it.
  EXPECT_EQ(cudaArrayGetInfo(nullptr, nullptr, nullptr, a), cudaErrorInvalidValue);
  cudaTextureObject_t again = 0;
  EXPECT_EQ(cudaCreateTextureObject(&again, &r, &t, nullptr), cudaErrorInvalidValue);
  EXPECT_TRUE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), 64 * 64 * 4));
  EXPECT_EQ(cudaDestroyTextureObject(o), cudaSuccess);
  EXPECT_FALSE(Memory().IsAllocated(reinterpret_cast<uintptr_t>(a), 1));
  EXPECT_EQ(cudaDestroyTextureObject(o), cudaErrorInvalidValue);
  EXPECT_EQ(cudaDestroyTextureObject(0), cudaErrorInvalidValue);
  EXPECT_EQ(cudaGetLastError(), cudaErrorInvalidValue);
}

}  // namespace
}  // namespace tessera::optix7
