// tessera-optix7-accuracy: the OptiX 7 layer's speed/accuracy settings (issue 26;
// docs/optix7_engine.md "Speed and accuracy"), on whatever devices TESSERA_DEVICES names
// (tests/optix7_accuracy runs it on inproc and local:2).
//
//   leaks      closed meshes (an icosphere, a subdivided cube) shot from inside through every
//              vertex and edge midpoint, at offsets 0 to 1e7 and scales 1e-6 to 1e6, their
//              vertices baked or placed by an instance transform: misses counted in default,
//              robust and watertight mode; watertight (context flag or build flag) must have none.
//   shadows    a shadow ray from each hit of random rays from inside, outwards: from
//              origin + t * direction with tmin 1e-4 (printed), from tesseraOptixGetSpawnPoint,
//              and with TESSERA_ACCURACY_OFFSET_RAYS: those two must hit nothing.
//   update     OPTIX_BUILD_OPERATION_UPDATE of moved vertices gives the hits a build gives.
//   intervals  hits at exactly tmin and tmax count (OptiX's closed interval), just outside do not,
//              for triangles and intersection programs; NaN and infinite reported distances never
//              reach a program; invalid rays with exceptions off miss.
//   --bench    trace time per accuracy mode, build and update time (printed, not checked).
#include <cuda_runtime.h>
#include <optix.h>
#include <optix_function_table_definition.h>
#include <optix_stubs.h>
#include <tessera/optix7_ext.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "params.h"

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

int failures = 0;

void Require(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "FAILED: %s\n", what.c_str());
}

float3 F3(float x, float y, float z) { return float3{x, y, z}; }

// ---- Meshes
// --------------------------------------------------------------------------------------

struct Mesh {
  std::vector<float> vertices;  // 3 a vertex, around the origin, radius about 1
  std::vector<uint32_t> indices;
};

