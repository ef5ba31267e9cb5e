// optix7_sample_check NAME IMAGE: what each OptiX 7 sample's image must show (run_on_devices.cmake
// runs it on the in-process image once every device set gave the same bits). Exit 1 naming each
// check that failed.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

int g_failures = 0;

std::ostream& operator<<(std::ostream& o, const std::array<int, 3>& p) {
  return o << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
}

// A failed check: said with its line, and counted.
struct Failure {
  explicit Failure(int line) : line_(line) {}
  ~Failure() {
    std::fprintf(stderr, "check at line %d failed: %s\n", line_, text_.str().c_str());
    ++g_failures;
  }
  template <typename T>
  Failure& operator<<(const T& v) {
    text_ << v;
    return *this;
  }

 private:
  int line_;
  std::ostringstream text_;
};
#define CHECK_THAT(cond) \
  if (cond) {            \
  } else                 \
    Failure(__LINE__) << #cond << " "
#define EXPECT_TRUE(c) CHECK_THAT(c)
#define EXPECT_EQ(a, b) CHECK_THAT((a) == (b)) << (a) << " vs " << (b)
#define EXPECT_NE(a, b) CHECK_THAT((a) != (b))
#define EXPECT_GT(a, b) CHECK_THAT((a) > (b)) << (a) << " vs " << (b)
#define EXPECT_LT(a, b) CHECK_THAT((a) < (b)) << (a) << " vs " << (b)
#define EXPECT_NEAR(a, b, d) CHECK_THAT(std::abs((a) - (b)) <= (d)) << (a) << " vs " << (b)
#define ASSERT_EQ(a, b)                                            \
  if ((a) != (b)) {                                                \
    Failure(__LINE__) << #a " == " #b " " << (a) << " vs " << (b); \
    return;                                                        \
  }

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;  // top row first, as the file holds it
  std::array<int, 3> At(int x, int y_from_bottom) const {
    const size_t i = (size_t(height - 1 - y_from_bottom) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2]};
  }
};

std::string g_path;

Image Load(const std::string&) {
  Image image;
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(g_path);
  if (!in) {
    Failure(__LINE__) << "cannot read " << g_path << ": " << OIIO::geterror();
    return image;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width;
  image.height = spec.height;
  image.rgba.resize(size_t(spec.width) * spec.height * 4);
  EXPECT_EQ(spec.nchannels, 4);
  EXPECT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, image.rgba.data()));
  return image;
}

// The colour make_color gives linear `c` (sqrt, then 255.99 scaled).
int Channel(float c) { return static_cast<int>(std::sqrt(c) * 255.99f); }

void TriangleShowsBarycentricsOverTheBackground() {
  const Image image = Load("triangle");
  ASSERT_EQ(image.width, 320);
  const std::array<int, 3> background = {Channel(0.3f), Channel(0.1f), Channel(0.2f)};
  EXPECT_EQ(image.At(0, 0), background);
  EXPECT_EQ(image.At(319, 239), background);
  // The centre lies inside the triangle: all three barycentrics contribute.
  const std::array<int, 3> centre = image.At(160, 120);
  EXPECT_NE(centre, background);
  for (int c : centre) EXPECT_GT(c, 60);
}

void SpheresAreShadedAndCastShadows() {
  const Image image = Load("spheres");
  ASSERT_EQ(image.width, 320);
  std::set<std::array<int, 3>> colours;
  for (int y = 0; y < image.height; y += 4) {
    for (int x = 0; x < image.width; x += 4) colours.insert(image.At(x, y));
  }
  EXPECT_GT(colours.size(), 100u);  // lit and shadowed spheres, ground, sky
  // The top row is sky (blue over red), the bottom row ground (grey).
  const std::array<int, 3> sky = image.At(160, 199), ground = image.At(160, 0);
  EXPECT_GT(sky[2], sky[0]);
  EXPECT_NEAR(ground[0], ground[1], 20);
}

