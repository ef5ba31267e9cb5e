// tessera-bench-texture: what a bilinear texture lookup costs a launch. A 2048x2048 RGBA8 texture
// is read once per launch index of a 2048x2048 launch, through an rtTextureSampler (bilinear,
// normalized float read mode: tex2D) and, as the baseline, as the nearest texel from an
// rtBuffer<uchar4, 2> converted to float by hand. Both write a float4 OUTPUT buffer. The last line
// is texture_vs_buffer=<median textured launch / median buffer launch> (target: at most 1.3).
// --check runs 64x64 and exits 1 unless the buffer launch gives the nearest texels exactly and
// the textured one CUDA's bilinear blend (weights with 8 fractional bits) of the four around.
#include <tessera/rt.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "common/rt_util.h"

namespace tessera::bench {
namespace {

struct Options {
  unsigned size = 2048;  // texture and launch, square
  std::string devices = "inproc";
  int repeats = 7;
  std::string module = TESSERA_BENCH_MODULE_DIR "/bench_texture.so";
  bool check = false;
};

// Texel bytes: a fixed hash of the position, so images are reproducible.
uint8_t TexelByte(unsigned x, unsigned y, unsigned channel) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ channel * 0xcb1ab31fu;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return static_cast<uint8_t>(h >> 24);
}

class TextureContext {
 public:
  explicit TextureContext(const Options& o) : size_(o.size) {
    Check(nullptr, rtContextCreate(&context_), "rtContextCreate");
    try {
      Build(o);
    } catch (...) {
      rtContextDestroy(context_);
      throw;
    }
  }
  ~TextureContext() { rtContextDestroy(context_); }
  TextureContext(const TextureContext&) = delete;
  TextureContext& operator=(const TextureContext&) = delete;

  // Launches entry 0 (sample_texture) or 1 (read_buffer); returns its wall time.
  double Launch(unsigned entry) {
    const double start = NowSeconds();
    Check(context_, rtContextLaunch2D(context_, entry, size_, size_), "rtContextLaunch2D");
    return NowSeconds() - start;
  }

  std::vector<float> Output() {
    void* mapped = nullptr;
    Check(context_, rtBufferMap(output_, &mapped), "rtBufferMap(output)");
    const float* f = static_cast<const float*>(mapped);
    std::vector<float> values(f, f + size_t{size_} * size_ * 4);
    Check(context_, rtBufferUnmap(output_), "rtBufferUnmap(output)");
    return values;
  }

 private:
  void Build(const Options& o) {
    UseDevices(context_, o.devices);
    Check(context_, rtContextSetEntryPointCount(context_, 2), "rtContextSetEntryPointCount");
    Check(context_, rtContextSetRayTypeCount(context_, 1), "rtContextSetRayTypeCount");
    const char* entries[] = {"sample_texture", "read_buffer"};
    for (unsigned i = 0; i < 2; ++i) {
      RTprogram program = nullptr;
      Check(context_, rtProgramCreateFromPTXFile(context_, o.module.c_str(), entries[i], &program),
            std::string("rtProgramCreateFromPTXFile ") + entries[i]);
      Check(context_, rtContextSetRayGenerationProgram(context_, i, program),
            "rtContextSetRayGenerationProgram");
    }
    output_ = Buffer(RT_BUFFER_OUTPUT, RT_FORMAT_FLOAT4);
    RTbuffer texels = Buffer(RT_BUFFER_INPUT, RT_FORMAT_UNSIGNED_BYTE4);
    void* mapped = nullptr;
    Check(context_, rtBufferMap(texels, &mapped), "rtBufferMap(texels)");
    uint8_t* bytes = static_cast<uint8_t*>(mapped);
    for (unsigned y = 0; y < size_; ++y) {
      for (unsigned x = 0; x < size_; ++x) {
        for (unsigned c = 0; c < 4; ++c)
          bytes[(size_t{y} * size_ + x) * 4 + c] = TexelByte(x, y, c);
      }
    }
    Check(context_, rtBufferUnmap(texels), "rtBufferUnmap(texels)");

    RTtexturesampler sampler = nullptr;
    Check(context_, rtTextureSamplerCreate(context_, &sampler), "rtTextureSamplerCreate");
    for (unsigned d = 0; d < 2; ++d) {
      Check(context_, rtTextureSamplerSetWrapMode(sampler, d, RT_WRAP_CLAMP_TO_EDGE),
            "rtTextureSamplerSetWrapMode");
    }
    Check(context_,
          rtTextureSamplerSetFilteringModes(sampler, RT_FILTER_LINEAR, RT_FILTER_LINEAR,
                                            RT_FILTER_NONE),
          "rtTextureSamplerSetFilteringModes");
    Check(context_, rtTextureSamplerSetReadMode(sampler, RT_TEXTURE_READ_NORMALIZED_FLOAT),
          "rtTextureSamplerSetReadMode");
    Check(context_,
          rtTextureSamplerSetIndexingMode(sampler, RT_TEXTURE_INDEX_NORMALIZED_COORDINATES),
          "rtTextureSamplerSetIndexingMode");
    Check(context_, rtTextureSamplerSetMaxAnisotropy(sampler, 1.0f),
          "rtTextureSamplerSetMaxAnisotropy");
    Check(context_, rtTextureSamplerSetMipLevelCount(sampler, 1),
          "rtTextureSamplerSetMipLevelCount");
    Check(context_, rtTextureSamplerSetArraySize(sampler, 1), "rtTextureSamplerSetArraySize");
    Check(context_, rtTextureSamplerSetBuffer(sampler, 0, 0, texels), "rtTextureSamplerSetBuffer");

    Object("output", output_);
    Object("texels", texels);
    RTvariable v = nullptr;
    Check(context_, rtContextDeclareVariable(context_, "image", &v), "declare image");
    Check(context_, rtVariableSetObject(v, sampler), "rtVariableSetObject(image)");
  }