// An icosahedron subdivided `levels` times, its vertices on the unit sphere; closed (every edge
// shared by two triangles: midpoints are shared through a map).
Mesh Icosphere(int levels) {
  const float p = (1.f + std::sqrt(5.f)) / 2.f;
  std::vector<std::array<double, 3>> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                          {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                          {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  auto normalize = [](std::array<double, 3> a) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<double, 3>{a[0] / l, a[1] / l, a[2] / l};
  };
  for (auto& x : v) x = normalize(x);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      v.push_back(normalize({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      return mid[key] = static_cast<uint32_t>(v.size() - 1);
    };
    std::vector<uint32_t> next;
    for (size_t t = 0; t < f.size(); t += 3) {
      const uint32_t a = f[t], b = f[t + 1], c = f[t + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(next);
  }
  Mesh m;
  for (const auto& x : v) {
    for (double c : x) m.vertices.push_back(static_cast<float>(c));
  }
  m.indices = std::move(f);
  return m;
}

// The cube [-1, 1]^3, each face an n x n grid of squares (two triangles each); vertices on the
// cube's edges and corners shared between faces, so the mesh is closed.
Mesh Cube(int n) {
  Mesh m;
  std::map<std::array<int, 3>, uint32_t> ids;  // by grid coordinates 0..n
  auto id = [&](std::array<int, 3> g) {
    if (auto it = ids.find(g); it != ids.end()) return it->second;
    for (int c : g)
      m.vertices.push_back(-1.f + 2.f * static_cast<float>(c) / static_cast<float>(n));
    return ids[g] = static_cast<uint32_t>(m.vertices.size() / 3 - 1);
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side <= n; side += n) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::array<uint32_t, 4> q;
          for (int k = 0; k < 4; ++k) {
            std::array<int, 3> g;
            g[axis] = side;
            g[u] = i + (k == 1 || k == 2);
            g[w] = j + (k >= 2);
            q[k] = id(g);
          }
          m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
      }
    }
  }
  return m;
}

// ---- The OptiX side
// ------------------------------------------------------------------------------

struct Accel {
  CUdeviceptr buffer = 0;
  size_t size = 0;
  OptixTraversableHandle handle = 0;
  CUdeviceptr vertices = 0, indices = 0, aabbs = 0, instances = 0;
};

class Harness {
 public:
  Harness() {
    CHECK_CUDA(cudaFree(nullptr));
    CHECK_OPTIX(optixInit());
    OptixDeviceContextOptions context_options = {};
    CHECK_OPTIX(optixDeviceContextCreate(nullptr, &context_options, &context_));
    OptixPipelineCompileOptions pipeline_options = {};
    pipeline_options.pipelineLaunchParamsVariableName = "params";
    pipeline_options.numPayloadValues = 4;
    pipeline_options.exceptionFlags = OPTIX_EXCEPTION_FLAG_NONE;
    pipeline_options.traversableGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_ANY;
    const std::string input = TESSERA_ACCURACY_MODULE;  // a module's path
    char log[2048];
    size_t log_size = sizeof(log);
    OptixModuleCompileOptions module_options = {};
    CHECK_OPTIX(optixModuleCreate(context_, &module_options, &pipeline_options, input.c_str(),
                                  input.size(), log, &log_size, &module_));
    OptixProgramGroupDesc desc[4] = {};
    desc[0].kind = OPTIX_PROGRAM_GROUP_KIND_RAYGEN;
    desc[0].raygen.module = module_;
    desc[0].raygen.entryFunctionName = "__raygen__primary";
    desc[1].kind = OPTIX_PROGRAM_GROUP_KIND_MISS;
    desc[1].miss.module = module_;
    desc[1].miss.entryFunctionName = "__miss__none";
    desc[2].kind = OPTIX_PROGRAM_GROUP_KIND_HITGROUP;
    desc[2].hitgroup.moduleCH = module_;
    desc[2].hitgroup.entryFunctionNameCH = "__closesthit__record";
    desc[3] = desc[2];
    desc[3].hitgroup.moduleIS = module_;
    desc[3].hitgroup.entryFunctionNameIS = "__intersection__report";
    OptixProgramGroupOptions group_options = {};
    log_size = sizeof(log);
    CHECK_OPTIX(
        optixProgramGroupCreate(context_, desc, 4, &group_options, log, &log_size, groups_));
    OptixPipelineLinkOptions link_options = {};
    link_options.maxTraceDepth = 2;
    log_size = sizeof(log);
    CHECK_OPTIX(optixPipelineCreate(context_, &pipeline_options, &link_options, groups_, 4, log,
                                    &log_size, &pipeline_));
    struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
      char header[OPTIX_SBT_RECORD_HEADER_SIZE];
    } records[4];
    for (int i = 0; i < 4; ++i) CHECK_OPTIX(optixSbtRecordPackHeader(groups_[i], &records[i]));
    CUdeviceptr d = 0;
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d), sizeof records));
    CHECK_CUDA(
        cudaMemcpy(reinterpret_cast<void*>(d), records, sizeof records, cudaMemcpyHostToDevice));
    for (int custom = 0; custom < 2; ++custom) {
      OptixShaderBindingTable& sbt = sbt_[custom];
      sbt.raygenRecord = d;
      sbt.missRecordBase = d + sizeof(Record);
      sbt.missRecordStrideInBytes = sizeof(Record);
      sbt.missRecordCount = 1;
      sbt.hitgroupRecordBase = d + (custom ? 3 : 2) * sizeof(Record);
      sbt.hitgroupRecordStrideInBytes = sizeof(Record);
      sbt.hitgroupRecordCount = 1;
    }
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d_params_), sizeof(Params)));
  }

  void SetAccuracy(unsigned flags) {
    CHECK_OPTIX(tesseraOptixDeviceContextSetAccuracy(context_, flags));
  }

  // A triangle GAS of `m` with `flags`; `update` rebuilds `*accel` in place.
  void BuildTriangles(const std::vector<float>& vertices, const std::vector<uint32_t>& indices,
                      unsigned flags, Accel* accel, bool update = false) {
    if (!update) {
      CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&accel->vertices), vertices.size() * 4));
      CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&accel->indices), indices.size() * 4));
      CHECK_CUDA(cudaMemcpy(reinterpret_cast<void*>(accel->indices), indices.data(),
                            indices.size() * 4, cudaMemcpyHostToDevice));
    }
    CHECK_CUDA(cudaMemcpy(reinterpret_cast<void*>(accel->vertices), vertices.data(),
                          vertices.size() * 4, cudaMemcpyHostToDevice));
    const unsigned geometry_flags = OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT;
    OptixBuildInput input = {};
    input.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
    input.triangleArray.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
    input.triangleArray.numVertices = static_cast<unsigned>(vertices.size() / 3);
    input.triangleArray.vertexBuffers = &accel->vertices;
    input.triangleArray.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
    input.triangleArray.numIndexTriplets = static_cast<unsigned>(indices.size() / 3);
    input.triangleArray.indexBuffer = accel->indices;
    input.triangleArray.flags = &geometry_flags;
    input.triangleArray.numSbtRecords = 1;
    Build(input, flags, accel, update);
  }

  // A custom-primitive GAS of one box.
  void BuildBox(const OptixAabb& box, Accel* accel) {
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&accel->aabbs), sizeof box));
    CHECK_CUDA(cudaMemcpy(reinterpret_cast<void*>(accel->aabbs), &box, sizeof box,
                          cudaMemcpyHostToDevice));
    const unsigned geometry_flags = OPTIX_GEOMETRY_FLAG_DISABLE_ANYHIT;
    OptixBuildInput input = {};
    input.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
    input.customPrimitiveArray.aabbBuffers = &accel->aabbs;
    input.customPrimitiveArray.numPrimitives = 1;
    input.customPrimitiveArray.flags = &geometry_flags;
    input.customPrimitiveArray.numSbtRecords = 1;
    Build(input, OPTIX_BUILD_FLAG_NONE, accel, false);
  }

  // An IAS of one instance of `child`, transform `m` (3x4 row-major).
  void BuildInstance(const Accel& child, const float m[12], Accel* accel) {
    OptixInstance inst = {};
    std::memcpy(inst.transform, m, sizeof(inst.transform));
    inst.visibilityMask = 255;
    inst.traversableHandle = child.handle;
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&accel->instances), sizeof inst));
    CHECK_CUDA(cudaMemcpy(reinterpret_cast<void*>(accel->instances), &inst, sizeof inst,
                          cudaMemcpyHostToDevice));
    OptixBuildInput input = {};
    input.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
    input.instanceArray.instances = accel->instances;
    input.instanceArray.numInstances = 1;
    Build(input, OPTIX_BUILD_FLAG_NONE, accel, false);
  }

  void Free(Accel* a) {
    for (CUdeviceptr p : {a->buffer, a->vertices, a->indices, a->aabbs, a->instances}) {
      if (p != 0) CHECK_CUDA(cudaFree(reinterpret_cast<void*>(p)));
    }
    *a = Accel{};
  }

  // One launch of `rays`; the results, and the launch's time in seconds.
  std::vector<TestResult> Run(OptixTraversableHandle handle, const std::vector<TestRay>& rays,
                              unsigned shadow_mode = kNoShadow, bool custom = false,
                              double* seconds = nullptr) {
    TestRay* d_rays = nullptr;
    TestResult* d_results = nullptr;
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d_rays), rays.size() * sizeof(TestRay)));
    CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&d_results), rays.size() * sizeof(TestResult)));
    CHECK_CUDA(
        cudaMemcpy(d_rays, rays.data(), rays.size() * sizeof(TestRay), cudaMemcpyHostToDevice));
    Params p = {};
    p.handle = handle;
    p.rays = d_rays;
    p.results = d_results;
    p.count = static_cast<unsigned>(rays.size());
    p.shadow_mode = shadow_mode;
    p.scene_epsilon = 1e-4f;
    CHECK_CUDA(cudaMemcpy(d_params_, &p, sizeof p, cudaMemcpyHostToDevice));
    const auto start = std::chrono::steady_clock::now();
    CHECK_OPTIX(optixLaunch(pipeline_, nullptr, reinterpret_cast<CUdeviceptr>(d_params_), sizeof p,
                            &sbt_[custom ? 1 : 0], p.count, 1, 1));
    CHECK_CUDA(cudaDeviceSynchronize());
    if (seconds != nullptr) {
      *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    std::vector<TestResult> out(rays.size());
    CHECK_CUDA(
        cudaMemcpy(out.data(), d_results, out.size() * sizeof(TestResult), cudaMemcpyDeviceToHost));
    CHECK_CUDA(cudaFree(d_rays));
    CHECK_CUDA(cudaFree(d_results));
    return out;
  }

 private:
  void Build(const OptixBuildInput& input, unsigned flags, Accel* accel, bool update) {
    OptixAccelBuildOptions options = {};
    options.buildFlags = flags;
    options.operation = update ? OPTIX_BUILD_OPERATION_UPDATE : OPTIX_BUILD_OPERATION_BUILD;
    OptixAccelBufferSizes sizes;
    CHECK_OPTIX(optixAccelComputeMemoryUsage(context_, &options, &input, 1, &sizes));
    void* temp = nullptr;
    CHECK_CUDA(cudaMalloc(&temp, std::max(sizes.tempSizeInBytes, sizes.tempUpdateSizeInBytes)));
    if (!update) {
      CHECK_CUDA(cudaMalloc(reinterpret_cast<void**>(&accel->buffer), sizes.outputSizeInBytes));
      accel->size = sizes.outputSizeInBytes;
    }
    CHECK_OPTIX(optixAccelBuild(context_, nullptr, &options, &input, 1,
                                reinterpret_cast<CUdeviceptr>(temp),
                                std::max(sizes.tempSizeInBytes, sizes.tempUpdateSizeInBytes),
                                accel->buffer, accel->size, &accel->handle, nullptr, 0));
    CHECK_CUDA(cudaFree(temp));
  }

  OptixDeviceContext context_ = nullptr;
  OptixModule module_ = nullptr;
  OptixProgramGroup groups_[4] = {};
  OptixPipeline pipeline_ = nullptr;
  OptixShaderBindingTable sbt_[2] = {};
  void* d_params_ = nullptr;
};

