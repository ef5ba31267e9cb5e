// Lowering: what a launch ships to a device (StateDelta) and asks of it (LaunchRequest).
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "hash.h"
#include "launch_fixture.h"

namespace tessera::test {
namespace {

using Kind = v1::Object::KindCase;

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The wire's module hash of a file (api/src/hash.h).
std::string ModuleHashOf(const std::string& path) { return api::ModuleHash(FileBytes(path)); }

const v1::Variable* FindVariable(const google::protobuf::RepeatedPtrField<v1::Variable>& vars,
                                 const std::string& name) {
  for (const v1::Variable& v : vars) {
    if (v.name() == name) return &v;
  }
  return nullptr;
}

TEST_F(LaunchTest, FirstLaunchShipsEverything) {
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 1u);
  const v1::StateDelta& d = LastDelta();
  EXPECT_NE(d.session_id(), 0u);
  EXPECT_EQ(d.sequence(), 1u);
  EXPECT_TRUE(d.removed().empty());

  auto kinds = ObjectKinds(d);
  auto count = [&](Kind k) { return std::count(kinds.begin(), kinds.end(), k); };
  EXPECT_EQ(count(Kind::kProgram), 4);
  EXPECT_EQ(count(Kind::kBuffer), 2);
  EXPECT_EQ(count(Kind::kGeometry), 1);
  EXPECT_EQ(count(Kind::kMaterial), 1);
  EXPECT_EQ(count(Kind::kGeometryInstance), 1);
  EXPECT_EQ(count(Kind::kGeometryGroup), 1);
  EXPECT_EQ(count(Kind::kGroup), 1);
  EXPECT_EQ(count(Kind::kTransform), 1);
  EXPECT_EQ(count(Kind::kAcceleration), 2);
  EXPECT_EQ(kinds.size(), 14u);

  // Context state.
  const v1::ContextState& c = d.context();
  EXPECT_EQ(c.entry_point_count(), 1u);
  EXPECT_EQ(c.ray_type_count(), 1u);
  ASSERT_EQ(c.ray_generation_size(), 1);
  EXPECT_NE(c.ray_generation(0), 0u);
  EXPECT_EQ(c.exception(0), 0u);
  EXPECT_EQ(c.miss(0), 0u);
  EXPECT_EQ(c.stack_size(), 1024u);
  EXPECT_EQ(c.exception_mask(), 1u << (RT_EXCEPTION_STACK_OVERFLOW - 0x3EE));
  ASSERT_EQ(c.print_launch_index_size(), 3);
  EXPECT_EQ(c.print_launch_index(0), -1);
  const v1::Variable* scale = FindVariable(c.variables(), "scale");
  ASSERT_NE(scale, nullptr);
  EXPECT_EQ(scale->type(), static_cast<uint32_t>(RT_OBJECTTYPE_FLOAT));
  float value = 0;
  ASSERT_EQ(scale->data().size(), sizeof(float));
  std::memcpy(&value, scale->data().data(), sizeof(float));
  EXPECT_EQ(value, 2.5f);
  const v1::Variable* out = FindVariable(c.variables(), "output");
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(out->type(), static_cast<uint32_t>(RT_OBJECTTYPE_BUFFER));
  EXPECT_EQ(out->object_id(), Id(output));
  const v1::Variable* top = FindVariable(c.variables(), "top_object");
  ASSERT_NE(top, nullptr);
  EXPECT_EQ(top->type(), static_cast<uint32_t>(RT_OBJECTTYPE_GROUP));

  // Only the INPUT buffer's contents travel.
  ASSERT_EQ(d.chunks_size(), 1);
  EXPECT_EQ(d.chunks(0).buffer_id(), Id(input));
  EXPECT_EQ(d.chunks(0).offset(), 0u);
  ASSERT_EQ(d.chunks(0).data().size(), 16 * sizeof(int));
  EXPECT_EQ(reinterpret_cast<const int*>(d.chunks(0).data().data())[7], 7);
  EXPECT_NE(d.chunks(0).hash(), 0u);

