// Loads the OptiX-style programs that CMake compiled as modules (optix_style_program.cu,
// no_using_directive_program.cu) and checks what their entry points compute. Loading with
// RTLD_NOW also proves every function they call has a definition somewhere.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

namespace {

class Module {
 public:
  explicit Module(const char* name) {
    const std::string path = std::string(TESSERA_DEVICE_MATH_MODULE_DIR) + "/" + name + ".so";
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle_ == nullptr) error_ = dlerror();
  }
  ~Module() {
    if (handle_ != nullptr) dlclose(handle_);
  }
  Module(const Module&) = delete;
  Module& operator=(const Module&) = delete;

  bool loaded() const { return handle_ != nullptr; }
  const std::string& error() const { return error_; }

  template <typename Fn>
  Fn* Get(const char* symbol) const {
    return reinterpret_cast<Fn*>(dlsym(handle_, symbol));
  }

 private:
  void* handle_ = nullptr;
  std::string error_;
};

class OptixStyleProgramTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(module_.loaded()) << module_.error(); }

  template <typename Fn>
  Fn* Get(const char* symbol) {
    Fn* fn = module_.Get<Fn>(symbol);
    EXPECT_NE(fn, nullptr) << symbol;
    return fn;
  }

  Module module_{"optix_style_program"};
};

TEST_F(OptixStyleProgramTest, SphereIntersectionAndBounds) {
  auto* intersect =
      Get<float(float, float, float, float, float, float)>("program_intersect_sphere");
  ASSERT_NE(intersect, nullptr);
  EXPECT_FLOAT_EQ(intersect(0.0f, 0.0f, -5.0f, 0.0f, 0.0f, 1.0f), 4.0f);
  EXPECT_EQ(intersect(0.0f, 5.0f, -5.0f, 0.0f, 0.0f, 1.0f), -1.0f);

  auto* bound = Get<void(int, float*)>("program_bound_sphere");
  ASSERT_NE(bound, nullptr);
  float result[6] = {};
  bound(0, result);
  const float expected[6] = {-1.0f, -1.0f, -1.0f, 1.0f, 1.0f, 1.0f};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(result[i], expected[i]) << i;
}

TEST_F(OptixStyleProgramTest, WhittedShading) {
  auto* shade =
      Get<void(const float*, const float*, const float*, float*, float*, float*)>("program_shade");
  ASSERT_NE(shade, nullptr);
  const float hit[3] = {0.0f, 0.0f, 0.0f};
  const float dir[3] = {0.0f, -1.0f, 0.0f};
  const float normal[3] = {0.0f, 1.0f, 0.0f};
  float color[3];
  float reflected[3];
  float importance = 0.0f;
  shade(hit, dir, normal, color, reflected, &importance);
  // Ambient 0.2 * 0.5, diffuse 0.5 * 1, specular 0.2 * 1^88.
  for (float c : color) EXPECT_FLOAT_EQ(c, 0.8f);
  EXPECT_FLOAT_EQ(reflected[0], 0.0f);
  EXPECT_FLOAT_EQ(reflected[1], 1.0f);
  EXPECT_FLOAT_EQ(reflected[2], 0.0f);
  EXPECT_FLOAT_EQ(importance, 0.05f);
}

TEST_F(OptixStyleProgramTest, Refraction) {
  auto* refract = Get<int(float, const float*, const float*, float*)>("program_refract");
  ASSERT_NE(refract, nullptr);
  const float n[3] = {0.0f, 1.0f, 0.0f};
  const float straight[3] = {0.0f, -1.0f, 0.0f};
  float out[3];
  EXPECT_EQ(refract(1.5f, straight, n, out), 1);
  EXPECT_NEAR(out[1], -1.0f, 1e-6f);
  const float grazing_exit[3] = {std::sin(1.0472f), std::cos(1.0472f), 0.0f};
  EXPECT_EQ(refract(1.5f, grazing_exit, n, out), 0);
  EXPECT_EQ(out[0], 0.0f);
}