// ---- Scenes of the leak and shadow tests
// ----------------------------------------------------------

// Where a mesh is: its centre and radius, baked into the vertices or an instance's transform.
struct Placement {
  double offset;  // the centre is offset * (1, 0.5, -0.25)
  double scale;
  bool instanced;
};

std::string Name(const char* mesh, const Placement& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s at %g, scale %g, %s", mesh, p.offset, p.scale,
                p.instanced ? "instanced" : "baked");
  return buf;
}

float3 Centre(const Placement& p) {
  return F3(static_cast<float>(p.offset), static_cast<float>(p.offset * 0.5),
            static_cast<float>(-p.offset * 0.25));
}

// Object-space point `v` in world space, as the scene has it (float arithmetic, as the host of
// a real application would bake it; Embree's instances apply the same matrix).
float3 Place(const Placement& p, const float* v) {
  const float3 c = Centre(p);
  const float s = static_cast<float>(p.scale);
  return F3(s * v[0] + c.x, s * v[1] + c.y, s * v[2] + c.z);
}

// The acceleration of mesh `m` placed by `p`, built with `flags`; `gas` holds the GAS of an
// instanced placement.
OptixTraversableHandle Scene(Harness& h, const Mesh& m, const Placement& p, unsigned flags,
                             Accel* gas, Accel* ias) {
  if (!p.instanced) {
    std::vector<float> baked;
    for (size_t k = 0; k < m.vertices.size(); k += 3) {
      const float3 w = Place(p, &m.vertices[k]);
      baked.insert(baked.end(), {w.x, w.y, w.z});
    }
    h.BuildTriangles(baked, m.indices, flags, gas);
    return gas->handle;
  }
  h.BuildTriangles(m.vertices, m.indices, flags, gas);
  const float3 c = Centre(p);
  const float s = static_cast<float>(p.scale);
  const float t[12] = {s, 0, 0, c.x, 0, s, 0, c.y, 0, 0, s, c.z};
  h.BuildInstance(*gas, t, ias);
  return ias->handle;
}