void InstancesShowThreeMaterialsAndTheMaskedOneIsHidden() {
  const Image image = Load("instancing");
  ASSERT_EQ(image.width, 320);
  int red = 0, green = 0, blue = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const auto p = image.At(x, y);
      red += p[0] > p[1] + 40 && p[0] > p[2] + 40;
      green += p[1] > p[0] + 40 && p[1] > p[2] + 20;
      blue += p[2] > 185;  // brighter than any background blue (at most 180)
    }
  }
  EXPECT_GT(red, 500);
  EXPECT_GT(green, 500);
  EXPECT_GT(blue, 200);
  // Between the grid's cubes near the middle lies background (grey-blue), where the red
  // instance that only visibility mask 2 sees would be in front of everything.
  const auto gap = image.At(185, 101);
  EXPECT_LT(gap[0], gap[2]) << gap;
  EXPECT_NEAR(gap[0], gap[1], 30) << gap;
}

// The motion blur sample's image: an orthographic view of x in [-1.6, 1.6], y in [-1.2, 1.2].
void MovingThingsBlurAndTheStillOneStaysSharp() {
  const Image image = Load("motion_blur");
  ASSERT_EQ(image.width, 320);
  auto at = [&](float x, float y) {
    return image.At(static_cast<int>((x / 1.6f + 1.f) * 160.f),
                    static_cast<int>((y / 1.2f + 1.f) * 120.f));
  };
  const std::array<int, 3> background = {Channel(0.1f), Channel(0.1f), Channel(0.15f)};
  EXPECT_EQ(image.At(0, 0), background);
  // The still square is sharp: its full colour inside, background just past its edge.
  const std::array<int, 3> blue = {Channel(0.15f), Channel(0.3f), Channel(0.95f)};
  EXPECT_EQ(at(0.8f, 0.55f), blue);
  EXPECT_EQ(at(0.95f, 0.55f), blue);
  EXPECT_EQ(at(1.1f, 0.55f), background);
  // The moving mesh covers its first place about a third of the shutter time: red, but between
  // the background and its full colour; past its path there is background.
  const std::array<int, 3> start = at(-1.15f, 0.55f);
  EXPECT_GT(start[0], background[0] + 30) << start;
  EXPECT_LT(start[0], Channel(0.9f) - 30) << start;
  EXPECT_GT(start[0], start[1] + 40) << start;
  EXPECT_EQ(at(-1.5f, 0.55f), background);
  EXPECT_EQ(at(-0.75f, 0.15f), background);  // below the arc of its path
  // The spinning square's centre is always covered; a point near its corner only while the
  // corner passes.
  EXPECT_EQ(at(0.8f, -0.5f), (std::array<int, 3>{Channel(0.1f), Channel(0.85f), Channel(0.2f)}));
  const std::array<int, 3> corner = at(1.012f, -0.288f);
  EXPECT_GT(corner[1], background[1] + 30) << corner;
  EXPECT_LT(corner[1], Channel(0.85f) - 30) << corner;
  // Blur leaves many colours between the background and the full ones.
  std::set<std::array<int, 3>> colours;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) colours.insert(image.At(x, y));
  }
  EXPECT_GT(colours.size(), 20u);  // 16 samples a pixel: up to 17 levels per moving object
}

void CutoutsLetTheBackgroundThroughTheHoles() {
  const Image image = Load("cutouts");
  ASSERT_EQ(image.width, 320);
  // Along the middle row the leaves alternate with what lies behind their holes.
  int leaf = 0, other = 0;
  for (int x = 0; x < image.width; ++x) {
    const auto p = image.At(x, image.height / 2);
    if (p[1] > p[0] + 40 && p[1] > p[2] + 40) {
      ++leaf;
    } else {
      ++other;
    }
  }
  EXPECT_GT(leaf, 30);
  EXPECT_GT(other, 30);
}

void DynamicFramesDifferAndTheLastRebuildMatchesItsSurface() {
  const Image image = Load("dynamic");
  ASSERT_EQ(image.width, 128 * 5);
  std::vector<std::vector<unsigned char>> frames(5);
  for (int f = 0; f < 5; ++f) {
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < 128; ++x) {
        const auto p = image.At(f * 128 + x, y);
        frames[f].insert(frames[f].end(), p.begin(), p.end());
      }
    }
  }
  for (int f = 1; f < 5; ++f) EXPECT_NE(frames[f], frames[f - 1]) << "frame " << f;
}

