// tessera-optix7-texture-probe: CUDA texture objects end to end, as an OptiX 7 application uses
// them. Makes arrays (1D, 2D, 3D, layered, cube maps, mipmapped), pitched and linear memory of
// every texel family, fills them with cudaMemcpy2DToArray, cudaMemcpy3D, cudaMemcpy2D and
// cudaMemcpy, creates texture objects over them with CUDA's address, filter and read modes, and
// launches probe.cu, which samples them with tex1D ... texCubemapLayered, the Lod and Grad forms,
// tex1Dfetch and tex2Dgather at chosen coordinates. Every result must equal, bit for bit, what the
// OptiX 3 layer's sampler returns for the same texels described as an OptiX 3 rtTextureSampler
// (reference.cc). Exit 0 when all do; otherwise each mismatch is printed and the exit is 1.
// tests/optix7_textures runs it on inproc, local:1 and local:3.
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "probe.h"
#include "reference.h"

#define CHECK_CUDA(call)                                                                          \
  do {                                                                                            \
    const cudaError_t e_ = (call);                                                                \
    if (e_ != cudaSuccess) {                                                                      \
      std::fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call, cudaGetErrorString(e_)); \
      std::exit(1);                                                                               \
    }                                                                                             \
  } while (0)
#define CHECK_OPTIX(call)                                                                        \
  do {                                                                                           \
    const OptixResult r_ = (call);                                                               \
    if (r_ != OPTIX_SUCCESS) {                                                                   \
      std::fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call, optixGetErrorName(r_)); \
      std::exit(1);                                                                              \
    }                                                                                            \
  } while (0)

namespace {

using reference::Wrap;

enum class Storage { kArray, kPitched, kLinear, kMipmapped };

// One texture: its texels, its storage, its modes, and the lookups probed on it.
struct Case {
  const char* name;
  char kind;  // 'u', 's', 'f' (float), 'h' (half)
  unsigned bits, channels;
  unsigned w, h, d;  // level 0; d counts layers or faces when layered or a cube map
  unsigned flags;    // cudaArrayLayered, cudaArrayCubemap
  Storage storage;
  unsigned levels;
  Wrap wrap[3];
  bool linear;
  char mip;  // 'n', 'p', 'l'
  bool normalized_read, srgb, normalized_coords;
  float mip_bias, mip_max;
  std::vector<unsigned> ops;
  unsigned result;
};

// A small deterministic generator: the same texels and coordinates on every run.
struct Random {
  uint64_t s;
  uint32_t Next() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(s >> 33);
  }
  float Uniform(float lo, float hi) { return lo + (hi - lo) * (Next() % 1000000) / 1e6f; }
};

unsigned Dims(const Case& c) {
  if (c.flags != 0) return 3;
  return c.d > 1 ? 3 : c.h > 1 ? 2 : 1;
}

// Level `l`'s size, as CUDA (and tessera/detail/mip_levels.h) make mipmaps: halved, at least 1.
void LevelSize(const Case& c, unsigned l, unsigned* w, unsigned* h, unsigned* d) {
  *w = std::max(1u, c.w >> l);
  *h = std::max(1u, c.h >> l);
  *d = c.flags != 0 ? c.d : std::max(1u, c.d >> l);
}

std::vector<unsigned char> Texels(const Case& c, size_t count, Random& r) {
  const size_t bytes = count * c.bits / 8 * c.channels;
  std::vector<unsigned char> t(bytes);
  const size_t elements = count * c.channels;
  for (size_t i = 0; i < elements; ++i) {
    if (c.kind == 'f') {
      const float f = r.Uniform(-2.f, 2.f);
      std::memcpy(&t[i * 4], &f, 4);
    } else if (c.kind == 'h') {
      uint16_t h = static_cast<uint16_t>(r.Next());
      if (((h >> 10) & 0x1f) == 0x1f) h ^= 0x4000;  // finite
      std::memcpy(&t[i * 2], &h, 2);
    } else {
      for (unsigned b = 0; b < c.bits / 8; ++b) t[i * c.bits / 8 + b] = r.Next() & 0xff;
    }
  }
  return t;
}