TestRay Toward(const float3& from, const float3& to) {
  TestRay r = {};
  r.origin = from;
  r.direction = F3(to.x - from.x, to.y - from.y, to.z - from.z);
  r.tmin = 0.f;
  r.tmax = std::numeric_limits<float>::infinity();
  return r;
}

// Rays from the centre through every vertex and every edge's midpoint.
std::vector<TestRay> VertexAndEdgeRays(const Mesh& m, const Placement& p) {
  std::vector<TestRay> rays;
  const float3 c = Centre(p);
  for (size_t k = 0; k < m.vertices.size(); k += 3)
    rays.push_back(Toward(c, Place(p, &m.vertices[k])));
  std::map<std::pair<uint32_t, uint32_t>, bool> edges;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = m.indices[t + e], b = m.indices[t + (e + 1) % 3];
      if (!edges.emplace(std::make_pair(std::min(a, b), std::max(a, b)), true).second) continue;
      const float3 pa = Place(p, &m.vertices[3 * a]), pb = Place(p, &m.vertices[3 * b]);
      rays.push_back(
          Toward(c, F3((pa.x + pb.x) * 0.5f, (pa.y + pb.y) * 0.5f, (pa.z + pb.z) * 0.5f)));
    }
  }
  return rays;
}

// `n` rays from the centre in directions spread over the sphere (a fixed sequence).
std::vector<TestRay> RandomRays(const Placement& p, unsigned n) {
  std::vector<TestRay> rays;
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const float3 c = Centre(p);
  for (unsigned i = 0; i < n; ++i) {
    const double z = 2 * next() - 1, phi = 2 * M_PI * next(), r = std::sqrt(1 - z * z);
    TestRay ray = {};
    ray.origin = c;
    ray.direction = F3(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                       static_cast<float>(z));
    ray.tmax = std::numeric_limits<float>::infinity();
    rays.push_back(ray);
  }
  return rays;
}

