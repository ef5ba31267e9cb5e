#include "engine_fixture.h"

#include <stdlib.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "accel_build.h"
#include "host_device_memory.h"
#include "module.h"
#include "sbt_header.h"
#include "tessera/scheduler/module_hash.h"

namespace tessera::optix7_test {
namespace {

optix7::HostDeviceMemory& Memory() { return **optix7::HostDeviceMemory::Get(); }

TestModule* StoreModule(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  EXPECT_FALSE(bytes.str().empty()) << path;
  auto* m = new TestModule{scheduler::ModuleHash(bytes.str()), path};
  const absl::Status s = worker::ModuleCache::Get().Store(m->hash, bytes.str());
  EXPECT_TRUE(s.ok()) << s;
  return m;
}

v1::Optix7Entry Entry(const TestModule& m, const std::string& fn) {
  v1::Optix7Entry e;
  if (fn.empty()) return e;
  e.set_module_hash(m.hash);
  e.set_module_path(m.path);
  e.set_function(fn);
  return e;
}

struct alignas(OPTIX_SBT_RECORD_ALIGNMENT) Record {
  memory::SbtHeader header;
  RecordData data;
};
static_assert(sizeof(Record) == 48);

}  // namespace

TestModule* EngineTest::trace_module_ = nullptr;
TestModule* EngineTest::calls_module_ = nullptr;

float Result::real(unsigned index, unsigned k) const {
  const uint32_t w = word(index, k);
  float f;
  std::memcpy(&f, &w, sizeof(f));
  return f;
}

void EngineTest::SetUpTestSuite() {
  if (trace_module_ != nullptr) return;
  char dir[] = "/tmp/tessera_optix7_engine_test_XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  worker::ModuleCache::Get().SetDirectory(dir);
  trace_module_ = StoreModule(TESSERA_OPTIX7_TRACE_MODULE);
  calls_module_ = StoreModule(TESSERA_OPTIX7_CALLS_MODULE);
}

EngineTest::EngineTest()
    : device_(rtcNewDevice(nullptr)), engine_(std::make_unique<worker::Optix7Engine>(device_)) {}

EngineTest::~EngineTest() {
  engine_.reset();
  rtcReleaseDevice(device_);
  for (CUdeviceptr p : buffers_) cudaFree(reinterpret_cast<void*>(p));
}

CUdeviceptr EngineTest::Alloc(size_t bytes) {
  void* p = nullptr;
  EXPECT_EQ(cudaMalloc(&p, bytes), cudaSuccess);
  const auto address = reinterpret_cast<CUdeviceptr>(p);
  buffers_.push_back(address);
  state_.allocations[address] = bytes;
  return address;
}

OptixBuildInput EngineTest::Triangles(const std::vector<float>& vertices,
                                      const std::vector<uint32_t>& indices, unsigned geometry_flags,
                                      unsigned primitive_index_offset,
                                      const std::vector<uint32_t>& sbt_index_offsets) {
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_TRIANGLES;
  OptixBuildInputTriangleArray& t = in.triangleArray;
  pointers_.push_back(Upload(vertices));
  t.vertexBuffers = &pointers_.back();
  t.numVertices = static_cast<unsigned>(vertices.size() / 3);
  t.vertexFormat = OPTIX_VERTEX_FORMAT_FLOAT3;
  t.indexBuffer = Upload(indices);
  t.numIndexTriplets = static_cast<unsigned>(indices.size() / 3);
  t.indexFormat = OPTIX_INDICES_FORMAT_UNSIGNED_INT3;
  t.primitiveIndexOffset = primitive_index_offset;
  unsigned records = 1;
  if (!sbt_index_offsets.empty()) {
    for (uint32_t o : sbt_index_offsets) records = std::max(records, o + 1);
    t.sbtIndexOffsetBuffer = Upload(sbt_index_offsets);
    t.sbtIndexOffsetSizeInBytes = 4;
  }
  flags_.emplace_back(records, geometry_flags);
  t.flags = flags_.back().data();
  t.numSbtRecords = records;
  return in;
}

OptixBuildInput EngineTest::Spheres(const std::vector<float4>& spheres) {
  std::vector<float> boxes;
  for (const float4& s : spheres) {
    boxes.insert(boxes.end(), {s.x - s.w, s.y - s.w, s.z - s.w, s.x + s.w, s.y + s.w, s.z + s.w});
  }
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_CUSTOM_PRIMITIVES;
  OptixBuildInputCustomPrimitiveArray& c = in.customPrimitiveArray;
  pointers_.push_back(Upload(boxes));
  c.aabbBuffers = &pointers_.back();
  c.numPrimitives = static_cast<unsigned>(spheres.size());
  flags_.emplace_back(1, 0u);
  c.flags = flags_.back().data();
  c.numSbtRecords = 1;
  return in;
}

OptixBuildInput EngineTest::Instances(const std::vector<OptixInstance>& instances) {
  OptixBuildInput in{};
  in.type = OPTIX_BUILD_INPUT_TYPE_INSTANCES;
  in.instanceArray.instances = Upload(instances);
  in.instanceArray.numInstances = static_cast<unsigned>(instances.size());
  return in;
}

OptixTraversableHandle EngineTest::Build(const std::vector<OptixBuildInput>& inputs,
                                         const OptixMotionOptions& motion) {
  OptixAccelBuildOptions options{};
  options.operation = OPTIX_BUILD_OPERATION_BUILD;
  options.motionOptions = motion;
  auto sizes = optix7::AccelBufferSizes(Memory(), options, inputs.data(),
                                        static_cast<unsigned>(inputs.size()));
  EXPECT_TRUE(sizes.ok()) << sizes.status();
  if (!sizes.ok()) return 0;
  const CUdeviceptr out = Alloc(sizes->outputSizeInBytes);
  auto handle =
      optix7::BuildAccel(Memory(), options, inputs.data(), static_cast<unsigned>(inputs.size()),
                         out, sizes->outputSizeInBytes);
  EXPECT_TRUE(handle.ok()) << handle.status();
  return handle.ok() ? *handle : 0;
}

uint64_t EngineTest::Group(uint32_t kind, const TestModule& m, const std::string& entry,
                           const std::string& continuation, const std::string& ch,
                           const std::string& ah, const std::string& is) {
  v1::Optix7ProgramGroup g;
  g.set_id(next_id_++);
  g.set_version(1);
  g.set_kind(kind);
  *g.mutable_entry() = Entry(m, entry);
  *g.mutable_continuation() = Entry(m, continuation);
  *g.mutable_closest_hit() = Entry(m, ch);
  *g.mutable_any_hit() = Entry(m, ah);
  *g.mutable_intersection() = Entry(m, is);
  state_.program_groups[g.id()] = g;
  return g.id();
}

OptixTraversableHandle EngineTest::Transform(const void* data, size_t bytes,
                                             OptixTransformType type) {
  const CUdeviceptr p = Alloc(bytes);  // cudaMalloc: 256-byte aligned
  EXPECT_EQ(cudaMemcpy(reinterpret_cast<void*>(p), data, bytes, cudaMemcpyHostToDevice),
            cudaSuccess);
  return p | type;
}

uint64_t EngineTest::Raygen(const TestModule& m, const std::string& fn) {
  return Group(OPTIX_PROGRAM_GROUP_KIND_RAYGEN, m, fn, "", "", "", "");
}
uint64_t EngineTest::Miss(const TestModule& m, const std::string& fn) {
  return Group(OPTIX_PROGRAM_GROUP_KIND_MISS, m, fn, "", "", "", "");
}
uint64_t EngineTest::Exception(const TestModule& m, const std::string& fn) {
  return Group(OPTIX_PROGRAM_GROUP_KIND_EXCEPTION, m, fn, "", "", "", "");
}
uint64_t EngineTest::HitGroup(const TestModule& m, const std::string& ch, const std::string& ah,
                              const std::string& is) {
  return Group(OPTIX_PROGRAM_GROUP_KIND_HITGROUP, m, "", "", ch, ah, is);
}
uint64_t EngineTest::Callables(const TestModule& m, const std::string& dc, const std::string& cc) {
  return Group(OPTIX_PROGRAM_GROUP_KIND_CALLABLES, m, dc, cc, "", "", "");
}

CUdeviceptr EngineTest::Records(const std::vector<uint64_t>& groups, uint32_t first_value) {
  if (groups.empty()) return 0;
  std::vector<Record> records(groups.size());
  for (size_t i = 0; i < groups.size(); ++i) {
    records[i].header = memory::SbtHeader{memory::kSbtHeaderMagic, groups[i], {0, 0}};
    records[i].data.value = first_value + static_cast<uint32_t>(i);
  }
  return Upload(records);
}

uint64_t EngineTest::Pipeline(unsigned max_trace_depth, unsigned exception_flags) {
  v1::Optix7Pipeline p;
  p.set_id(next_id_++);
  p.set_version(1);
  for (const auto& [id, g] : state_.program_groups) p.add_program_groups(id);
  p.set_params_name("params");
  p.set_max_trace_depth(max_trace_depth);
  p.set_exception_flags(exception_flags);
  p.set_num_payload_values(12);
  p.set_num_attribute_values(3);
  p.set_traversable_graph_flags(graph_flags_);
  p.set_primitive_type_flags(primitive_flags_);
  p.set_uses_motion_blur(motion_blur_);
  state_.pipelines[p.id()] = p;
  return p.id();
}

v1::Optix7Launch EngineTest::MakeLaunch(const Sbt& sbt, CUdeviceptr params) {
  v1::Optix7Launch l;
  l.set_params(params);
  l.set_params_size(sizeof(EngineParams));
  l.set_batched(batched_);
  l.set_raygen_record(Records({sbt.raygen}, Sbt::kRaygenValue));
  if (sbt.exception != 0) l.set_exception_record(Records({sbt.exception}, Sbt::kExceptionValue));
  l.set_miss_record_base(Records(sbt.miss, Sbt::kMissBase));
  l.set_miss_record_stride(sizeof(Record));
  l.set_miss_record_count(static_cast<uint32_t>(sbt.miss.size()));
  l.set_hitgroup_record_base(Records(sbt.hit, Sbt::kHitBase));
  l.set_hitgroup_record_stride(sizeof(Record));
  l.set_hitgroup_record_count(static_cast<uint32_t>(sbt.hit.size()));
  l.set_callables_record_base(Records(sbt.callables, Sbt::kCallablesBase));
  l.set_callables_record_stride(sizeof(Record));
  l.set_callables_record_count(static_cast<uint32_t>(sbt.callables.size()));
  return l;
}

Result EngineTest::Run(const Sbt& sbt, EngineParams params, unsigned width,
                       unsigned max_trace_depth, unsigned exception_flags, unsigned tile_width,
                       unsigned threads) {
  Result r;
  const size_t words = size_t{width} * ENGINE_WORDS;
  const CUdeviceptr out = Upload(std::vector<uint32_t>(words, 0));
  params.out = reinterpret_cast<unsigned int*>(out);
  v1::Optix7Launch launch = MakeLaunch(sbt, Upload(std::vector<EngineParams>{params}));
  launch.set_pipeline(Pipeline(max_trace_depth, exception_flags));
  r.prepared = engine_->Prepare(state_, launch, nullptr);
  if (!r.prepared.ok()) return r;
  const std::atomic<bool> cancel{false}, stop{false};
  const worker::Index3 dims{width, 1, 1};
  if (tile_width == 0) tile_width = width;
  std::vector<v1::TileResult> tiles((width + tile_width - 1) / tile_width);
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      for (size_t k = t; k < tiles.size(); k += threads) {
        const uint32_t x = static_cast<uint32_t>(k) * tile_width;
        EXPECT_TRUE(engine_->RunTile({x, 0, 0}, {tile_width, 1, 1}, dims, cancel, stop, tiles[k]));
      }
    });
  }
  for (std::thread& t : pool) t.join();
  for (const v1::TileResult& t : tiles) r.tile.MergeFrom(t);
  r.out.resize(words);
  EXPECT_EQ(
      cudaMemcpy(r.out.data(), reinterpret_cast<void*>(out), words * 4, cudaMemcpyDeviceToHost),
      cudaSuccess);
  return r;
}

EngineParams EngineTest::DownZ(float x0, float y) {
  EngineParams p{};
  p.origin = make_float3(x0, y, 1.f);
  p.step = make_float3(1.f, 0.f, 0.f);
  p.direction = make_float3(0.f, 0.f, -1.f);
  p.tmin = 0.f;
  p.tmax = 100.f;
  p.visibility_mask = 0xFF;
  p.sbt_stride = 1;
  return p;
}

}  // namespace tessera::optix7_test