cudaTextureAddressMode AddressOf(Wrap w) {
  switch (w) {
    case Wrap::kRepeat:
      return cudaAddressModeWrap;
    case Wrap::kMirror:
      return cudaAddressModeMirror;
    case Wrap::kClampToBorder:
      return cudaAddressModeBorder;
    default:
      return cudaAddressModeClamp;
  }
}

cudaChannelFormatDesc DescOf(const Case& c) {
  const int b = static_cast<int>(c.bits);
  const cudaChannelFormatKind kind = c.kind == 'u'   ? cudaChannelFormatKindUnsigned
                                     : c.kind == 's' ? cudaChannelFormatKindSigned
                                                     : cudaChannelFormatKindFloat;
  return cudaCreateChannelDesc(b, c.channels > 1 ? b : 0, c.channels > 2 ? b : 0,
                               c.channels > 2 ? b : 0, kind);
}

// Copies one level's packed texels into an array with cudaMemcpy2DToArray (one plane) or
// cudaMemcpy3D (several), as applications do.
void Fill(cudaArray_t a, const unsigned char* texels, size_t row, unsigned h, unsigned d,
          unsigned texel) {
  if (d == 1) {
    CHECK_CUDA(cudaMemcpy2DToArray(a, 0, 0, texels, row, row, h, cudaMemcpyHostToDevice));
    return;
  }
  cudaMemcpy3DParms p = {};
  p.srcPtr = make_cudaPitchedPtr(const_cast<unsigned char*>(texels), row, row / texel, h);
  p.dstArray = a;
  p.extent = make_cudaExtent(row / texel, h, d);
  p.kind = cudaMemcpyHostToDevice;
  CHECK_CUDA(cudaMemcpy3D(&p));
}

struct Made {
  cudaTextureObject_t texture;
  reference::Sampler sampler;
  std::vector<unsigned char> texels;  // every level, packed, one after another
};