unsigned Misses(const std::vector<TestResult>& r) {
  unsigned n = 0;
  for (const TestResult& x : r) n += x.hit == 0;
  return n;
}

unsigned ShadowHits(const std::vector<TestResult>& r) {
  unsigned n = 0;
  for (const TestResult& x : r) n += x.hit == 1 && x.shadow == 1;
  return n;
}

// Offsets 0 to 1e7 of the mesh's radius at radii 1e-6, 1 and 1e6 (at 1e7 radii a mesh's vertices
// round to a grid of a tenth of its radius: the mesh is still closed, and still must not leak).
std::vector<Placement> Placements() {
  std::vector<Placement> out;
  for (bool instanced : {false, true}) {
    for (double scale : {1e-6, 1.0, 1e6}) {
      for (double radii : {0.0, 1e3, 1e5, 1e7})
        out.push_back(Placement{radii * scale, scale, instanced});
    }
  }
  return out;
}

struct NamedMesh {
  const char* name;
  Mesh mesh;
};

void TestLeaks(Harness& h, const std::vector<NamedMesh>& meshes) {
  std::printf("leaks (misses of rays through vertices and edge midpoints from inside):\n");
  std::printf("  %-46s %6s %8s %8s %10s %8s\n", "scene", "rays", "default", "robust", "watertight",
              "wt-flag");
  for (const NamedMesh& nm : meshes) {
    for (const Placement& p : Placements()) {
      const std::vector<TestRay> rays = VertexAndEdgeRays(nm.mesh, p);
      unsigned counts[4];
      const unsigned modes[4] = {0, TESSERA_ACCURACY_ROBUST, TESSERA_ACCURACY_WATERTIGHT, 0};
      for (int m = 0; m < 4; ++m) {
        h.SetAccuracy(modes[m]);
        Accel gas, ias;
        const unsigned flags = m == 3 ? TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT : 0;
        const OptixTraversableHandle handle = Scene(h, nm.mesh, p, flags, &gas, &ias);
        counts[m] = Misses(h.Run(handle, rays));
        h.Free(&gas);
        h.Free(&ias);
      }
      h.SetAccuracy(0);
      std::printf("  %-46s %6zu %8u %8u %10u %8u\n", Name(nm.name, p).c_str(), rays.size(),
                  counts[0], counts[1], counts[2], counts[3]);
      Require(counts[2] == 0, Name(nm.name, p) + ": watertight mode leaks");
      Require(counts[3] == 0, Name(nm.name, p) + ": TESSERA_OPTIX_BUILD_FLAG_WATERTIGHT leaks");
    }
  }
}