  RTbuffer Buffer(unsigned type, RTformat format) {
    RTbuffer b = nullptr;
    Check(context_, rtBufferCreate(context_, type, &b), "rtBufferCreate");
    Check(context_, rtBufferSetFormat(b, format), "rtBufferSetFormat");
    Check(context_, rtBufferSetSize2D(b, size_, size_), "rtBufferSetSize2D");
    return b;
  }

  void Object(const char* name, RTbuffer buffer) {
    RTvariable v = nullptr;
    Check(context_, rtContextDeclareVariable(context_, name, &v), std::string("declare ") + name);
    Check(context_, rtVariableSetObject(v, buffer), std::string("rtVariableSetObject ") + name);
  }

  unsigned size_;
  RTcontext context_ = nullptr;
  RTbuffer output_ = nullptr;
};

// The coordinate texture.cu's Coordinate() gives launch index i of n, in texels, and the
// program's float arithmetic.
float TexelCoordinate(unsigned i, unsigned n, unsigned texels, float offset) {
  return (static_cast<float>(i) + offset) / static_cast<float>(n) * static_cast<float>(texels);
}

// CUDA's linear filtering of one channel (CUDA C Programming Guide, "Linear Filtering"): the
// weight has 8 fractional bits; coordinates clamp to the edge texels.
float Bilinear(unsigned size, float x, float y, unsigned c) {
  const float xb = x - 0.5f, yb = y - 0.5f;
  const float fx = std::floor(xb), fy = std::floor(yb);
  const float a = std::round((xb - fx) * 256.0f) / 256.0f;
  const float b = std::round((yb - fy) * 256.0f) / 256.0f;
  auto texel = [&](float tx, float ty) {
    const unsigned cx = static_cast<unsigned>(std::clamp(tx, 0.0f, static_cast<float>(size - 1)));
    const unsigned cy = static_cast<unsigned>(std::clamp(ty, 0.0f, static_cast<float>(size - 1)));
    return TexelByte(cx, cy, c) / 255.0f;
  };
  return (1 - a) * (1 - b) * texel(fx, fy) + a * (1 - b) * texel(fx + 1, fy) +
         (1 - a) * b * texel(fx, fy + 1) + a * b * texel(fx + 1, fy + 1);
}

int RunCheck(Options o) {
  o.size = 64;
  TextureContext context(o);
  size_t wrong_texture = 0, wrong_buffer = 0;
  context.Launch(0);
  const std::vector<float> sampled = context.Output();
  context.Launch(1);
  const std::vector<float> read = context.Output();
  for (unsigned y = 0; y < o.size; ++y) {
    for (unsigned x = 0; x < o.size; ++x) {
      const float tx = TexelCoordinate(x, o.size, o.size, 0.3f);
      const float ty = TexelCoordinate(y, o.size, o.size, 0.7f);
      for (unsigned c = 0; c < 4; ++c) {
        const size_t i = (size_t{y} * o.size + x) * 4 + c;
        if (std::fabs(sampled[i] - Bilinear(o.size, tx, ty, c)) > 1e-5f) ++wrong_texture;
        const float nearest = TexelByte(std::min(static_cast<unsigned>(tx), o.size - 1),
                                        std::min(static_cast<unsigned>(ty), o.size - 1), c) /
                              255.0f;
        if (std::fabs(read[i] - nearest) > 1e-6f) ++wrong_buffer;
      }
    }
  }
  std::printf("check %ux%u: %zu wrong texture values, %zu wrong buffer values\n", o.size, o.size,
              wrong_texture, wrong_buffer);
  return wrong_texture == 0 && wrong_buffer == 0 ? 0 : 1;
}

int Run(const Options& o) {
  TextureContext context(o);
  std::printf("texture %ux%u RGBA8, launch %ux%u on '%s', %d repeats (load average %.2f)\n", o.size,
              o.size, o.size, o.size, o.devices.c_str(), o.repeats, LoadAverage());
  context.Launch(0);  // first launches ship the state and load the modules
  context.Launch(1);
  std::vector<double> texture, buffer;
  for (int r = 0; r < o.repeats; ++r) {  // interleaved, so that load changes hit both alike
    texture.push_back(context.Launch(0));
    buffer.push_back(context.Launch(1));
  }
  const double t = Median(texture), b = Median(buffer);
  std::printf("%-28s %8.1f ms\n", "bilinear tex2D per index", t * 1e3);
  std::printf("%-28s %8.1f ms\n", "buffer read per index", b * 1e3);
  std::printf("texture_vs_buffer=%.3f\n", t / b);
  return 0;
}

}  // namespace
}  // namespace tessera::bench

int main(int argc, char** argv) {
  tessera::bench::Options o;
  CLI::App app{"A bilinear texture lookup per launch index against a buffer read."};
  app.add_option("--size", o.size, "texture and launch side")->capture_default_str();
  app.add_option("--devices", o.devices, "device spec")->capture_default_str();
  app.add_option("--repeats", o.repeats, "timed launches of each")->capture_default_str();
  app.add_option("--module", o.module, "bench_texture.so")->capture_default_str();
  app.add_flag("--check", o.check, "64x64, checks values only");
  CLI11_PARSE(app, argc, argv);
  try {
    return o.check ? tessera::bench::RunCheck(o) : tessera::bench::Run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tessera-bench-texture: %s\n", e.what());
    return 1;
  }
}
