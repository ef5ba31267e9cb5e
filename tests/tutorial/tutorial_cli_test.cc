// tessera-tutorial's command line, run in-process through RunTutorialMain.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "tutorial/cli.h"
#include "tutorial/render.h"
#include "tutorial_test_util.h"

namespace tessera::tutorial::testing {
namespace {

struct Result {
  int status;
  std::string out;
  std::string err;
};

Result RunCli(std::vector<std::string> args) {
  args.insert(args.begin(), "tessera-tutorial");
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  std::ostringstream out;
  std::ostringstream err;
  const int status = RunTutorialMain(static_cast<int>(argv.size()), argv.data(), out, err);
  return {status, out.str(), err.str()};
}

// A path in the test temp directory, unique per process (other builds may run this test at the
// same time), removed at the end of the test.
struct TempFile {
  explicit TempFile(const std::string& name)
      : path((std::filesystem::path(::testing::TempDir()) /
              ("tessera_tutorial_" + std::to_string(getpid()) + "_" + name))
                 .string()) {}
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
  const std::string path;
};

TEST(TutorialCli, Step11RendersTheEnvironmentCamera) {
  const TempFile file("step11.png");
  const Result r = RunCli({"--step", "11", "--width", "32", "--height", "16", "--out", file.path});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(file.path));
}

TEST(TutorialCli, UnknownStepFails) {
  const TempFile file("step12.png");
  const Result r = RunCli({"--step", "12", "--out", file.path});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("unknown step 12"), std::string::npos) << r.err;
}

TEST(TutorialCli, UnknownExtensionFails) {
  const TempFile file("image.bmp");
  const std::string& path = file.path;
  const Result r = RunCli({"--step", "0", "--out", path});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("unsupported extension '.bmp'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(TutorialCli, MissingOutFails) {
  const Result r = RunCli({"--step", "0"});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

// An output that cannot be written fails before rendering, with the reason.
TEST(TutorialCli, UnwritableOutFailsBeforeRendering) {
  const Result r = RunCli({"--step", "10", "--width", "16", "--height", "12", "--out",
                           "/nonexistent/no-such-dir/a.png"});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("directory '/nonexistent/no-such-dir': No such file or directory"),
            std::string::npos)
      << r.err;
}

// Outputs that can never be written fail before rendering: no name before the extension, a
// symlink into a missing directory, a PNG wider than libpng allows.
TEST(TutorialCli, HopelessOutputsFailBeforeRendering) {
  const TempFile dangling("dangling.png");
  std::filesystem::create_symlink("/nonexistent/x.png", dangling.path);
  const TempFile big("big.png");
  const struct {
    std::vector<std::string> args;
    std::string said;
  } cases[] = {
      {{"--out", ::testing::TempDir() + "/.png"}, "needs a name before '.png'"},
      {{"--out", dangling.path}, "directory '/nonexistent': No such file or directory"},
      {{"--out", big.path, "--width", "1000001", "--height", "1"},
       "at most 1000000 pixels wide and high"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = {"--step", "10", "--modules", "/nonexistent/no-such-dir"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const Result r = RunCli(args);  // a render would fail on the modules: it is never reached
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(c.said), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(big.path));
  }
}

// A write the disk refuses (a device that is always full) fails with the reason instead of
// printing the path; OpenImageIO's PNG writer alone reported success and left a truncated file.
TEST(TutorialCli, AFullDiskFailsTheRun) {
  const TempFile full("full.png");
  std::filesystem::create_symlink("/dev/full", full.path);
  const Result r = RunCli({"--step", "0", "--width", "16", "--height", "12", "--out", full.path});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full")) << "the device was replaced";
}

// A new image replaces the previous one whole, through a symlink the link stays, and no
// temporary file is left beside it.
TEST(TutorialCli, ReplacesAnImageWholeAndKeepsSymlinks) {
  const TempFile image("replaced.png");
  const TempFile link("replaced_link.png");
  std::filesystem::create_symlink(image.path, link.path);
  ASSERT_EQ(RunCli({"--step", "0", "--width", "16", "--height", "12", "--out", link.path}).status,
            0);
  const uintmax_t first = std::filesystem::file_size(image.path);
  ASSERT_EQ(RunCli({"--step", "0", "--width", "64", "--height", "48", "--out", link.path}).status,
            0);
  EXPECT_TRUE(std::filesystem::is_symlink(link.path));
  EXPECT_GT(std::filesystem::file_size(image.path), first);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(image.path);
  ASSERT_NE(in, nullptr) << OIIO::geterror();
  EXPECT_EQ(in->spec().width, 64);
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(image.path).parent_path())) {
    EXPECT_EQ(entry.path().filename().string().rfind(".tessera-tutorial-", 0), std::string::npos)
        << entry.path();
  }
}

TEST(TutorialCli, MissingModulesNamed) {
  const TempFile file("nomodules.png");
  const Result r = RunCli({"--step", "0", "--width", "16", "--height", "12", "--out", file.path,
                           "--modules", "/nonexistent/no-such-dir"});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("no-such-dir"), std::string::npos) << r.err;
}

// Reads an image back as float RGBA.
std::vector<float> ReadBack(const std::string& path, OIIO::ImageSpec* spec) {
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in != nullptr) << OIIO::geterror();
  if (!in) return {};
  *spec = in->spec();
  std::vector<float> pixels(static_cast<size_t>(spec->width) * spec->height * spec->nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec->nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
  return pixels;
}

TEST(TutorialCli, WritesExrWithTheRenderedFloats) {
  const TempFile file("step1.exr");
  const std::string& path = file.path;
  const Result r = RunCli({"--step", "1", "--width", std::to_string(kWidth), "--height",
                           std::to_string(kHeight), "--out", path});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find(path), std::string::npos) << "prints the output path: " << r.out;
  OIIO::ImageSpec spec;
  const std::vector<float> pixels = ReadBack(path, &spec);
  ASSERT_EQ(spec.width, kWidth);
  ASSERT_EQ(spec.height, kHeight);
  ASSERT_EQ(spec.nchannels, 4);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(pixels, Rendered(1).rgba) << "the EXR holds exactly what was rendered";
}

TEST(TutorialCli, WritesEightBitPng) {
  const TempFile file("step0.png");
  const std::string& path = file.path;
  const Result r = RunCli({"--step", "0", "--width", std::to_string(kWidth), "--height",
                           std::to_string(kHeight), "--out", path});
  ASSERT_EQ(r.status, 0) << r.err;
  OIIO::ImageSpec spec;
  const std::vector<float> pixels = ReadBack(path, &spec);
  ASSERT_EQ(spec.width, kWidth);
  ASSERT_EQ(spec.height, kHeight);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  // The same image within 8-bit quantization.
  const Image& rendered = Rendered(0);
  ASSERT_EQ(pixels.size(), rendered.rgba.size());
  for (size_t i = 0; i < pixels.size(); ++i) {
    const float expected = std::fmin(1.0f, std::fmax(0.0f, rendered.rgba[i]));
    ASSERT_NEAR(pixels[i], expected, 0.5f / 255.0f + 1e-6f) << "component " << i;
  }
}

TEST(TutorialCli, AnEnvironmentMapThatCannotBeReadFailsNamingIt) {
  const TempFile file("step5.png");
  const std::string missing = "/nonexistent/sky.hdr";
  const Result r = RunCli(
      {"--step", "5", "--width", "16", "--height", "12", "--envmap", missing, "--out", file.path});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("environment map"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(file.path));
}

}  // namespace
}  // namespace tessera::tutorial::testing