void TestShadows(Harness& h, const std::vector<NamedMesh>& meshes) {
  std::printf("self-intersections of shadow rays leaving hits of 2000 rays from inside:\n");
  std::printf("  %-46s %9s %11s %11s %11s\n", "scene", "eps 1e-4", "spawn point", "offset rays",
              "spawn (wt)");
  for (const NamedMesh& nm : meshes) {
    for (const Placement& p : Placements()) {
      const std::vector<TestRay> rays = RandomRays(p, 2000);
      Accel gas, ias;
      const OptixTraversableHandle handle = Scene(h, nm.mesh, p, 0, &gas, &ias);
      const std::vector<TestResult> plain = h.Run(handle, rays, kHitPoint);
      const std::vector<TestResult> spawn = h.Run(handle, rays, kSpawnPoint);
      h.SetAccuracy(TESSERA_ACCURACY_OFFSET_RAYS);
      const std::vector<TestResult> offset = h.Run(handle, rays, kHitPoint);
      h.SetAccuracy(TESSERA_ACCURACY_WATERTIGHT);
      const std::vector<TestResult> watertight = h.Run(handle, rays, kSpawnPoint);
      h.SetAccuracy(0);
      h.Free(&gas);
      h.Free(&ias);
      std::printf("  %-46s %9u %11u %11u %11u\n", Name(nm.name, p).c_str(), ShadowHits(plain),
                  ShadowHits(spawn), ShadowHits(offset), ShadowHits(watertight));
      Require(ShadowHits(spawn) == 0, Name(nm.name, p) + ": shadow rays from the spawn point hit");
      Require(ShadowHits(offset) == 0,
              Name(nm.name, p) + ": shadow rays with TESSERA_ACCURACY_OFFSET_RAYS hit");
      Require(ShadowHits(watertight) == 0,
              Name(nm.name, p) + ": watertight shadow rays from the spawn point hit");
      Require(Misses(watertight) == 0, Name(nm.name, p) + ": watertight random rays leak");
    }
  }
}

// Vertices of `m` moved and bent: what an animation's next frame might do.
std::vector<float> Moved(const Mesh& m) {
  std::vector<float> v = m.vertices;
  for (size_t k = 0; k < v.size(); k += 3) {
    const float bend = 1.f + 0.1f * std::sin(5.f * v[k]);
    v[k] = 1.5f * v[k] * bend + 0.1f;
    v[k + 1] = 1.5f * v[k + 1] * bend + 0.05f;
    v[k + 2] = 1.5f * v[k + 2] * bend;
  }
  return v;
}

void TestUpdate(Harness& h, const Mesh& m) {
  const Placement origin{0, 1, false};
  const std::vector<TestRay> rays = RandomRays(origin, 4000);
  Accel updated, rebuilt;
  h.BuildTriangles(m.vertices, m.indices, OPTIX_BUILD_FLAG_ALLOW_UPDATE, &updated);
  const std::vector<TestResult> before = h.Run(updated.handle, rays);
  const std::vector<float> moved = Moved(m);
  h.BuildTriangles(moved, m.indices, OPTIX_BUILD_FLAG_ALLOW_UPDATE, &updated, /*update=*/true);
  const std::vector<TestResult> after = h.Run(updated.handle, rays);
  h.BuildTriangles(moved, m.indices, OPTIX_BUILD_FLAG_NONE, &rebuilt);
  const std::vector<TestResult> want = h.Run(rebuilt.handle, rays);
  unsigned differ = 0, moved_hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    differ +=
        after[i].hit != want[i].hit || after[i].prim != want[i].prim || after[i].t != want[i].t;
    moved_hits += after[i].t != before[i].t;
  }
  std::printf(
      "update: %zu rays, %u differ from a build of the moved vertices, %u moved, %u leak "
      "(as many as the build's: %u)\n",
      rays.size(), differ, moved_hits, Misses(after), Misses(want));
  Require(differ == 0, "update: hits differ from a build of the same vertices");
  Require(moved_hits > rays.size() / 2, "update: the hits did not move with the vertices");
  h.Free(&updated);
  h.Free(&rebuilt);
}

TestRay Ray(float3 o, float3 d, float tmin, float tmax, float report = 0.f) {
  TestRay r;
  r.origin = o;
  r.direction = d;
  r.tmin = tmin;
  r.tmax = tmax;
  r.report = report;
  return r;
}