void CornellBoxHasRedAndGreenWallsAndALight() {
  const Image image = Load("path_tracer");
  ASSERT_EQ(image.width, 256);
  // The red wall on the left, the green one on the right, at mid height.
  long left[3] = {}, right[3] = {};
  for (int y = 100; y < 156; ++y) {
    for (int x = 4; x < 20; ++x) {
      const auto l = image.At(x, y), r = image.At(255 - x, y);
      for (int c = 0; c < 3; ++c) {
        left[c] += l[c];
        right[c] += r[c];
      }
    }
  }
  EXPECT_GT(left[0], 2 * left[1]);
  EXPECT_GT(right[1], 2 * right[0]);
  // The light on the ceiling is the brightest thing in the image.
  int brightest = 0;
  for (int y = 180; y < 256; ++y) {
    for (int x = 100; x < 156; ++x) {
      const auto p = image.At(x, y);
      brightest = std::max(brightest, p[0] + p[1] + p[2]);
    }
  }
  EXPECT_GT(brightest, 600);
}

// The multi-GPU sample assembles bands that 1-3 devices rendered (the sample itself requires them
// to equal one device's render): here, that the picture is the scene, with triangles across the
// band boundaries of two and three devices.
void MultiGpuShowsThreeTrianglesOnTheGroundUnderTheSky() {
  const Image image = Load("multi_gpu");
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  const std::array<int, 3> sky = image.At(160, 239), ground = image.At(160, 0);
  EXPECT_GT(sky[2], sky[0] + 40);
  EXPECT_NEAR(ground[0], ground[1], 20);
  EXPECT_GT(ground[0], 150);
  // Pixels of each triangle's colour, and those rows of each band boundary crosses.
  std::array<int, 3> count = {0, 0, 0};
  std::array<std::set<int>, 3> rows;
  int shadowed = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const auto p = image.At(x, y);
      for (int c = 0; c < 3; ++c) {
        if (p[c] > p[(c + 1) % 3] + 50 && p[c] > p[(c + 2) % 3] + 50) {
          ++count[c];
          rows[c].insert(y);
        }
      }
      // Ground grey in the shadow of a triangle: darker than the lit ground, still grey.
      shadowed += std::abs(p[0] - p[1]) < 15 && p[0] < ground[0] - 60 && p[0] > 30;
    }
  }
  for (int c = 0; c < 3; ++c) EXPECT_GT(count[c], 1500) << "colour channel " << c;
  // Band boundaries: rows 120 (two devices) and 160 (three, counted from the bottom).
  for (int c = 0; c < 3; ++c) {
    EXPECT_TRUE(rows[c].count(119) == 1 && rows[c].count(120) == 1) << "channel " << c;
  }
  EXPECT_TRUE(rows[0].count(159) == 1 && rows[0].count(160) == 1) << "red across row 160";
  EXPECT_TRUE(rows[1].count(159) == 1 && rows[1].count(160) == 1) << "green across row 160";
  EXPECT_GT(shadowed, 20);
}

}  // namespace

int main(int argc, char** argv) {
  const std::map<std::string, std::function<void()>> checks = {
      {"triangle", TriangleShowsBarycentricsOverTheBackground},
      {"spheres", SpheresAreShadedAndCastShadows},
      {"instancing", InstancesShowThreeMaterialsAndTheMaskedOneIsHidden},
      {"cutouts", CutoutsLetTheBackgroundThroughTheHoles},
      {"dynamic", DynamicFramesDifferAndTheLastRebuildMatchesItsSurface},
      {"path_tracer", CornellBoxHasRedAndGreenWallsAndALight},
      {"motion_blur", MovingThingsBlurAndTheStillOneStaysSharp},
      {"multi_gpu", MultiGpuShowsThreeTrianglesOnTheGroundUnderTheSky},
      {"exceptions", [] {}},  // the sample checks its exception records itself (exit status)
  };
  if (argc != 3 || checks.count(argv[1]) == 0) {
    std::fprintf(stderr,
                 "usage: optix7_sample_check SAMPLE IMAGE (SAMPLE: a samples/optix7 name)\n");
    return 2;
  }
  g_path = argv[2];
  checks.at(argv[1])();
  if (g_failures == 0) std::printf("%s: image checks passed\n", argv[1]);
  return g_failures == 0 ? 0 : 1;
}
