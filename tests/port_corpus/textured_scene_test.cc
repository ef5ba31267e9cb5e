// The SDK's textured Phong (textured_phong.cu with phong.h) on its parallelogram floor and a
// sphere with texture coordinates, lit by a buffer of BasicLight with shadow rays, under a
// latitude-longitude environment map (envmap.cu), the host making every object with the OptiX C
// API: rendered on inproc, local:1 and local:3, and checked where the host can say what the
// texture, the shadow or the environment must give.
#include <optix.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "common_structs.h"
#include "port_corpus_fixture.h"

namespace tessera::testing {
namespace {

using optix::float3;
using optix::make_float3;

constexpr unsigned kWidth = 64, kHeight = 48;

// The diffuse texture: 8x8 RGBA8 texels in squares of 4x4, red where the square's x + y is even
// and blue where it is odd.
constexpr unsigned kTexels = 8, kSquare = 4;
constexpr unsigned char kRed[4] = {230, 40, 40, 255}, kBlue[4] = {40, 60, 220, 255};
// What a normalized float read of a texel gives: the byte / 255, correctly rounded.
float3 Kd(const unsigned char* texel) {
  return make_float3(texel[0] / 255.f, texel[1] / 255.f, texel[2] / 255.f);
}

// The environment: 16x8 float texels, blocks of 4x4 (four around the horizon, one row below it
// and one above), each block one colour.
constexpr unsigned kEnvWidth = 16, kEnvHeight = 8, kEnvBlock = 4;
float3 EnvColor(unsigned bu, unsigned bv) {
  return bv == 0 ? make_float3(0.30f, 0.25f + 0.05f * bu, 0.10f)
                 : make_float3(0.15f + 0.10f * bu, 0.45f, 0.30f - 0.05f * bu);
}

const PinholeCamera kCamera = {make_float3(0.f, 1.5f, -4.f), make_float3(0.8f, 0.f, 0.f),
                               make_float3(0.f, 0.6f, 0.f), make_float3(0.f, -0.15f, 1.f)};
const float3 kLightPos = make_float3(-4.f, 5.f, -1.f);
const float3 kLightColor = make_float3(0.8f, 0.8f, 0.8f);
const float3 kAmbient = make_float3(0.2f, 0.2f, 0.2f);
const float3 kSphereCentre = make_float3(0.f, 0.f, 0.f);
constexpr float kSphereRadius = 1.f, kFloorY = -1.f, kFloorHalf = 3.f;

// Where coordinate `x` (in texels or env texels) lies in its block of `block`, if bilinear
// filtering there reads that block's texels alone (with a margin for the host's rounding): the
// block's index, else -1.
int BlockOf(float x, unsigned block) {
  const float b = std::floor(x / block), in = x - b * block;
  return in >= 0.6f && in <= block - 0.6f ? static_cast<int>(b) : -1;
}
// The checker square's colour at texture coordinates (u, v), repeated: red 0, blue 1, or -1 near
// an edge.
int CheckerAt(float u, float v) {
  const int sx = BlockOf((u - std::floor(u)) * kTexels, kSquare);
  const int sy = BlockOf((v - std::floor(v)) * kTexels, kSquare);
  if (sx < 0 || sy < 0) return -1;
  return (sx + sy) & 1;
}

class TexturedSceneTest : public PortCorpusTest {
 protected:
  RTbuffer DiffuseTexels() {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_UNSIGNED_BYTE4), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize2D(b, kTexels, kTexels), RT_SUCCESS);
    std::vector<unsigned char> texels;
    for (unsigned j = 0; j < kTexels; ++j) {
      for (unsigned i = 0; i < kTexels; ++i) {
        const unsigned char* c = ((i / kSquare + j / kSquare) & 1) ? kBlue : kRed;
        texels.insert(texels.end(), c, c + 4);
      }
    }
    Fill(b, texels);
    return b;
  }
  RTbuffer EnvTexels() {
    RTbuffer b = nullptr;
    EXPECT_EQ(rtBufferCreate(ctx_, RT_BUFFER_INPUT, &b), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetFormat(b, RT_FORMAT_FLOAT4), RT_SUCCESS);
    EXPECT_EQ(rtBufferSetSize2D(b, kEnvWidth, kEnvHeight), RT_SUCCESS);
    std::vector<float> texels;
    for (unsigned j = 0; j < kEnvHeight; ++j) {
      for (unsigned i = 0; i < kEnvWidth; ++i) {
        const float3 c = EnvColor(i / kEnvBlock, j / kEnvBlock);
        texels.insert(texels.end(), {c.x, c.y, c.z, 1.f});
      }
    }
    Fill(b, texels);
    return b;
  }