void MakeTexture(const Case& c, Random& r, Made* m) {
  const unsigned texel = c.bits / 8 * c.channels;
  const unsigned levels = c.storage == Storage::kMipmapped ? c.levels : 1;
  std::vector<size_t> offsets;
  size_t total = 0;
  for (unsigned l = 0; l < levels; ++l) {
    unsigned w, h, d;
    LevelSize(c, l, &w, &h, &d);
    offsets.push_back(total);
    total += size_t(w) * h * d;
  }
  m->texels = Texels(c, total, r);
  const cudaChannelFormatDesc desc = DescOf(c);
  cudaResourceDesc res = {};
  // CUDA's extents: 0 for an unused height or depth (a 1D layered array has height 0).
  const bool has_height = c.h > 1 || (c.flags & cudaArrayCubemap) != 0 || (c.d > 1 && c.flags == 0);
  const cudaExtent extent = make_cudaExtent(c.w, has_height ? c.h : 0, c.d > 1 ? c.d : 0);
  switch (c.storage) {
    case Storage::kArray: {
      cudaArray_t a = nullptr;
      CHECK_CUDA(cudaMalloc3DArray(&a, &desc, extent, c.flags));
      Fill(a, m->texels.data(), size_t(c.w) * texel, c.h, c.d, texel);
      res.resType = cudaResourceTypeArray;
      res.res.array.array = a;
      break;
    }
    case Storage::kMipmapped: {
      cudaMipmappedArray_t mm = nullptr;
      CHECK_CUDA(cudaMallocMipmappedArray(&mm, &desc, extent, c.levels, c.flags));
      for (unsigned l = 0; l < levels; ++l) {
        cudaArray_t a = nullptr;
        CHECK_CUDA(cudaGetMipmappedArrayLevel(&a, mm, l));
        unsigned w, h, d;
        LevelSize(c, l, &w, &h, &d);
        Fill(a, m->texels.data() + offsets[l] * texel, size_t(w) * texel, h, d, texel);
      }
      res.resType = cudaResourceTypeMipmappedArray;
      res.res.mipmap.mipmap = mm;
      break;
    }
    case Storage::kPitched: {
      void* p = nullptr;
      size_t pitch = 0;
      CHECK_CUDA(cudaMallocPitch(&p, &pitch, size_t(c.w) * texel, c.h));
      CHECK_CUDA(cudaMemcpy2D(p, pitch, m->texels.data(), size_t(c.w) * texel, size_t(c.w) * texel,
                              c.h, cudaMemcpyHostToDevice));
      res.resType = cudaResourceTypePitch2D;
      res.res.pitch2D.devPtr = p;
      res.res.pitch2D.desc = desc;
      res.res.pitch2D.width = c.w;
      res.res.pitch2D.height = c.h;
      res.res.pitch2D.pitchInBytes = pitch;
      break;
    }
    case Storage::kLinear: {
      void* p = nullptr;
      CHECK_CUDA(cudaMalloc(&p, m->texels.size()));
      CHECK_CUDA(cudaMemcpy(p, m->texels.data(), m->texels.size(), cudaMemcpyHostToDevice));
      res.resType = cudaResourceTypeLinear;
      res.res.linear.devPtr = p;
      res.res.linear.desc = desc;
      res.res.linear.sizeInBytes = m->texels.size();
      break;
    }
  }
  cudaTextureDesc tex = {};
  for (int i = 0; i < 3; ++i) tex.addressMode[i] = AddressOf(c.wrap[i]);
  tex.filterMode = c.linear ? cudaFilterModeLinear : cudaFilterModePoint;
  tex.mipmapFilterMode = c.mip == 'l' ? cudaFilterModeLinear : cudaFilterModePoint;
  tex.readMode = c.normalized_read ? cudaReadModeNormalizedFloat : cudaReadModeElementType;
  tex.sRGB = c.srgb;
  tex.normalizedCoords = c.normalized_coords;
  tex.mipmapLevelBias = c.mip_bias;
  tex.maxMipmapLevelClamp = c.mip_max;
  CHECK_CUDA(cudaCreateTextureObject(&m->texture, &res, &tex, nullptr));

  reference::Sampler& s = m->sampler;
  for (unsigned l = 0; l < levels; ++l) {
    unsigned w, h, d;
    LevelSize(c, l, &w, &h, &d);
    s.levels[l] = {m->texels.data() + offsets[l] * texel, w, h, d};
  }
  s.level_count = levels;
  s.buffer_dims = Dims(c);
  s.layered = (c.flags & cudaArrayLayered) != 0;
  s.cubemap = (c.flags & cudaArrayCubemap) != 0;
  s.kind = c.kind;
  s.bits = c.bits;
  s.channels = c.channels;
  for (int i = 0; i < 3; ++i) s.wrap[i] = c.wrap[i];
  s.linear = c.linear;
  s.mip = c.storage == Storage::kMipmapped ? c.mip : 'n';
  s.normalized_read = c.normalized_read;
  s.srgb = c.srgb;
  s.normalized_coords = c.normalized_coords;
  s.mip_bias = c.mip_bias;
  s.mip_max = c.mip_max;
}

// Coordinates along an axis of n texels: random ones, texel centres and edges, and some outside.
float Coordinate(const Case& c, unsigned n, unsigned k, Random& r) {
  static const float kSpecial[] = {0.f, 0.5f, 1.f, -0.25f, 1.75f, 0.999f, 2.5f, -3.125f};
  const float f = k < 8 ? kSpecial[k] : r.Uniform(-1.5f, 2.5f);
  return c.normalized_coords ? f : f * static_cast<float>(n);
}

