// tesseraBufferCreateFromImage: files OpenImageIO writes here (PNG, JPEG, EXR, HDR) come back as
// buffers of the documented format, size, channel expansion and row order; bad input fails with
// a code and a message naming the file.
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "tessera/image.h"
#include "tessera/rt.h"

namespace {

class ImageLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(rtContextCreate(&context_), RT_SUCCESS); }
  void TearDown() override { rtContextDestroy(context_); }

  std::string Path(const std::string& name) const {
    return ::testing::TempDir() + "tessera_image_" + name;
  }

  // Writes a width x height image of `channels` channels of type T, top row first.
  template <typename T>
  void Write(const std::string& path, int width, int height, int channels,
             const std::vector<T>& pixels, OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << OIIO::geterror();
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(width, height, channels, type))) << out->geterror();
    ASSERT_TRUE(out->write_image(type, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
  }

  template <typename T>
  std::vector<T> Read(RTbuffer buffer, RTformat expected_format, RTsize w, RTsize h) {
    RTformat format;
    EXPECT_EQ(rtBufferGetFormat(buffer, &format), RT_SUCCESS);
    EXPECT_EQ(format, expected_format);
    RTsize width = 0, height = 0;
    EXPECT_EQ(rtBufferGetSize2D(buffer, &width, &height), RT_SUCCESS);
    EXPECT_EQ(width, w);
    EXPECT_EQ(height, h);
    void* data = nullptr;
    EXPECT_EQ(rtBufferMap(buffer, &data), RT_SUCCESS);
    std::vector<T> texels(static_cast<const T*>(data), static_cast<const T*>(data) + w * h * 4);
    EXPECT_EQ(rtBufferUnmap(buffer), RT_SUCCESS);
    return texels;
  }

  RTcontext context_ = nullptr;
};

TEST_F(ImageLoaderTest, AnRgbPngBecomesOpaqueBytesBottomRowFirst) {
  // 2x2: top row red, green; bottom row blue, white.
  const std::vector<uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  Write(Path("rgb.png"), 2, 2, 3, rgb, OIIO::TypeDesc::UINT8);
  RTbuffer buffer = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("rgb.png").c_str(), 0, &buffer), RT_SUCCESS)
      << tesseraImageGetErrorString();
  const std::vector<uint8_t> texels = Read<uint8_t>(buffer, RT_FORMAT_UNSIGNED_BYTE4, 2, 2);
  const std::vector<uint8_t> expected = {0,   0, 255, 255, 255, 255, 255, 255,   // bottom row
                                         255, 0, 0,   255, 0,   255, 0,   255};  // top row
  EXPECT_EQ(texels, expected);
  EXPECT_STREQ(tesseraImageGetErrorString(), "");

  RTbuffer top_first = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("rgb.png").c_str(),
                                         TESSERA_IMAGE_TOP_ROW_FIRST, &top_first),
            RT_SUCCESS);
  const std::vector<uint8_t> rows = Read<uint8_t>(top_first, RT_FORMAT_UNSIGNED_BYTE4, 2, 2);
  EXPECT_EQ(std::vector<uint8_t>(rows.begin(), rows.begin() + 4),
            (std::vector<uint8_t>{255, 0, 0, 255}));
}

TEST_F(ImageLoaderTest, GreyAndGreyAlphaExpandToRgba) {
  Write(Path("grey.png"), 1, 1, 1, std::vector<uint8_t>{77}, OIIO::TypeDesc::UINT8);
  // Grey and alpha in an EXR, where no writer converts between straight and premultiplied alpha.
  Write(Path("grey_alpha.exr"), 1, 1, 2, std::vector<float>{0.25f, 0.5f}, OIIO::TypeDesc::FLOAT);
  RTbuffer grey = nullptr, grey_alpha = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("grey.png").c_str(), 0, &grey), RT_SUCCESS);
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("grey_alpha.exr").c_str(), 0, &grey_alpha),
            RT_SUCCESS);
  EXPECT_EQ(Read<uint8_t>(grey, RT_FORMAT_UNSIGNED_BYTE4, 1, 1),
            (std::vector<uint8_t>{77, 77, 77, 255}));
  EXPECT_EQ(Read<float>(grey_alpha, RT_FORMAT_FLOAT4, 1, 1),
            (std::vector<float>{0.25f, 0.25f, 0.25f, 0.5f}));
}