TEST_F(OptixStyleProgramTest, CameraAndEnvironment) {
  auto* pinhole = Get<void(unsigned, unsigned, unsigned, unsigned, float*)>("program_pinhole");
  ASSERT_NE(pinhole, nullptr);
  float d[3];
  pinhole(320, 240, 640, 480, d);
  EXPECT_FLOAT_EQ(d[0], 0.0f);
  EXPECT_FLOAT_EQ(d[1], 0.0f);
  EXPECT_FLOAT_EQ(d[2], -1.0f);
  pinhole(0, 0, 640, 480, d);
  const float k = -1.0f / std::sqrt(3.0f);
  EXPECT_FLOAT_EQ(d[0], k);
  EXPECT_FLOAT_EQ(d[1], k);
  EXPECT_FLOAT_EQ(d[2], k);

  auto* env = Get<void(float, float, float, float*)>("program_env_uv");
  ASSERT_NE(env, nullptr);
  float uv[2];
  env(0.0f, 0.0f, 1.0f, uv);
  EXPECT_FLOAT_EQ(uv[0], 0.5f);
  EXPECT_FLOAT_EQ(uv[1], 0.5f);
}

TEST_F(OptixStyleProgramTest, ConvexHullRustAndTransform) {
  auto* chull = Get<float(float, float, float, float, float, float)>("program_chull");
  ASSERT_NE(chull, nullptr);
  EXPECT_FLOAT_EQ(chull(0.0f, 0.0f, -5.0f, 0.0f, 0.0f, 1.0f), 4.0f);

  auto* rust = Get<float(float, float, float)>("program_rust");
  ASSERT_NE(rust, nullptr);
  EXPECT_FLOAT_EQ(rust(2.25f, 1.0f, 1.0f), 0.25f);
  EXPECT_FLOAT_EQ(rust(-0.75f, 3.0f, 0.0f), 0.25f);

  auto* transform = Get<void(float*)>("program_transform");
  ASSERT_NE(transform, nullptr);
  float p[4];
  transform(p);
  EXPECT_NEAR(p[0], 1.0f, 1e-6f);
  EXPECT_NEAR(p[1], 3.0f, 1e-6f);
  EXPECT_NEAR(p[2], 3.0f, 1e-6f);
  EXPECT_EQ(p[3], 1.0f);
}

TEST_F(OptixStyleProgramTest, IntrinsicsAndAtomicsInsideTheModule) {
  auto* count = Get<unsigned(unsigned)>("program_count");
  ASSERT_NE(count, nullptr);
  const unsigned start = count(0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([count] { count(10000); });
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(count(0) - start, 40000u);

  auto* bits = Get<int(float)>("program_bits");
  ASSERT_NE(bits, nullptr);
  EXPECT_EQ(bits(1.0f), 0x3F800000 ^ 7);

  auto* fast = Get<float(float)>("program_fast_math");
  ASSERT_NE(fast, nullptr);
  EXPECT_NEAR(fast(1.0f), std::exp(1.0f) + 4.5f, 1e-5f);

  auto* alignment = Get<int()>("program_payload_alignment");
  ASSERT_NE(alignment, nullptr);
  EXPECT_EQ(alignment(), 16);
}

TEST(NoUsingDirectiveProgramTest, LookupWithoutUsingNamespaceOptix) {
  Module module("no_using_directive_program");
  ASSERT_TRUE(module.loaded()) << module.error();
  auto* adl = module.Get<float(float, float, float)>("module_adl");
  auto* qualified = module.Get<float(float)>("module_qualified");
  auto* std_mix = module.Get<int(int, int)>("module_std_mix");
  ASSERT_NE(adl, nullptr);
  ASSERT_NE(qualified, nullptr);
  ASSERT_NE(std_mix, nullptr);
  EXPECT_FLOAT_EQ(adl(3.0f, 0.0f, 4.0f), 2.4f);
  EXPECT_FLOAT_EQ(qualified(2.0f), 9.0f);
  EXPECT_EQ(std_mix(3, 9), 13);
}

}  // namespace