// One texture per row.
// clang-format off
const Case kCases[] = {
    // name, kind, bits, channels, w, h, d, flags, storage, levels, wrap, linear, mip,
    // normalized read, sRGB, normalized coordinates, mip bias, mip max, lookups, result type
    {"rgba8 bilinear wrap", 'u', 8, 4, 13, 7, 1, 0, Storage::kArray, 1,
     {Wrap::kRepeat, Wrap::kRepeat, Wrap::kRepeat}, true, 'n', true, false, true, 0, 0,
     {kTex2D, kTex2DPointerForm, kTex2DLod}, kFloat4},
    {"rgba8 bilinear clamp sRGB", 'u', 8, 4, 9, 9, 1, 0, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kRepeat}, true, 'n', true, true, true, 0, 0,
     {kTex2D}, kFloat4},
    {"rgba8 point mirror/border element", 'u', 8, 4, 6, 5, 1, 0, Storage::kArray, 1,
     {Wrap::kMirror, Wrap::kClampToBorder, Wrap::kRepeat}, false, 'n', false, false, true, 0, 0,
     {kTex2D}, kUchar4},
    {"rgba8 gather", 'u', 8, 4, 5, 4, 1, 0, Storage::kArray, 1,
     {Wrap::kRepeat, Wrap::kMirror, Wrap::kRepeat}, false, 'n', true, false, true, 0, 0,
     {kTex2DGather}, kFloat4},
    {"char1 snorm border unnormalized", 's', 8, 1, 7, 3, 1, 0, Storage::kArray, 1,
     {Wrap::kClampToBorder, Wrap::kClampToBorder, Wrap::kRepeat}, true, 'n', true, false, false,
     0, 0, {kTex2D}, kFloat1},
    {"ushort4 pitched bilinear", 'u', 16, 4, 10, 6, 1, 0, Storage::kPitched, 1,
     {Wrap::kClampToEdge, Wrap::kMirror, Wrap::kRepeat}, true, 'n', true, false, true, 0, 0,
     {kTex2D}, kFloat4},
    {"short2 point element", 's', 16, 2, 5, 5, 1, 0, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kRepeat}, false, 'n', false, false, false, 0,
     0, {kTex2D}, kShort2},
    {"half4 bilinear wrap", 'h', 16, 4, 8, 3, 1, 0, Storage::kArray, 1,
     {Wrap::kRepeat, Wrap::kRepeat, Wrap::kRepeat}, true, 'n', false, false, true, 0, 0,
     {kTex2D}, kFloat4},
    {"float1 1D linear wrap", 'f', 32, 1, 17, 1, 1, 0, Storage::kArray, 1,
     {Wrap::kRepeat, Wrap::kRepeat, Wrap::kRepeat}, true, 'n', false, false, true, 0, 0,
     {kTex1D, kTex1DLod}, kFloat1},
    {"float2 3D trilinear", 'f', 32, 2, 5, 4, 3, 0, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kMirror, Wrap::kRepeat}, true, 'n', false, false, true, 0, 0,
     {kTex3D, kTex3DLod}, kFloat4},
    {"float4 2D layered", 'f', 32, 4, 4, 4, 3, cudaArrayLayered, Storage::kArray, 1,
     {Wrap::kRepeat, Wrap::kClampToEdge, Wrap::kRepeat}, true, 'n', false, false, true, 0, 0,
     {kTex2DLayered}, kFloat4},
    {"uchar1 1D layered", 'u', 8, 1, 8, 1, 4, cudaArrayLayered, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kRepeat}, false, 'n', true, false, true, 0,
     0, {kTex1DLayered}, kFloat1},
    {"float1 cubemap", 'f', 32, 1, 4, 4, 6, cudaArrayCubemap, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kClampToEdge}, true, 'n', false, false, true,
     0, 0, {kTexCubemap}, kFloat1},
    {"rgba8 layered cubemap", 'u', 8, 4, 3, 3, 12, cudaArrayCubemap | cudaArrayLayered,
     Storage::kArray, 1, {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kClampToEdge}, false,
     'n', false, false, true, 0, 0, {kTexCubemapLayered}, kUchar4},
    {"uint linear memory fetch", 'u', 32, 1, 37, 1, 1, 0, Storage::kLinear, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kClampToEdge}, false, 'n', false, false,
     false, 0, 0, {kTex1DFetch}, kUint4},
    {"int4 point element", 's', 32, 4, 4, 3, 1, 0, Storage::kArray, 1,
     {Wrap::kClampToEdge, Wrap::kClampToEdge, Wrap::kRepeat}, false, 'n', false, false, false, 0,
     0, {kTex2D}, kInt4},
    {"float4 mipmapped trilinear", 'f', 32, 4, 16, 8, 1, 0, Storage::kMipmapped, 5,
     {Wrap::kClampToEdge, Wrap::kRepeat, Wrap::kRepeat}, true, 'l', false, false, true, 0.25f, 4,
     {kTex2DLod, kTex2D, kTex2DGrad}, kFloat4},
    {"rgba8 mipmapped nearest level", 'u', 8, 4, 8, 8, 1, 0, Storage::kMipmapped, 4,
     {Wrap::kRepeat, Wrap::kRepeat, Wrap::kRepeat}, true, 'p', true, false, true, 0, 3,
     {kTex2DLod}, kFloat4},
};
// clang-format on