TEST_F(ImageLoaderTest, ExrAndHdrBecomeLinearFloats) {
  const std::vector<float> rgba = {0.25f, 2.0f, 100.0f, 0.5f, 1.0f, 0.0f, 3.5f, 1.0f};
  Write(Path("two.exr"), 2, 1, 4, rgba, OIIO::TypeDesc::FLOAT);
  RTbuffer exr = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("two.exr").c_str(), 0, &exr), RT_SUCCESS)
      << tesseraImageGetErrorString();
  EXPECT_EQ(Read<float>(exr, RT_FORMAT_FLOAT4, 2, 1), rgba);

  // Radiance HDR stores RGBE: values a power of two apart from the shared exponent survive.
  const std::vector<float> rgb = {0.5f, 4.0f, 1.0f};
  Write(Path("one.hdr"), 1, 1, 3, rgb, OIIO::TypeDesc::FLOAT);
  RTbuffer hdr = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("one.hdr").c_str(), 0, &hdr), RT_SUCCESS)
      << tesseraImageGetErrorString();
  EXPECT_EQ(Read<float>(hdr, RT_FORMAT_FLOAT4, 1, 1), (std::vector<float>{0.5f, 4.0f, 1.0f, 1.0f}));
}

TEST_F(ImageLoaderTest, AJpegLoadsAsBytesAndTheFloatFlagGivesFloats) {
  std::vector<uint8_t> grey(8 * 8 * 3, 128);
  Write(Path("grey.jpg"), 8, 8, 3, grey, OIIO::TypeDesc::UINT8);
  RTbuffer bytes = nullptr, floats = nullptr;
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("grey.jpg").c_str(), 0, &bytes),
            RT_SUCCESS);
  const std::vector<uint8_t> texels = Read<uint8_t>(bytes, RT_FORMAT_UNSIGNED_BYTE4, 8, 8);
  for (size_t i = 0; i < texels.size(); i += 4) {
    EXPECT_NEAR(texels[i], 128, 2);  // JPEG is lossy, but a flat image stays nearly flat
    EXPECT_EQ(texels[i + 3], 255);
  }
  ASSERT_EQ(tesseraBufferCreateFromImage(context_, Path("grey.jpg").c_str(), TESSERA_IMAGE_FLOAT,
                                         &floats),
            RT_SUCCESS);
  const std::vector<float> values = Read<float>(floats, RT_FORMAT_FLOAT4, 8, 8);
  EXPECT_NEAR(values[0], 128.0f / 255.0f, 2.0f / 255.0f);
  EXPECT_EQ(values[3], 1.0f);
}

TEST_F(ImageLoaderTest, BadInputFailsWithACodeAndAMessageNamingTheFile) {
  RTbuffer buffer = nullptr;
  const std::string missing = Path("does_not_exist.png");
  EXPECT_EQ(tesseraBufferCreateFromImage(context_, missing.c_str(), 0, &buffer),
            RT_ERROR_FILE_NOT_FOUND);
  EXPECT_NE(std::string(tesseraImageGetErrorString()).find(missing), std::string::npos)
      << tesseraImageGetErrorString();
  EXPECT_EQ(buffer, nullptr);

  const std::string not_an_image = Path("not_an_image.png");
  std::FILE* f = std::fopen(not_an_image.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("this is text", f);
  std::fclose(f);
  EXPECT_EQ(tesseraBufferCreateFromImage(context_, not_an_image.c_str(), 0, &buffer),
            RT_ERROR_FILE_NOT_FOUND);
  EXPECT_NE(std::string(tesseraImageGetErrorString()).find(not_an_image), std::string::npos);
  EXPECT_EQ(buffer, nullptr);

  EXPECT_EQ(tesseraBufferCreateFromImage(nullptr, missing.c_str(), 0, &buffer),
            RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraBufferCreateFromImage(context_, nullptr, 0, &buffer), RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraBufferCreateFromImage(context_, missing.c_str(), 0, nullptr),
            RT_ERROR_INVALID_VALUE);
  EXPECT_EQ(tesseraBufferCreateFromImage(context_, missing.c_str(), 64, &buffer),
            RT_ERROR_INVALID_VALUE);
  EXPECT_NE(std::string(tesseraImageGetErrorString()).find("unknown flags"), std::string::npos);
}

}  // namespace