void TestIntervals(Harness& h) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float above = std::nextafter(1.f, 2.f), below = std::nextafter(1.f, 0.f);
  // Two triangles at z = 1 over [-1, 1]^2; a ray along +z meets them at t = 1 exactly.
  Accel quad;
  h.BuildTriangles({-1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1}, {0, 1, 2, 0, 2, 3}, 0, &quad);
  const float3 o = F3(0.25f, 0.375f, 0.f), d = F3(0.f, 0.f, 1.f);
  struct Case {
    const char* what;
    TestRay ray;
    unsigned hit;
  };
  const std::vector<Case> triangles = {
      {"[0, inf]", Ray(o, d, 0.f, inf), 1},
      {"tmin = t", Ray(o, d, 1.f, inf), 1},
      {"tmax = t", Ray(o, d, 0.f, 1.f), 1},
      {"tmin = tmax = t", Ray(o, d, 1.f, 1.f), 1},
      {"tmin just past t", Ray(o, d, above, inf), 0},
      {"tmax just before t", Ray(o, d, 0.f, below), 0},
      {"tmin > tmax", Ray(o, d, 2.f, 0.5f), 0},
      // Invalid rays, exceptions off: they miss.
      {"NaN origin", Ray(F3(nan, 0.375f, 0.f), d, 0.f, inf), 0},
      {"infinite origin", Ray(F3(0.25f, -inf, 0.f), d, 0.f, inf), 0},
      {"NaN direction", Ray(o, F3(0.f, nan, 1.f), 0.f, inf), 0},
      {"infinite direction", Ray(o, F3(0.f, 0.f, inf), 0.f, inf), 0},
      {"negative tmin", Ray(o, d, -1.f, inf), 0},
      {"infinite tmin", Ray(o, d, inf, inf), 0},
      {"NaN tmin", Ray(o, d, nan, inf), 0},
      {"NaN tmax", Ray(o, d, 0.f, nan), 0},
  };
  std::vector<TestRay> rays;
  for (const Case& c : triangles) rays.push_back(c.ray);
  std::vector<TestResult> got = h.Run(quad.handle, rays);
  Require(got[0].t == 1.f, "intervals: the quad is not hit at t = 1 exactly");
  for (size_t i = 0; i < triangles.size(); ++i) {
    Require(got[i].hit == triangles[i].hit,
            std::string("intervals, triangles: ") + triangles[i].what +
                (triangles[i].hit ? " should hit" : " should miss"));
  }
  // An intersection program reporting whatever distance the ray names, on a box around the ray.
  Accel box;
  h.BuildBox(OptixAabb{-1, -1, -1, 1, 1, 1}, &box);
  const float3 bo = F3(0.f, 0.f, -5.f);
  const std::vector<Case> custom = {
      {"report = tmin", Ray(bo, d, 1.f, 4.f, 1.f), 1},
      {"report = tmax", Ray(bo, d, 1.f, 4.f, 4.f), 1},
      {"report inside", Ray(bo, d, 1.f, 4.f, 2.5f), 1},
      {"report below tmin", Ray(bo, d, 1.f, 4.f, below), 0},
      {"report past tmax", Ray(bo, d, 1.f, 4.f, std::nextafter(4.f, 5.f)), 0},
      {"report NaN", Ray(bo, d, 0.f, inf, nan), 0},
      {"report +inf, tmax inf", Ray(bo, d, 0.f, inf, inf), 0},
      {"report -inf", Ray(bo, d, 0.f, inf, -inf), 0},
  };
  rays.clear();
  for (const Case& c : custom) rays.push_back(c.ray);
  got = h.Run(box.handle, rays, kNoShadow, /*custom=*/true);
  for (size_t i = 0; i < custom.size(); ++i) {
    Require(got[i].hit == custom[i].hit, std::string("intervals, custom primitives: ") +
                                             custom[i].what +
                                             (custom[i].hit ? " should hit" : " should miss"));
    if (got[i].hit) {
      Require(got[i].t == custom[i].ray.report,
              std::string("intervals, custom primitives: ") + custom[i].what + ": wrong t");
    }
  }
  h.Free(&quad);
  h.Free(&box);
}

