// A rendered image as the tutorial hands it around: float RGBA, top row first.
#ifndef TESSERA_SAMPLES_TUTORIAL_IMAGE_H_
#define TESSERA_SAMPLES_TUTORIAL_IMAGE_H_

#include <cstddef>
#include <vector>

namespace tessera::tutorial {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // 4 floats per pixel, row-major, row 0 at the top

  const float* Pixel(int x, int y) const {
    return &rgba[4 *
                 (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x))];
  }
};

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_IMAGE_H_