  // The scene: the floor (a 6x6 parallelogram at y = -1 whose texture repeats twice along each
  // side) and a unit sphere on it, both textured Phong; one light; the environment map as the
  // miss program. Returns the BGRA8 pixels.
  std::vector<std::uint32_t> Render(const char* spec) {
    UseDevices(spec, 2);  // radiance and shadow rays
    Ok(rtContextSetRayGenerationProgram(ctx_, 0, Program("pinhole_camera", "pinhole_camera")));
    Ok(rtContextSetExceptionProgram(ctx_, 0, Program("pinhole_camera", "exception")));
    Ok(rtContextSetMissProgram(ctx_, 0, Program("envmap", "envmap_miss")));

    RTmaterial material = nullptr;
    Ok(rtMaterialCreate(ctx_, &material));
    Ok(rtMaterialSetClosestHitProgram(material, 0,
                                      Program("textured_phong", "closest_hit_radiance")));
    Ok(rtMaterialSetAnyHitProgram(material, 1, Program("textured_phong", "any_hit_shadow")));
    Ok(rtVariableSetObject(MaterialVar(material, "kd_map"),
                           Sampler2D(DiffuseTexels(), RT_WRAP_REPEAT, RT_WRAP_REPEAT)));
    SetFloat3(MaterialVar(material, "Ks"), make_float3(0.1f, 0.1f, 0.1f));
    Ok(rtVariableSet1f(MaterialVar(material, "phong_exp"), 32.f));

    // The floor as the SDK's parallelogram takes it: edges scaled by 1 / |v|^2.
    RTgeometry floor =
        NewGeometry(Program("parallelogram", "intersect"), Program("parallelogram", "bounds"), 1);
    const float side = 2.f * kFloorHalf;
    const float3 anchor = make_float3(-kFloorHalf, kFloorY, -kFloorHalf);
    Ok(rtVariableSet4f(GeometryVar(floor, "plane"), 0.f, 1.f, 0.f, kFloorY));
    SetFloat3(GeometryVar(floor, "v1"), make_float3(side, 0.f, 0.f) / (side * side));
    SetFloat3(GeometryVar(floor, "v2"), make_float3(0.f, 0.f, side) / (side * side));
    SetFloat3(GeometryVar(floor, "anchor"), anchor);
    RTgeometryinstance floor_instance = NewInstance(floor, material);
    Ok(rtVariableSet2f(InstanceVar(floor_instance, "texcoord_scale"), 2.f, 2.f));
    SetFloat3(InstanceVar(floor_instance, "reflectivity"), make_float3(0.f, 0.f, 0.f));

    RTgeometry sphere = NewGeometry(Program("sphere_texcoord", "intersect"),
                                    Program("sphere_texcoord", "bounds"), 1);
    Ok(rtVariableSet4f(GeometryVar(sphere, "sphere"), kSphereCentre.x, kSphereCentre.y,
                       kSphereCentre.z, kSphereRadius));
    RTgeometryinstance sphere_instance = NewInstance(sphere, material);
    SetFloat3(InstanceVar(sphere_instance, "reflectivity"), make_float3(0.2f, 0.2f, 0.2f));

    RTgeometrygroup group = NewGroup({floor_instance, sphere_instance});
    Ok(rtVariableSetObject(ContextVar("top_object"), group));
    Ok(rtVariableSetObject(ContextVar("top_shadower"), group));

    BasicLight light = {};
    light.pos = kLightPos;
    light.color = kLightColor;
    light.casts_shadow = 1;
    Fill(Buffer1D("lights", RT_BUFFER_INPUT, RT_FORMAT_USER, 1, sizeof(BasicLight)),
         std::vector<BasicLight>{light});
    SetFloat3(ContextVar("ambient_light_color"), kAmbient);
    Ok(rtVariableSet1i(ContextVar("max_depth"), 1));
    Ok(rtVariableSet1ui(ContextVar("radiance_ray_type"), 0));
    Ok(rtVariableSet1ui(ContextVar("shadow_ray_type"), 1));
    Ok(rtVariableSet1f(ContextVar("scene_epsilon"), 1e-3f));
    Ok(rtVariableSetObject(ContextVar("envmap"),
                           Sampler2D(EnvTexels(), RT_WRAP_REPEAT, RT_WRAP_CLAMP_TO_EDGE)));
    SetCamera(kCamera);
    SetFloat3("bad_color", 1.f, 0.f, 1.f);
    RTbuffer out =
        Buffer2D("output_buffer", RT_BUFFER_OUTPUT, RT_FORMAT_UNSIGNED_BYTE4, kWidth, kHeight);
    Ok(rtContextLaunch2D(ctx_, 0, kWidth, kHeight));
    return ReadAs<std::uint32_t>(out);
  }
};

