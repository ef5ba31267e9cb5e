// The build's sky as a buffer, computed in memory (tutorial/envmap.h). The HDR file the build
// writes holds the same sky rounded to its 8-bit mantissas, so images rendered with one differ a
// little from images rendered with the other.
#include <cstring>
#include <vector>

#include "tutorial/envmap.h"
#include "tutorial/rt_check.h"
#include "tutorial/sky.h"

namespace tessera::tutorial {

RTbuffer ComputedSky(RTcontext context, const std::string& path) {
  if (!path.empty()) {
    throw TutorialError("environment map: the computed sky reads no image file ('" + path +
                        "'): load it with LoadEnvmapFile");
  }
  const std::vector<float> rgb = SkyPixels();
  RTbuffer buffer = nullptr;
  RT_CHECK(context, rtBufferCreate(context, RT_BUFFER_INPUT, &buffer));
  RT_CHECK(context, rtBufferSetFormat(buffer, RT_FORMAT_FLOAT4));
  RT_CHECK(context, rtBufferSetSize2D(buffer, kSkyWidth, kSkyHeight));
  void* data = nullptr;
  RT_CHECK(context, rtBufferMap(buffer, &data));
  auto* texels = static_cast<float*>(data);
  for (int row = 0; row < kSkyHeight; ++row) {
    const float* from = &rgb[static_cast<size_t>(kSkyHeight - 1 - row) * kSkyWidth * 3];  // flip
    for (int col = 0; col < kSkyWidth; ++col) {
      float* t = &texels[(static_cast<size_t>(row) * kSkyWidth + col) * 4];
      std::memcpy(t, from + static_cast<size_t>(col) * 3, 3 * sizeof(float));
      t[3] = 1.0f;
    }
  }
  RT_CHECK(context, rtBufferUnmap(buffer));
  return buffer;
}

}  // namespace tessera::tutorial