  // Buffers, transforms and groups carry what devices need.
  for (const v1::Object& o : d.objects()) {
    if (o.has_buffer() && o.buffer().id() == Id(output)) {
      EXPECT_EQ(o.buffer().desc(), static_cast<uint32_t>(RT_BUFFER_OUTPUT));
      EXPECT_EQ(o.buffer().format(), static_cast<uint32_t>(RT_FORMAT_FLOAT));
      EXPECT_EQ(o.buffer().element_size(), 4u);
      ASSERT_EQ(o.buffer().dims_size(), 2);
      EXPECT_EQ(o.buffer().dims(0), 8u);
      EXPECT_EQ(o.buffer().dims(1), 4u);
    }
    if (o.has_transform()) {
      ASSERT_EQ(o.transform().matrix_size(), 16);
      ASSERT_EQ(o.transform().inverse_size(), 16);
      EXPECT_EQ(o.transform().matrix(0), 2.0f);
      EXPECT_EQ(o.transform().matrix(3), 1.0f);  // row-major: translation in column 3
      EXPECT_EQ(o.transform().inverse(0), 0.5f);
      EXPECT_EQ(o.transform().inverse(3), -0.5f);
      EXPECT_EQ(o.transform().child().type(), static_cast<uint32_t>(RT_OBJECTTYPE_GEOMETRY_GROUP));
    }
    if (o.has_group()) {
      ASSERT_EQ(o.group().children_size(), 1);
      EXPECT_EQ(o.group().children(0).type(), static_cast<uint32_t>(RT_OBJECTTYPE_TRANSFORM));
      EXPECT_NE(o.group().acceleration(), 0u);
    }
    if (o.has_program()) {
      EXPECT_EQ(o.program().module_path(), kTestModule);
      EXPECT_EQ(o.program().module_hash(), ModuleHashOf(kTestModule));
    }
    if (o.has_material()) {
      ASSERT_EQ(o.material().closest_hit_size(), 1);
      EXPECT_NE(o.material().closest_hit(0), 0u);
      EXPECT_EQ(o.material().any_hit(0), 0u);
    }
  }

  // The programs' one module travels whole, in order, under its hash.
  ASSERT_GE(d.modules_size(), 1);
  std::string module;
  for (const v1::ModuleChunk& m : d.modules()) {
    EXPECT_EQ(m.module_hash(), ModuleHashOf(kTestModule));
    EXPECT_EQ(m.offset(), module.size());
    EXPECT_LE(m.data().size(), size_t{4} << 20);
    module += m.data();
    EXPECT_EQ(m.total_size(), FileBytes(kTestModule).size());
  }
  EXPECT_EQ(module, FileBytes(kTestModule));