// Trace time per accuracy mode, and build against update time, end to end (launch times: the
// first launch after a build builds the device's scene).
void Bench(Harness& h) {
  const Mesh m = Icosphere(7);  // 327,680 triangles
  const Placement origin{0, 1, false};
  const std::vector<TestRay> rays = RandomRays(origin, 1000000);
  std::printf("bench: %zu triangles, %zu rays from inside (launch seconds, best of 5)\n",
              m.indices.size() / 3, rays.size());
  const std::pair<const char*, unsigned> modes[] = {
      {"default", 0},
      {"robust", TESSERA_ACCURACY_ROBUST},
      {"watertight", TESSERA_ACCURACY_WATERTIGHT},
      {"compact", TESSERA_ACCURACY_COMPACT},
      {"offset rays (shadow rays)", TESSERA_ACCURACY_OFFSET_RAYS},
  };
  for (const auto& [name, flags] : modes) {
    for (unsigned shadow : {kNoShadow, kHitPoint}) {
      if (flags == TESSERA_ACCURACY_OFFSET_RAYS && shadow == kNoShadow) continue;
      h.SetAccuracy(flags);
      Accel gas;
      h.BuildTriangles(m.vertices, m.indices, OPTIX_BUILD_FLAG_PREFER_FAST_TRACE, &gas);
      double build_and_trace = 0, best = 1e30;
      h.Run(gas.handle, rays, shadow, false, &build_and_trace);
      for (int i = 0; i < 5; ++i) {
        double s = 0;
        h.Run(gas.handle, rays, shadow, false, &s);
        best = std::min(best, s);
      }
      std::printf("  %-28s %-14s first launch %.3f s, trace %.3f s\n", name,
                  shadow ? "+ shadow rays" : "primary only", build_and_trace, best);
      h.Free(&gas);
    }
  }
  h.SetAccuracy(0);
  for (unsigned quality : std::vector<unsigned>{OPTIX_BUILD_FLAG_PREFER_FAST_BUILD, 0u,
                                                OPTIX_BUILD_FLAG_PREFER_FAST_TRACE}) {
    Accel gas;
    h.BuildTriangles(m.vertices, m.indices, quality, &gas);
    double first = 0, best = 1e30;
    h.Run(gas.handle, rays, kNoShadow, false, &first);
    for (int i = 0; i < 5; ++i) {
      double s = 0;
      h.Run(gas.handle, rays, kNoShadow, false, &s);
      best = std::min(best, s);
    }
    std::printf("  quality %-20s first launch %.3f s, trace %.3f s\n",
                quality == OPTIX_BUILD_FLAG_PREFER_FAST_BUILD ? "PREFER_FAST_BUILD"
                : quality                                     ? "PREFER_FAST_TRACE"
                                                              : "neither",
                first, best);
    h.Free(&gas);
  }
  // A few rays, so that the launch time is the scene's: ALLOW_UPDATE, then UPDATE of moved
  // vertices, against a build of the moved vertices.
  const std::vector<TestRay> few = RandomRays(origin, 16);
  const std::vector<float> moved = Moved(m);
  Accel updated, rebuilt;
  double t_build = 0, t_update = 0, t_rebuild = 0, t_empty = 0;
  h.BuildTriangles(m.vertices, m.indices, OPTIX_BUILD_FLAG_ALLOW_UPDATE, &updated);
  h.Run(updated.handle, few, kNoShadow, false, &t_build);
  h.Run(updated.handle, few, kNoShadow, false, &t_empty);
  h.BuildTriangles(moved, m.indices, OPTIX_BUILD_FLAG_ALLOW_UPDATE, &updated, true);
  h.Run(updated.handle, few, kNoShadow, false, &t_update);
  h.BuildTriangles(moved, m.indices, OPTIX_BUILD_FLAG_NONE, &rebuilt);
  h.Run(rebuilt.handle, few, kNoShadow, false, &t_rebuild);
  std::printf(
      "  launch after: ALLOW_UPDATE build %.3f s, UPDATE %.3f s, build (no update) %.3f s,"
      " no change %.3f s\n",
      t_build, t_update, t_rebuild, t_empty);
  h.Free(&updated);
  h.Free(&rebuilt);
}

}  // namespace

int main(int argc, char** argv) {
  Harness h;
  if (argc == 2 && std::strcmp(argv[1], "--bench") == 0) {
    Bench(h);
    return 0;
  }
  const std::vector<NamedMesh> meshes = {{"icosphere (1280 triangles)", Icosphere(3)},
                                         {"cube (8x8 a face)", Cube(8)}};
  TestIntervals(h);
  TestLeaks(h, meshes);
  TestShadows(h, meshes);
  TestUpdate(h, Icosphere(4));
  if (failures != 0) std::fprintf(stderr, "%d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