constexpr unsigned kProbesPerOp = 40;

}  // namespace

int main() {
  CHECK_CUDA(cudaFree(nullptr));
  CHECK_OPTIX(optixInit());
  OptixDeviceContextOptions context_options = {};
  OptixDeviceContext context = nullptr;
  CHECK_OPTIX(optixDeviceContextCreate(nullptr, &context_options, &context));

  Random r{20261130};
  std::vector<Made> made(sizeof kCases / sizeof kCases[0]);
  std::vector<Probe> probes;
  std::vector<reference::Lookup> lookups;
  std::vector<size_t> case_of;
  for (size_t i = 0; i < made.size(); ++i) {
    const Case& c = kCases[i];
    MakeTexture(c, r, &made[i]);
    for (unsigned op : c.ops) {
      for (unsigned k = 0; k < kProbesPerOp; ++k) {
        Probe p = {};
        p.texture = made[i].texture;
        p.op = op;
        p.result = c.result;
        p.x = Coordinate(c, c.w, k, r);
        p.y = Coordinate(c, c.h, (k + 3) % kProbesPerOp, r);
        p.z = Coordinate(c, c.d, (k + 5) % kProbesPerOp, r);
        if (op == kTexCubemap || op == kTexCubemapLayered) {
          p.x = r.Uniform(-1, 1);
          p.y = r.Uniform(-1, 1);
          p.z = r.Uniform(-1, 1);
        }
        if (op == kTex1DFetch) p.x = static_cast<float>(static_cast<int>(k) - 2);
        p.level = r.Uniform(-1.f, 5.f);
        p.layer = static_cast<int>(k % 7) - 1;  // -1 ... 5: past the last layer too
        p.comp = static_cast<int>(k % 4);
        p.ddx = make_float2(r.Uniform(-0.3f, 0.3f), r.Uniform(-0.3f, 0.3f));
        p.ddy = make_float2(r.Uniform(-0.3f, 0.3f), r.Uniform(-0.3f, 0.3f));
        probes.push_back(p);
        lookups.push_back({op,
                           c.result,
                           p.x,
                           p.y,
                           p.z,
                           p.level,
                           p.layer,
                           p.comp,
                           {p.ddx.x, p.ddx.y},
                           {p.ddy.x, p.ddy.y}});
        case_of.push_back(i);
      }
    }
  }

  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.numPayloadValues = 0;
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  const std::string input = TESSERA_PROBE_MODULE;  // a module's path
  char log[2048];
  size_t log_size = sizeof(log);
  OptixModule module = nullptr;
  CHECK_OPTIX(optixModuleCreate(context, &module_options, &pipeline_options, input.c_str(),
                                input.size(), log, &log_size, &module));
  OptixProgramGroupDesc desc = {};
  desc.kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
  desc.raygen.module = module;
  desc.raygen.entryFunctionName = "__raygen__probe";
  OptixProgramGroupOptions group_options = {};
  OptixProgramGroup group = nullptr;
  log_size = sizeof(log);
  CHECK_OPTIX(optixProgramGroupCreate(context, &desc, 1, &group_options, log, &log_size, &group));
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 1;
  OptixPipeline pipeline = nullptr;
  log_size = sizeof(log);
  CHECK_OPTIX(optixPipelineCreate(context, &pipeline_options, &link_options, &group, 1, log,
                                  &log_size, &pipeline));

  struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
    char header[OPTIX_SBT_RECORD_HEADER_SIZE];
  } record;
  CHECK_OPTIX(optixSbtRecordPackHeader(group, &record));
  void* d_record = nullptr;
  CHECK_CUDA(cudaMalloc(&d_record, sizeof record));
  CHECK_CUDA(cudaMemcpy(d_record, &record, sizeof record, cudaMemcpyHostToDevice));
  OptixShaderBindingTable sbt = {};
  sbt.raygenRecord = reinterpret_cast<CUdeviceptr>(d_record);

  Probe* d_probes = nullptr;
  uint4* d_out = nullptr;
  CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d_probes), probes.size() * sizeof(Probe)));
  CHECK_CUDA(
      cudaMemcpy(d_probes, probes.data(), probes.size() * sizeof(Probe), cudaMemcpyHostToDevice));
  CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d_out), probes.size() * sizeof(uint4)));
  CHECK_CUDA(cudaMemset(d_out, 0xff, probes.size() * sizeof(uint4)));
  Params params = {d_probes, static_cast<unsigned>(probes.size()), d_out};
  void* d_params = nullptr;
  CHECK_CUDA(cudaMalloc(&d_params, sizeof params));
  CHECK_CUDA(cudaMemcpy(d_params, &params, sizeof params, cudaMemcpyHostToDevice));
  CHECK_OPTIX(optixLaunch(pipeline, nullptr, reinterpret_cast<CUdeviceptr>(d_params), sizeof params,
                          &sbt, static_cast<unsigned>(probes.size()), 1, 1));
  CHECK_CUDA(cudaDeviceSynchronize());
  std::vector<uint4> out(probes.size());
  CHECK_CUDA(cudaMemcpy(out.data(), d_out, out.size() * sizeof(uint4), cudaMemcpyDeviceToHost));

  size_t mismatches = 0, nonzero = 0;
  for (size_t i = 0; i < probes.size(); ++i) {
    unsigned want[4];
    reference::Sample(made[case_of[i]].sampler, lookups[i], want);
    const unsigned got[4] = {out[i].x, out[i].y, out[i].z, out[i].w};
    if (got[0] | got[1] | got[2] | got[3]) ++nonzero;
    if (std::memcmp(got, want, sizeof got) != 0) {
      if (++mismatches <= 20) {
        std::fprintf(stderr,
                     "%s: op %u at (%g, %g, %g) level %g layer %d: got %08x %08x %08x %08x, the "
                     "OptiX 3 sampler %08x %08x %08x %08x\n",
                     kCases[case_of[i]].name, probes[i].op, probes[i].x, probes[i].y, probes[i].z,
                     probes[i].level, probes[i].layer, got[0], got[1], got[2], got[3], want[0],
                     want[1], want[2], want[3]);
      }
    }
  }
  // Mostly zero results would mean the textures were never reached.
  std::printf("%zu lookups on %zu textures, %zu nonzero, %zu differ from the OptiX 3 sampler\n",
              probes.size(), made.size(), nonzero, mismatches);
  for (Made& m : made) CHECK_CUDA(cudaDestroyTextureObject(m.texture));
  CHECK_OPTIX(optixPipelineDestroy(pipeline));
  CHECK_OPTIX(optixProgramGroupDestroy(group));
  CHECK_OPTIX(optixModuleDestroy(module));
  CHECK_OPTIX(optixDeviceContextDestroy(context));
  return mismatches == 0 && nonzero * 4 >= probes.size() * 3 ? 0 : 1;
}