  // One tile covers the 8x4 grid.
  const v1::LaunchRequest& r = LastLaunch();
  EXPECT_EQ(r.session_id(), d.session_id());
  EXPECT_EQ(r.entry_point(), 0u);
  ASSERT_EQ(r.dims_size(), 2);
  EXPECT_EQ(r.dims(0), 8u);
  EXPECT_EQ(r.dims(1), 4u);
  ASSERT_EQ(r.tiles_size(), 1);
  EXPECT_EQ(r.tiles(0).size(0), 8u);
  EXPECT_EQ(r.tiles(0).size(1), 4u);
}

TEST_F(LaunchTest, UnchangedSecondLaunchShipsNothing) {
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  // Not even a delta: the device holds everything, so the launch costs it no round trip.
  EXPECT_EQ(records[0]->deltas.size(), 1u);
  EXPECT_GT(LastLaunch().launch_id(), records[0]->launches.front().launch_id());
  // A change to the context alone sends the context, with the next sequence number.
  ASSERT_EQ(rtContextSetStackSize(ctx, 2048), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 2u);
  const v1::StateDelta& d = LastDelta();
  EXPECT_EQ(d.sequence(), 2u);
  EXPECT_EQ(d.objects_size(), 0);
  EXPECT_EQ(d.chunks_size(), 0);
  EXPECT_EQ(d.context().stack_size(), 2048u);
}

// A sampler travels as its own object naming its buffer: a change of its modes ships the sampler
// alone, no chunk of its texels; mip levels travel in the buffer's chunks, the count with it.
TEST_F(LaunchTest, SamplerModesShipTheSamplerAlone) {
  ASSERT_EQ(rtBufferSetMipLevelCount(input, 3), RT_SUCCESS);  // 16, 8, 4 ints
  RTtexturesampler sampler = nullptr;
  ASSERT_EQ(rtTextureSamplerCreate(ctx, &sampler), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerSetBuffer(sampler, 0, 0, input), RT_SUCCESS);
  RTvariable v = nullptr;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "tex", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetObject(v, sampler), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  {
    const v1::StateDelta& d = LastDelta();
    const v1::TextureSampler* t = nullptr;
    for (const v1::Object& o : d.objects()) {
      if (o.has_texture_sampler()) t = &o.texture_sampler();
      if (o.has_buffer() && o.buffer().id() == Id(input)) {
        EXPECT_EQ(o.buffer().mip_level_count(), 3u);
      }
    }
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->buffer(), Id(input));
    ASSERT_EQ(t->wrap_size(), 3);
    EXPECT_EQ(t->wrap(0), static_cast<uint32_t>(RT_WRAP_REPEAT));
    EXPECT_EQ(t->mip_filter(), static_cast<uint32_t>(RT_FILTER_NONE));
    uint64_t texel_bytes = 0;
    for (const v1::BufferChunk& c : d.chunks()) {
      if (c.buffer_id() == Id(input)) texel_bytes += c.data().size();
    }
    EXPECT_EQ(texel_bytes, (16u + 8u + 4u) * sizeof(int));
  }
  ASSERT_EQ(rtTextureSamplerSetWrapMode(sampler, 1, RT_WRAP_MIRROR), RT_SUCCESS);
  ASSERT_EQ(rtTextureSamplerSetMaxAnisotropy(sampler, 4.f), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  const v1::StateDelta& d = LastDelta();
  ASSERT_EQ(d.objects_size(), 1);
  ASSERT_TRUE(d.objects(0).has_texture_sampler());
  EXPECT_EQ(d.objects(0).texture_sampler().wrap(1), static_cast<uint32_t>(RT_WRAP_MIRROR));
  EXPECT_EQ(d.objects(0).texture_sampler().max_anisotropy(), 4.f);
  EXPECT_EQ(d.chunks_size(), 0);
  // Destroyed, it leaves the device.
  ASSERT_EQ(rtContextRemoveVariable(ctx, v), RT_SUCCESS);
  const uint64_t id = d.objects(0).texture_sampler().id();
  ASSERT_EQ(rtTextureSamplerDestroy(sampler), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  const v1::StateDelta& last = LastDelta();
  EXPECT_NE(std::find(last.removed().begin(), last.removed().end(), id), last.removed().end());
}

// A material lists one program per ray type: after the count changes, devices get every material
// again, lowered with the new count (they used to keep the old lists, and a closest hit for a ray
// type added back never ran).
TEST_F(LaunchTest, RayTypeCountChangeRelowersMaterials) {
  ASSERT_EQ(rtContextSetRayTypeCount(ctx, 2), RT_SUCCESS);
  ASSERT_EQ(rtMaterialSetClosestHitProgram(material, 1, MakeProgram("closest_hit")), RT_SUCCESS);
  ASSERT_EQ(rtContextSetRayTypeCount(ctx, 1), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtContextSetRayTypeCount(ctx, 2), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  bool seen = false;
  for (const v1::Object& o : LastDelta().objects()) {
    if (!o.has_material()) continue;
    seen = true;
    ASSERT_EQ(o.material().closest_hit_size(), 2);
    EXPECT_NE(o.material().closest_hit(1), 0u);
  }
  EXPECT_TRUE(seen) << "the material did not travel again";
}

// Module bytes in a delta.
size_t ModuleBytes(const v1::StateDelta& d) {
  size_t bytes = 0;
  for (const v1::ModuleChunk& m : d.modules()) bytes += m.data().size();
  return bytes;
}

TEST_F(LaunchTest, ModuleBytesTravelOncePerDevice) {
  UseFakes(2);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  const size_t module_size = FileBytes(kTestModule).size();
  for (int device = 0; device < 2; ++device) {
    EXPECT_EQ(ModuleBytes(LastDelta(device)), module_size) << "device " << device;
  }
  // A new program from the same module: the program travels, the module does not.
  RTprogram miss = MakeProgram("miss");
  ASSERT_EQ(rtContextSetMissProgram(ctx, 0, miss), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  for (int device = 0; device < 2; ++device) {
    const v1::StateDelta& d = LastDelta(device);
    auto kinds = ObjectKinds(d);
    EXPECT_EQ(std::count(kinds.begin(), kinds.end(), Kind::kProgram), 1) << "device " << device;
    EXPECT_EQ(ModuleBytes(d), 0u) << "device " << device;
  }
}

TEST_F(LaunchTest, ModuleTravelsAgainAfterAFailedApply) {
  // A device that rejects the delta (and stays, unlike one that is lost).
  records[0]->apply_status = absl::InvalidArgumentError("delta rejected");
  EXPECT_NE(Launch(), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 1u);
  EXPECT_GT(ModuleBytes(LastDelta()), 0u);
  // The device never confirmed the module, so the next delta carries it again.
  records[0]->apply_status = absl::OkStatus();
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 2u);
  EXPECT_EQ(ModuleBytes(LastDelta()), FileBytes(kTestModule).size());
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(ModuleBytes(LastDelta()), 0u);
  EXPECT_EQ(records[0]->deltas.size(), 2u);  // nothing new: no delta at all
}

TEST_F(LaunchTest, ChangingOneVariableShipsOnlyItsScope) {
  RTvariable shininess;
  ASSERT_EQ(rtMaterialDeclareVariable(material, "shininess", &shininess), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet1f(shininess, 40.0f), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  const v1::StateDelta& d = LastDelta();
  ASSERT_EQ(d.objects_size(), 1);
  ASSERT_TRUE(d.objects(0).has_material());
  const v1::Variable* v = FindVariable(d.objects(0).material().variables(), "shininess");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->type(), static_cast<uint32_t>(RT_OBJECTTYPE_FLOAT));
  EXPECT_EQ(d.chunks_size(), 0);

  // A context variable travels in the context state; no object ships.
  ASSERT_EQ(rtVariableSet1f(ctx_var("scale"), 3.0f), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(LastDelta().objects_size(), 0);
  float value = 0;
  std::memcpy(&value, FindVariable(LastDelta().context().variables(), "scale")->data().data(), 4);
  EXPECT_EQ(value, 3.0f);
}

// Devices keep their own thread count (a local worker's share of the cores) unless the
// application sets CPU_NUM_THREADS.
TEST_F(LaunchTest, ThreadCountShipsOnlyWhenSet) {
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(LastDelta().context().num_threads(), 0u);
  int three = 3;
  ASSERT_EQ(rtContextSetAttribute(ctx, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS, sizeof(three), &three),
            RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(LastDelta().context().num_threads(), 3u);
}

TEST_F(LaunchTest, DeclaredButUnsetVariablesDoNotShip) {
  RTvariable v;
  ASSERT_EQ(rtContextDeclareVariable(ctx, "later", &v), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(FindVariable(LastDelta().context().variables(), "later"), nullptr);
}

TEST_F(LaunchTest, DestroyedObjectsAppearInRemoved) {
  RTbuffer scratch;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &scratch), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(scratch, RT_FORMAT_FLOAT), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(scratch, 4), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  const uint64_t id = Id(scratch);
  ASSERT_EQ(rtBufferDestroy(scratch), RT_SUCCESS);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  ASSERT_EQ(LastDelta().removed_size(), 1);
  EXPECT_EQ(LastDelta().removed(0), id);
  ASSERT_EQ(Launch(), RT_SUCCESS);
  EXPECT_EQ(LastDelta().removed_size(), 0);  // reported once
}

TEST_F(LaunchTest, DestroyingAnAttachedObjectFailsValidationByName) {
  ASSERT_EQ(rtMaterialDestroy(material), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_ERROR_INVALID_CONTEXT);
  std::string message = ErrorString(ctx, RT_ERROR_INVALID_CONTEXT);
  EXPECT_NE(message.find("geometry instance #"), std::string::npos) << message;
  EXPECT_NE(message.find("destroyed material #"), std::string::npos) << message;
  EXPECT_TRUE(records[0]->deltas.empty());  // nothing reached the device
  // Re-attaching a live material repairs the graph.
  RTmaterial fresh;
  ASSERT_EQ(rtMaterialCreate(ctx, &fresh), RT_SUCCESS);
  ASSERT_EQ(rtGeometryInstanceSetMaterial(instance, 0, fresh), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_SUCCESS);
}

TEST_F(LaunchTest, ProgramVariablesShipWithTheProgram) {
  RTvariable v;
  ASSERT_EQ(rtProgramDeclareVariable(raygen, "eye", &v), RT_SUCCESS);
  ASSERT_EQ(rtVariableSet3f(v, 1, 2, 3), RT_SUCCESS);
  const float m[6] = {1, 2, 3, 4, 5, 6};
  RTvariable mv;
  ASSERT_EQ(rtProgramDeclareVariable(raygen, "m", &mv), RT_SUCCESS);
  ASSERT_EQ(rtVariableSetMatrix2x3fv(mv, 1, m), RT_SUCCESS);  // column-major in
  ASSERT_EQ(Launch(), RT_SUCCESS);
  bool found = false;
  for (const v1::Object& o : LastDelta().objects()) {
    if (!o.has_program() || o.program().function() != "ray_gen") continue;
    found = true;
    const v1::Variable* eye = FindVariable(o.program().variables(), "eye");
    ASSERT_NE(eye, nullptr);
    EXPECT_EQ(eye->type(), static_cast<uint32_t>(RT_OBJECTTYPE_FLOAT3));
    EXPECT_EQ(eye->data().size(), 12u);
    const v1::Variable* mat = FindVariable(o.program().variables(), "m");
    ASSERT_NE(mat, nullptr);
    EXPECT_EQ(mat->type(), static_cast<uint32_t>(RT_OBJECTTYPE_MATRIX_FLOAT2x3));
    ASSERT_EQ(mat->data().size(), 24u);
    const float* rows = reinterpret_cast<const float*>(mat->data().data());
    // Column-major {1,2,3,4,5,6} of a 2x3 matrix is rows {1,3,5} and {2,4,6}.
    EXPECT_EQ(rows[0], 1);
    EXPECT_EQ(rows[1], 3);
    EXPECT_EQ(rows[2], 5);
    EXPECT_EQ(rows[3], 2);
  }
  EXPECT_TRUE(found);
}

TEST_F(LaunchTest, ZeroDimensionsOnlyBuildAccelerations) {
  int dirty = 0;
  ASSERT_EQ(rtAccelerationIsDirty(group_accel, &dirty), RT_SUCCESS);
  EXPECT_EQ(dirty, 1);  // new accelerations are dirty
  ASSERT_EQ(rtContextLaunch1D(ctx, 0, 0), RT_SUCCESS);
  ASSERT_EQ(records[0]->deltas.size(), 1u);
  const v1::LaunchRequest& r = LastLaunch();
  ASSERT_EQ(r.dims_size(), 1);
  EXPECT_EQ(r.dims(0), 0u);
  EXPECT_EQ(r.tiles_size(), 0);
  ASSERT_EQ(rtAccelerationIsDirty(group_accel, &dirty), RT_SUCCESS);
  EXPECT_EQ(dirty, 0);
}

TEST_F(LaunchTest, LaunchDimensionalityFollowsTheCall) {
  // One thread in all (the fake device): the largest tiles already give enough of them.
  auto tiles = [&] {
    std::vector<v1::Tile> all;
    for (const v1::LaunchRequest& r : records[0]->launches) {
      for (const v1::Tile& t : r.tiles()) all.push_back(t);
    }
    records[0]->launches.clear();
    return all;
  };
  ASSERT_EQ(rtContextLaunch1D(ctx, 0, 100000), RT_SUCCESS);
  EXPECT_EQ(LastLaunch().dims_size(), 1);
  EXPECT_EQ(tiles().size(), 25u);  // 4096-wide tiles: 16 or more per thread on one device
  ASSERT_EQ(rtContextLaunch3D(ctx, 0, 64, 64, 16), RT_SUCCESS);
  EXPECT_EQ(LastLaunch().dims_size(), 3);
  std::vector<v1::Tile> three = tiles();
  EXPECT_EQ(three.size(), 4u * 4u * 4u);  // 16x16x4 tiles
  EXPECT_EQ(three[0].origin_size(), 3);
  ASSERT_EQ(rtContextLaunch2D(ctx, 0, 640, 512), RT_SUCCESS);
  EXPECT_EQ(tiles().size(), 10u * 8u);  // 64x64 tiles
}

TEST_F(LaunchTest, MappedBufferBlocksLaunch) {
  void* p;
  RTbuffer spare;
  ASSERT_EQ(rtBufferCreate(ctx, RT_BUFFER_INPUT, &spare), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetFormat(spare, RT_FORMAT_BYTE), RT_SUCCESS);
  ASSERT_EQ(rtBufferSetSize1D(spare, 3), RT_SUCCESS);
  ASSERT_EQ(rtBufferMap(spare, &p), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_ERROR_ALREADY_MAPPED);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_ALREADY_MAPPED).find("buffer #" + std::to_string(Id(spare))),
            std::string::npos);
  ASSERT_EQ(rtBufferUnmap(spare), RT_SUCCESS);
  ASSERT_EQ(rtBufferMap(input, &p), RT_SUCCESS);
  EXPECT_EQ(rtContextValidate(ctx), RT_ERROR_ALREADY_MAPPED);
  ASSERT_EQ(rtBufferUnmap(input), RT_SUCCESS);
  EXPECT_EQ(Launch(), RT_SUCCESS);
}

TEST_F(LaunchTest, EntryPointOutOfRange) {
  EXPECT_EQ(rtContextLaunch2D(ctx, 1, 4, 4), RT_ERROR_INVALID_VALUE);
  EXPECT_NE(ErrorString(ctx, RT_ERROR_INVALID_VALUE).find("entry point index 1"),
            std::string::npos);
  EXPECT_TRUE(records[0]->deltas.empty());
}

}  // namespace
}  // namespace tessera::test