TEST_F(TexturedSceneTest, CheckerShadowsAndEnvironmentWhereTheHostPutsThem) {
  const std::vector<std::uint32_t> image =
      OnEveryDeviceSet([&](const char* spec) { return Render(spec); });
  ASSERT_EQ(image.size(), size_t{kWidth} * kHeight);

  // What only ambient light gives each colour: a shadowed floor pixel, to the bit.
  const std::uint32_t in_shadow[2] = {Bgra8(Kd(kRed) * kAmbient), Bgra8(Kd(kBlue) * kAmbient)};
  int floor_lit[2] = {0, 0}, floor_shadowed[2] = {0, 0}, sphere_lit[2] = {0, 0}, env = 0;
  std::set<std::uint32_t> env_colors;
  for (unsigned y = 0; y < kHeight; ++y) {
    for (unsigned x = 0; x < kWidth; ++x) {
      SCOPED_TRACE(::testing::Message() << "pixel (" << x << ", " << y << ")");
      const std::uint32_t pixel = image[y * kWidth + x];
      const float3 dir = kCamera.Direction(x, y, kWidth, kHeight);
      const float near_sphere = HitSphere(kCamera.eye, dir, kSphereCentre, kSphereRadius + 0.05f);
      const float t_floor = dir.y < 0.f ? (kFloorY - kCamera.eye.y) / dir.y : -1.f;
      const float3 p = kCamera.eye + t_floor * dir;
      const bool floor_hit =
          t_floor > 0.f && std::fabs(p.x) < kFloorHalf + 0.1f && std::fabs(p.z) < kFloorHalf + 0.1f;

      if (near_sphere < 0.f && !floor_hit) {
        // The environment in this direction, as envmap.cu looks it up.
        const float u = (std::atan2(dir.x, dir.z) + M_PIf) * (0.5f * M_1_PIf);
        const float v = 0.5f * (1.f + std::sin(M_PIf * 0.5f - std::acos(dir.y)));
        const int bu = BlockOf(u * kEnvWidth, kEnvBlock), bv = BlockOf(v * kEnvHeight, kEnvBlock);
        if (bu < 0 || bv < 0) continue;
        EXPECT_EQ(pixel, Bgra8(EnvColor(bu, bv))) << "environment block " << bu << ", " << bv;
        env_colors.insert(pixel);
        ++env;
        continue;
      }

      const float on_sphere = HitSphere(kCamera.eye, dir, kSphereCentre, kSphereRadius - 0.05f);
      if (on_sphere > 0.f) {
        // The sphere's texture coordinates, as sphere_texcoord.cu reports them, where the light
        // reaches the surface well: the square's colour dominates.
        const float t = HitSphere(kCamera.eye, dir, kSphereCentre, kSphereRadius);
        const float3 n = optix::normalize(kCamera.eye + t * dir - kSphereCentre);
        const float3 to_light = optix::normalize(kLightPos - (kCamera.eye + t * dir));
        const int square =
            CheckerAt((std::atan2(n.x, n.z) + M_PIf) * (0.5f * M_1_PIf), std::acos(n.y) * M_1_PIf);
        if (square < 0 || optix::dot(n, to_light) < 0.2f) continue;
        const int dominant = square == 0 ? 0 : 2, other = 2 - dominant;
        EXPECT_GT(Channel(pixel, dominant), Channel(pixel, other)) << "sphere square " << square;
        ++sphere_lit[square];
        continue;
      }

      if (!floor_hit || (near_sphere > 0.f && near_sphere < t_floor)) continue;
      if (std::fabs(p.x) > kFloorHalf - 0.1f || std::fabs(p.z) > kFloorHalf - 0.1f) continue;
      const int square = CheckerAt(2.f * (p.x + kFloorHalf) / (2.f * kFloorHalf),
                                   2.f * (p.z + kFloorHalf) / (2.f * kFloorHalf));
      if (square < 0) continue;
      const float3 to_light = kLightPos - p;
      const float3 l = optix::normalize(to_light);
      const float blocker = HitSphere(p, l, kSphereCentre, kSphereRadius - 0.05f);
      const float clear = HitSphere(p, l, kSphereCentre, kSphereRadius + 0.05f);
      if (blocker > 0.f) {
        EXPECT_EQ(pixel, in_shadow[square]) << "a shadowed floor square " << square;
        ++floor_shadowed[square];
      } else if (clear < 0.f) {
        // Lit: the square's colour dominates, brighter than in shadow.
        const int dominant = square == 0 ? 0 : 2, other = 2 - dominant;
        EXPECT_GT(Channel(pixel, dominant), Channel(pixel, other)) << "floor square " << square;
        EXPECT_GT(Channel(pixel, dominant), Channel(in_shadow[square], dominant))
            << "a lit floor square " << square;
        ++floor_lit[square];
      }
    }
  }
  // Enough of each case was seen for the checks above to mean something.
  EXPECT_GE(floor_lit[0], 40);
  EXPECT_GE(floor_lit[1], 40);
  EXPECT_GE(floor_shadowed[0] + floor_shadowed[1], 10);
  EXPECT_GE(sphere_lit[0], 5);
  EXPECT_GE(sphere_lit[1], 5);
  EXPECT_GE(env, 50);
  EXPECT_GE(env_colors.size(), 3u) << "environment blocks seen";
  RecordProperty("floor_lit_red", floor_lit[0]);
  RecordProperty("floor_lit_blue", floor_lit[1]);
  RecordProperty("floor_shadowed", floor_shadowed[0] + floor_shadowed[1]);
  RecordProperty("sphere_red", sphere_lit[0]);
  RecordProperty("sphere_blue", sphere_lit[1]);
  RecordProperty("environment", env);
}

}  // namespace
}  // namespace tessera::testing
