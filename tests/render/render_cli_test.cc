// End-to-end tests of `tessera render`: the executable run on builtin:cornell, small (64x48, a few
// samples), its images read back with OpenImageIO.
#include <OpenImageIO/imageio.h>
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#ifndef TESSERA_CLI
#error "TESSERA_CLI must name the tessera executable"
#endif

extern char** environ;

namespace {

constexpr char kWidth[] = "--width=64";
constexpr char kHeight[] = "--height=48";

struct Result {
  int status = -1;  // exit status, or 128 + signal
  std::string out, err;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool Exists(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0;
}

// A directory of its own per test, removed afterwards.
class RenderCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/tessera-render-test-XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  // Spawns `tessera ARGS...`; stdout and stderr go to files, or stderr to `err_pipe` if given.
  pid_t Spawn(const std::vector<std::string>& args, int err_pipe = -1) {
    std::vector<std::string> all = {TESSERA_CLI};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, Path("stdout").c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (err_pipe >= 0) {
      posix_spawn_file_actions_adddup2(&actions, err_pipe, STDERR_FILENO);
    } else {
      posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, Path("stderr").c_str(),
                                       O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    pid_t pid = -1;
    const int error = posix_spawn(&pid, TESSERA_CLI, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    EXPECT_EQ(error, 0) << std::strerror(error);
    return pid;
  }

  Result Wait(pid_t pid) {
    int wstatus = 0;
    Result r;
    if (waitpid(pid, &wstatus, 0) == pid) {
      r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
    }
    r.out = ReadFile(Path("stdout"));
    r.err = ReadFile(Path("stderr"));
    return r;
  }

  Result Run(const std::vector<std::string>& args) { return Wait(Spawn(args)); }

  // `tessera render builtin:cornell -o OUT` small, with `extra` flags.
  Result Render(const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render", "builtin:cornell", "-o", out, kWidth, kHeight};
    bool level = false;
    for (const std::string& a : extra) level = level || a.rfind("--log-level", 0) == 0;
    if (!level) args.push_back("--log-level=warn");  // no progress lines
    args.insert(args.end(), extra.begin(), extra.end());
    return Run(args);
  }

  std::string dir_;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;
  std::vector<float> pixels;  // all channels, interleaved
  OIIO::ImageSpec spec;
  int Channel(const std::string& name) const {
    for (size_t i = 0; i < channels.size(); ++i) {
      if (channels[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
  float At(int x, int y, int c) const {
    return pixels[(static_cast<size_t>(y) * width + x) * channels.size() + c];
  }
};

Image Read(const std::string& path) {
  Image image;
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
  if (!in) return image;
  image.spec = in->spec();
  image.width = image.spec.width;
  image.height = image.spec.height;
  image.channels = image.spec.channelnames;
  image.pixels.resize(static_cast<size_t>(image.width) * image.height * image.channels.size());
  EXPECT_TRUE(
      in->read_image(0, 0, 0, image.spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()));
  return image;
}

// A number the renderer wrote: an int attribute in OpenEXR, a text chunk in PNG.
int IntAttribute(const Image& image, const char* name) {
  const int value = image.spec.get_int_attribute(name, -1);
  if (value != -1) return value;
  const std::string text = image.spec.get_string_attribute(name, "-1");
  return std::atoi(text.c_str());
}

int Samples(const Image& image) { return IntAttribute(image, "tessera:samples"); }

// Bit-identical radiance (R, G, B) of two float EXRs.
void ExpectSameBits(const std::string& a, const std::string& b) {
  const Image x = Read(a), y = Read(b);
  ASSERT_EQ(x.channels, y.channels);
  ASSERT_EQ(x.pixels.size(), y.pixels.size());
  size_t differ = 0;
  for (size_t i = 0; i < x.pixels.size(); ++i) {
    if (std::memcmp(&x.pixels[i], &y.pixels[i], sizeof(float)) != 0) ++differ;
  }
  EXPECT_EQ(differ, 0u) << a << " and " << b << " differ in " << differ << " values";
}

TEST_F(RenderCliTest, RendersALitCornellBoxWithLayers) {
  const std::string out = Path("cornell.exr");
  const Result r = Render(out, {"--spp=4"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, out + "\n");  // the path on stdout, nothing else
  const Image image = Read(out);
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  for (const char* name : {"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B", "normal.X",
                           "normal.Y", "normal.Z", "depth.Z"}) {
    EXPECT_GE(image.Channel(name), 0) << name;
  }
  EXPECT_EQ(Samples(image), 4);
  EXPECT_EQ(image.spec.get_int_attribute("tessera:seed", -1), 0);
  EXPECT_EQ(image.spec.get_string_attribute("tessera:scene"), "builtin:cornell");
  EXPECT_NE(image.spec.get_string_attribute("Software").find("tessera"), std::string::npos);

  // The light under the ceiling, top middle, is by far the brightest thing; the room is lit.
  const int red = image.Channel("R"), green = image.Channel("G");
  double sum = 0, light = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float v = image.At(x, y, red);
      ASSERT_TRUE(std::isfinite(v)) << x << "," << y;
      sum += v;
      if (y >= 2 && y < 8 && x >= 26 && x < 38) light = std::max<double>(light, v);
    }
  }
  const double mean = sum / (image.width * image.height);
  EXPECT_GT(mean, 0.05);
  EXPECT_GT(light, 4.0);
  EXPECT_GT(light, 10 * mean);
  // Left wall red, right wall green (the image is not mirrored).
  EXPECT_GT(image.At(8, 24, red), image.At(8, 24, green));
  EXPECT_GT(image.At(56, 24, green), image.At(56, 24, red));
  EXPECT_NEAR(image.At(8, 24, image.Channel("albedo.R")), 0.65f, 1e-3f);
  EXPECT_NEAR(image.At(56, 24, image.Channel("albedo.G")), 0.45f, 1e-3f);
  // The back wall, above the boxes: 4.4 units from the camera along its view axis, facing it.
  EXPECT_NEAR(image.At(32, 12, image.Channel("depth.Z")), 4.4f, 1e-3f);
  EXPECT_GT(image.At(32, 12, image.Channel("normal.Z")), 0.99f);
  // Outside the box's open front, at the middle of the image's left edge, nothing is hit.
  EXPECT_TRUE(std::isinf(image.At(0, 24, image.Channel("depth.Z"))));
}

TEST_F(RenderCliTest, SameBitsOnEveryDeviceSetAndTileSize) {
  const std::vector<std::string> common = {"--spp=3", "--exr-float"};
  const std::vector<std::vector<std::string>> runs = {
      {"--devices=inproc"},
      {"--devices=local:1"},
      {"--devices=inproc", "--threads=1"},
      {"--devices=local:2", "--pass-samples=1"},
      {"--devices=local:3", "--tile-size=8x4", "--pass-samples=2"},
  };
  for (size_t i = 0; i < runs.size(); ++i) {
    std::vector<std::string> args = common;
    args.insert(args.end(), runs[i].begin(), runs[i].end());
    const Result r = Render(Path("run" + std::to_string(i) + ".exr"), args);
    ASSERT_EQ(r.status, 0) << runs[i][0] << ": " << r.err;
  }
  for (size_t i = 1; i < runs.size(); ++i) {
    SCOPED_TRACE(runs[i][0]);
    ExpectSameBits(Path("run0.exr"), Path("run" + std::to_string(i) + ".exr"));
  }
  // And the seed matters.
  ASSERT_EQ(Render(Path("seed.exr"), {"--spp=3", "--exr-float", "--seed=7"}).status, 0);
  const Image a = Read(Path("run0.exr")), b = Read(Path("seed.exr"));
  EXPECT_NE(a.pixels, b.pixels);
}

TEST_F(RenderCliTest, ResumeEqualsAnUninterruptedRender) {
  ASSERT_EQ(Render(Path("whole.exr"), {"--spp=5", "--exr-float"}).status, 0);
  const std::string part = Path("part.exr");
  ASSERT_EQ(Render(part, {"--spp=2", "--exr-float", "--keep-accum"}).status, 0);
  ASSERT_TRUE(Exists(part + ".accum"));
  EXPECT_EQ(Samples(Read(part)), 2);
  const Result r =
      Render(part, {"--spp=5", "--exr-float", "--resume", "--devices=local:2", "--pass-samples=2"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Samples(Read(part)), 5);
  ExpectSameBits(Path("whole.exr"), part);
  EXPECT_FALSE(Exists(part + ".accum")) << "a finished image leaves no accumulation behind";
}

// SIGINT after the first pass: the render stops after the pass in flight, writes what it has
// with its sample count, exits 130 and leaves the sums, from which --resume ends exactly where an
// uninterrupted render does.
TEST_F(RenderCliTest, SigintWritesThePartialImageAndResumeFinishesIt) {
  const std::string out = Path("stopped.exr");
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid = Spawn({"render", "builtin:cornell", "-o", out, kWidth, kHeight, "--exr-float",
                           "--spp=100000", "--pass-samples=1", "--log-level=debug"},
                          fds[1]);
  close(fds[1]);
  // Wait for the first "pass done" line on stderr.
  std::string err;
  char buffer[4096];
  bool first_pass = false;
  while (!first_pass) {
    const ssize_t n = read(fds[0], buffer, sizeof(buffer));
    if (n <= 0) break;
    err.append(buffer, static_cast<size_t>(n));
    first_pass = err.find("pass done") != std::string::npos;
  }
  ASSERT_TRUE(first_pass) << err;
  ASSERT_EQ(kill(pid, SIGINT), 0);
  std::thread drain([&] {
    for (ssize_t n; (n = read(fds[0], buffer, sizeof(buffer))) > 0;) err.append(buffer, n);
  });
  const Result r = Wait(pid);
  drain.join();
  close(fds[0]);
  ASSERT_EQ(r.status, 130) << err;
  EXPECT_EQ(r.out, out + "\n");
  const int done = Samples(Read(out));
  ASSERT_GE(done, 1);
  ASSERT_LT(done, 100000);
  ASSERT_TRUE(Exists(out + ".accum"));

  const std::string spp = "--spp=" + std::to_string(done + 2);
  // Sums made with other settings are refused, naming the file, and left alone.
  const Result other = Render(out, {spp, "--exr-float", "--resume", "--seed=3"});
  EXPECT_EQ(other.status, 1);
  EXPECT_NE(other.err.find(out + ".accum"), std::string::npos) << other.err;
  ASSERT_EQ(Render(out, {spp, "--exr-float", "--resume"}).status, 0);
  ASSERT_EQ(Render(Path("straight.exr"), {spp, "--exr-float"}).status, 0);
  EXPECT_EQ(Samples(Read(out)), done + 2);
  ExpectSameBits(Path("straight.exr"), out);
}

TEST_F(RenderCliTest, SigtermExits143WithTheImageSoFar) {
  const std::string out = Path("term.png");
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid = Spawn({"render", "builtin:cornell", "-o", out, kWidth, kHeight, "--spp=100000",
                           "--pass-samples=1", "--log-level=debug"},
                          fds[1]);
  close(fds[1]);
  std::string err;
  char buffer[4096];
  while (err.find("pass done") == std::string::npos) {
    const ssize_t n = read(fds[0], buffer, sizeof(buffer));
    if (n <= 0) break;
    err.append(buffer, static_cast<size_t>(n));
  }
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  std::thread drain([&] {
    for (ssize_t n; (n = read(fds[0], buffer, sizeof(buffer))) > 0;) err.append(buffer, n);
  });
  const Result r = Wait(pid);
  drain.join();
  close(fds[0]);
  EXPECT_EQ(r.status, 143) << err;
  EXPECT_GE(Samples(Read(out)), 1);
}

// The process ids of `parent`'s children running `name`.
std::vector<pid_t> Children(pid_t parent, const std::string& name) {
  std::vector<pid_t> found;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return found;
  while (dirent* entry = readdir(proc)) {
    const pid_t pid = static_cast<pid_t>(std::atoi(entry->d_name));
    if (pid <= 0) continue;
    // /proc/PID/stat: "pid (comm) state ppid ..."
    const std::string stat = ReadFile("/proc/" + std::to_string(pid) + "/stat");
    const size_t close = stat.rfind(')');
    if (close == std::string::npos || stat.find("(" + name + ")") == std::string::npos) continue;
    if (std::atoi(stat.c_str() + close + 4) == parent) found.push_back(pid);
  }
  closedir(proc);
  return found;
}

// Sums stay on the devices between passes (GPU_LOCAL): a worker killed mid-render takes its share
// along, which the host notices in the sample counts and repairs by running the pass again from
// the last good sums. The image is the same bits as without the fault.
TEST_F(RenderCliTest, AWorkerKilledMidRenderCostsTimeNotBits) {
  const std::string out = Path("faulted.exr");
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t pid =
      Spawn({"render", "builtin:cornell", "-o", out, kWidth, kHeight, "--exr-float", "--spp=150",
             "--pass-samples=1", "--devices=local:2", "--log-level=debug"},
            fds[1]);
  close(fds[1]);
  std::string err;
  char buffer[4096];
  while (err.find("pass done") == std::string::npos) {
    const ssize_t n = read(fds[0], buffer, sizeof(buffer));
    if (n <= 0) break;
    err.append(buffer, static_cast<size_t>(n));
  }
  const std::vector<pid_t> workers = Children(pid, "tessera-worker");
  ASSERT_EQ(workers.size(), 2u) << err;
  ASSERT_EQ(kill(workers[1], SIGKILL), 0);
  std::thread drain([&] {
    for (ssize_t n; (n = read(fds[0], buffer, sizeof(buffer))) > 0;) err.append(buffer, n);
  });
  const Result r = Wait(pid);
  drain.join();
  close(fds[0]);
  ASSERT_EQ(r.status, 0) << err;
  EXPECT_NE(err.find("ran again: a device had lost its accumulation"), std::string::npos) << err;
  ASSERT_EQ(Render(Path("reference.exr"), {"--spp=150", "--exr-float", "--devices=inproc"}).status,
            0);
  ExpectSameBits(Path("reference.exr"), out);
}

TEST_F(RenderCliTest, FramesFollowThePatternAndSkipExistingSkips) {
  const std::string pattern = Path("f.####.png");
  Result r = Render(pattern, {"--spp=1", "--frames=0-48:24", "--max-depth=1"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<std::string> files = {Path("f.0000.png"), Path("f.0024.png"),
                                          Path("f.0048.png")};
  EXPECT_EQ(r.out, files[0] + "\n" + files[1] + "\n" + files[2] + "\n");
  for (const std::string& f : files) EXPECT_TRUE(Exists(f)) << f;
  EXPECT_FALSE(Exists(Path("f.0012.png")));
  // PNG: 8-bit sRGB RGB, its numbers in text chunks.
  const Image last = Read(files[2]);
  EXPECT_EQ(last.spec.format, OIIO::TypeDesc::UINT8);
  EXPECT_EQ(last.channels.size(), 3u);
  EXPECT_EQ(Samples(last), 1);
  EXPECT_EQ(IntAttribute(last, "tessera:frame"), 48);
  // Frame 48 is 2 s later: the short box has moved.
  EXPECT_NE(Read(files[0]).pixels, last.pixels);

  ASSERT_EQ(std::remove(files[1].c_str()), 0);
  r = Render(pattern, {"--spp=1", "--frames=0-48:24", "--max-depth=1", "--skip-existing",
                       "--log-level=info"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, files[1] + "\n") << "only the missing frame is rendered";
  EXPECT_NE(r.err.find(files[0] + " exists, skipped"), std::string::npos) << r.err;
  EXPECT_TRUE(Exists(files[1]));
}

TEST_F(RenderCliTest, MissingSceneIsARenderFailureNamingIt) {
  const std::string missing = Path("nowhere.gltf");
  const Result r = Run({"render", missing, "-o", Path("x.png")});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(missing), std::string::npos) << r.err;
  EXPECT_FALSE(Exists(Path("x.png")));
}

TEST_F(RenderCliTest, UsageErrorsExit2NamingTheFlag) {
  struct Case {
    std::vector<std::string> args;
    const char* named;
  };
  const Case cases[] = {
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--no-such-flag"}, "--no-such-flag"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--frames=5-2"}, "--frames"},
      {{"render", "builtin:cornell", "-o", Path("x.jpg")}, "--output"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--point-light=1,2,3"}, "--point-light"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--point-light=0,0,0,-1,1,1"},
       "--point-light"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--fov=180"}, "--fov"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--threads=0"}, "--threads"},
  };
  for (const Case& c : cases) {
    const Result r = Run(c.args);
    EXPECT_EQ(r.status, 2) << c.named << ": " << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
  }
  // Number checks say what they want in words, not as a range ending in DBL_MAX's 309 digits.
  const Case numbers[] = {
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--fps=0"},
       "--fps: must be greater than 0 (got 0)"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--clamp-indirect=-1"},
       "--clamp-indirect: must be 0 or more (got -1)"},
      {{"render", "builtin:cornell", "-o", Path("x.png"), "--time-limit=soon"},
       "--time-limit: must be a number (got 'soon')"},
  };
  for (const Case& c : numbers) {
    const Result r = Run(c.args);
    EXPECT_EQ(r.status, 2) << c.named << ": " << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 200u) << r.err;
  }
  const Result help = Run({"render", "--help"});
  EXPECT_EQ(help.status, 0);
  for (const char* flag :
       {"--spp", "--time-limit", "--max-depth", "--width", "--height", "--camera", "--frames",
        "--fps", "--skip-existing", "--env", "--seed", "--devices", "--tile-size", "--log-level",
        "--resume", "--threads", "--fov", "--point-light", "--look-from"}) {
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag;
  }
}

}  // namespace

namespace {

// An OBJ with no light and no emissive material (a quad facing the camera) renders lit by a white
// sky, with a warning saying so, and `--background 0,0,0` keeps it black.
TEST_F(RenderCliTest, AnUnlitSceneIsLitByAWhiteSkyWithAWarning) {
  const std::string obj = Path("unlit.obj");
  {
    std::ofstream f(obj);
    f << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
  }
  const std::string lit = Path("lit.png"), black = Path("black.png");
  Result r = Run({"render", obj, "-o", lit, kWidth, kHeight, "--spp=2", "--log-level=warn"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("has no lights and no emissive surfaces: lit by a white sky"),
            std::string::npos)
      << r.err;
  const Image a = Read(lit);
  float sum = 0.f;
  for (float v : a.pixels) sum += v;
  EXPECT_GT(sum, 0.1f * static_cast<float>(a.pixels.size()));
  r = Run({"render", obj, "-o", black, kWidth, kHeight, "--spp=2", "--log-level=warn",
           "--background=0,0,0"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("white sky"), std::string::npos) << r.err;
  const Image b = Read(black);
  float rgb = 0.f;
  for (size_t i = 0; i < b.pixels.size(); i += b.channels.size()) {
    rgb += b.pixels[i] + b.pixels[i + 1] + b.pixels[i + 2];
  }
  EXPECT_EQ(rgb, 0.f);
}

// A Lambertian quad (Kd 0.5, no Ks) lit by `--point-light` alone, seen head-on through `--fov`:
// at its middle, straight below the light, radiance is Kd / pi * I / d^2 (I = 4 pi, d = 2: 0.5),
// with no white sky (the light counts as the scene's); a narrower field of view fills the image
// with the quad, a wider one shows the black background around it.
TEST_F(RenderCliTest, PointLightAndFieldOfViewFromTheCommandLine) {
  const std::string obj = Path("quad.obj"), mtl = Path("quad.mtl");
  {
    std::ofstream m(mtl);
    m << "newmtl grey\nKd 0.5 0.5 0.5\n";
    std::ofstream f(obj);
    f << "mtllib quad.mtl\nusemtl grey\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 "
         "4\n";
  }
  const std::vector<std::string> common = {"render",
                                           obj,
                                           kWidth,
                                           kHeight,
                                           "--spp=4",
                                           "--max-depth=1",
                                           "--exr-float",
                                           "--look-from=0,0,5",
                                           "--look-at=0,0,0",
                                           "--point-light=0,0,2,12.566371,12.566371,12.566371",
                                           "--log-level=warn"};
  std::vector<std::string> narrow = common, wide = common;
  narrow.insert(narrow.end(), {"-o", Path("narrow.exr"), "--fov=10"});
  wide.insert(wide.end(), {"-o", Path("wide.exr"), "--fov=40"});
  Result r = Run(narrow);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("white sky"), std::string::npos) << r.err;
  ASSERT_EQ((r = Run(wide)).status, 0) << r.err;
  const Image a = Read(Path("narrow.exr")), b = Read(Path("wide.exr"));
  ASSERT_EQ(a.width, 64);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(a.At(32, 24, c), 0.5f, 0.01f) << c;  // cos and d barely change across a pixel
    EXPECT_GT(a.At(0, 0, c), 0.05f) << c;            // the quad reaches the corners
    EXPECT_EQ(b.At(0, 0, c), 0.f) << c;              // past the quad: black background
    EXPECT_NEAR(b.At(32, 24, c), 0.5f, 0.01f) << c;
  }
}

}  // namespace
