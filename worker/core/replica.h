// A device's replica of one host session's context state, built from StateDelta messages.
#ifndef TESSERA_WORKER_CORE_REPLICA_H_
#define TESSERA_WORKER_CORE_REPLICA_H_

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "absl/status/status.h"
#include "tessera/detail/mip_levels.h"
#include "tessera/v1/launch.pb.h"
#include "tessera/v1/state.pb.h"

namespace tessera::worker {

struct Value {
  uint32_t type = 0;  // RTobjecttype
  std::string data;
  uint64_t object_id = 0;
};
using Scope = std::unordered_map<std::string, Value>;

struct NodeRef {
  uint64_t id = 0;
  uint32_t type = 0;  // RTobjecttype
};

struct ProgramRec {
  std::string module_path, module_hash, function;
  Scope vars;
  bool has_id = false;  // programs may call it by id (v1::Program.has_id)
};
struct BufferRec {
  uint32_t desc = 0, format = 0;
  uint64_t element_size = 0;
  std::array<uint64_t, 3> dims{0, 1, 1};
  unsigned ndims = 0;
  std::vector<unsigned char> data;
  // GPU_LOCAL whose device pointers the host reads (v1::Buffer.return_writes): gathered too.
  bool return_writes = false;
  // Gathered buffers (OUTPUT or INPUT_OUTPUT, not GPU_LOCAL unless return_writes): one byte per
  // element, the write epoch in which programs last accessed it (TesseraBufferView::written), 0
  // for none since the last call; TakeWrittenRegions collects them.
  std::vector<unsigned char> written;
  std::vector<unsigned char> written_blocks;  // per 2^TESSERA_WRITTEN_BLOCK_SHIFT elements
  // INPUT_OUTPUT: the contents when the launch began, then as last sent to the host. Programs
  // mark the elements they read too, and an element that still holds the value the host has from
  // this device must not travel back: it would undo another device's write of it.
  std::vector<unsigned char> before;
  // Mip levels (v1::Buffer.mip_level_count): `data` holds them all, level 0 first.
  unsigned mip_levels = 1;
  // Elements of level 0, which programs index.
  uint64_t Elements() const { return dims[0] * dims[1] * dims[2]; }
  bool KeepsDepth() const;  // layered or cube map: the depth is not mipmapped
  // Bytes of every level.
  uint64_t Bytes() const {
    return mip_levels <= 1
               ? element_size * Elements()
               : element_size * detail::MipLevelOffset(dims, ndims, KeepsDepth(), mip_levels);
  }
  bool Gathered() const;
};
// A texture sampler (v1::TextureSampler): enum fields hold RT* values, checked when applied.
struct SamplerRec {
  uint64_t buffer = 0;
  std::array<uint32_t, 3> wrap{0, 0, 0};
  uint32_t min_filter = 0, mag_filter = 0, mip_filter = 0;
  float max_anisotropy = 1.f;
  float mip_level_clamp_min = 0.f, mip_level_clamp_max = 0.f;
  float mip_level_bias = 0.f;
  uint32_t read_mode = 0, index_mode = 0;
};
struct GeometryRec {
  uint64_t primitive_count = 0, intersection = 0, bounds = 0;
  Scope vars;
  bool builtin_triangles = false;  // GeometryTriangles: `mesh` says where they are
  v1::TriangleMesh mesh;
  size_t mesh_stamp = 0;  // a hash of `mesh`, for scene stamps (hashed once, not per check)
};
struct MaterialRec {
  std::vector<uint64_t> closest_hit, any_hit;
  Scope vars;
};
struct InstanceRec {
  uint64_t geometry = 0;
  std::vector<uint64_t> materials;
  Scope vars;
};
// Bounds rtAccelerationSetData restored for one child of a GeometryGroup (Acceleration
// .cached_bounds): used instead of running its bounding-box program when the counts agree.
struct CachedBounds {
  uint64_t primitive_count = 0;
  bool has_bounds = false;
  std::vector<float> bounds;  // 6 per primitive
};
struct AccelRec {
  std::string builder, traverser;
  std::map<std::string, std::string> properties;
  uint64_t build_epoch = 0;
  std::vector<CachedBounds> cached_bounds;
};
struct GeometryGroupRec {
  uint64_t acceleration = 0;
  std::vector<uint64_t> children;
};
struct GroupRec {
  uint64_t acceleration = 0;
  std::vector<NodeRef> children;
};
struct TransformRec {
  std::array<float, 16> matrix{}, inverse{};
  NodeRef child;
};
struct SelectorRec {
  uint64_t visit = 0;
  std::vector<NodeRef> children;
  Scope vars;
};

struct ContextRec {
  uint32_t entry_point_count = 0, ray_type_count = 0;
  std::vector<uint64_t> ray_generation, exception, miss;
  uint64_t stack_size = 1024;
  bool print_enabled = false;
  std::array<int32_t, 3> print_index{-1, -1, -1};
  uint64_t print_buffer_size = UINT64_MAX;  // bytes the host keeps of a launch's prints
  uint32_t exception_mask = 0;
  bool user_exceptions = false;
  uint32_t num_threads = 0;
  uint32_t accuracy_flags = 0;  // TESSERA_ACCURACY_* (tessera/accuracy.h)
  Scope vars;
};

class Replica {
 public:
  // Applies a delta: checks it whole first (sequence, ids, chunk bounds), so a rejected delta
  // leaves the replica as it was.
  absl::Status Apply(const v1::StateDelta& delta);
  // Appends to `out` the elements of gathered buffers that programs marked in write epochs
  // (after, upto], as runs of adjacent elements. Programs may run meanwhile provided none of them
  // can still mark with an epoch up to `upto` (the write epoch is past it and every program that
  // read an earlier one has returned): an element they write again gets a later epoch and
  // travels again. With `last` (no program running) it takes every epoch after `after` and
  // clears all marks for the next call.
  void TakeWrittenRegions(v1::TileResult* out, unsigned char after, unsigned char upto, bool last);
  // The epoch programs mark with (TesseraBufferView::write_epoch): 1 at the start of a call.
  const unsigned char* write_epoch() const { return &write_epoch_; }
  void SetWriteEpoch(unsigned char epoch) {
    __atomic_store_n(&write_epoch_, epoch, __ATOMIC_RELEASE);
  }
  // Records the contents of INPUT_OUTPUT buffers at the start of a launch (see BufferRec::before).
  void SnapshotForLaunch();

  const ContextRec& context() const { return context_; }
  template <typename T>
  const T* Find(const std::unordered_map<uint64_t, T>& map, uint64_t id) const {
    auto it = map.find(id);
    return it == map.end() ? nullptr : &it->second;
  }
  std::unordered_map<uint64_t, ProgramRec> programs;
  std::unordered_map<uint64_t, BufferRec> buffers;
  std::unordered_map<uint64_t, GeometryRec> geometries;
  std::unordered_map<uint64_t, MaterialRec> materials;
  std::unordered_map<uint64_t, InstanceRec> instances;
  std::unordered_map<uint64_t, AccelRec> accelerations;
  std::unordered_map<uint64_t, GeometryGroupRec> geometry_groups;
  std::unordered_map<uint64_t, GroupRec> groups;
  std::unordered_map<uint64_t, TransformRec> transforms;
  std::unordered_map<uint64_t, SelectorRec> selectors;
  std::unordered_map<uint64_t, SamplerRec> texture_samplers;
  uint64_t generation() const { return generation_; }  // bumps with every applied delta
  // Bumps with every applied delta that changes more than the bytes of variables and buffers:
  // the graph, programs, a buffer's shape, a variable's name, type, object or size. Deltas of
  // values alone are written in place (replica_values.cc), where bindings of an earlier plan
  // point.
  uint64_t structure_generation() const { return structure_generation_; }
  // Bumps with every applied delta that changes what programs are bound to: all of the above but
  // groups, geometry groups, transforms and accelerations, whose changes leave bindings valid.
  uint64_t bindings_generation() const { return bindings_generation_; }

 private:
  struct StagedBuffer;
  // The kind of object the replica holds under `id`, if any.
  v1::Object::KindCase KindOf(uint64_t id) const;
  // Records what buffer `b` of a delta makes of the buffer the replica holds (none if `removed`).
  void Stage(const v1::Buffer& b, bool removed,
             std::unordered_map<uint64_t, StagedBuffer>& staged) const;
  // Allocates the storage staged buffers need: RESOURCE_EXHAUSTED naming the buffer if it cannot.
  absl::Status Allocate(std::unordered_map<uint64_t, StagedBuffer>& staged) const;

  // A scope a delta of values alone rewrites, and its variables as the delta sends them.
  struct ValueWrite {
    Scope* scope;
    const google::protobuf::RepeatedPtrField<v1::Variable>* variables;
  };
  // What a delta changes: variables' bytes and buffer contents alone, those and graph nodes
  // (Group, GeometryGroup, Transform, Acceleration), or more. For the first two, `writes` are the
  // scopes it rewrites.
  enum class DeltaScope { kValues, kGraph, kEverything };
  DeltaScope Classify(const v1::StateDelta& delta, std::vector<ValueWrite>* writes);
  static bool IsGraphKind(v1::Object::KindCase kind);
  static void WriteValues(const std::vector<ValueWrite>& writes);
  void ApplyObject(const v1::Object& o);  // checked by Apply; buffers are staged instead
  void RemoveObject(uint64_t id);
  void WriteChunks(const v1::StateDelta& delta);  // checked by Apply

  ContextRec context_;
  uint64_t session_id_ = 0;
  uint64_t sequence_ = 0;
  uint64_t generation_ = 0;
  uint64_t structure_generation_ = 0;
  uint64_t bindings_generation_ = 0;
  alignas(64) unsigned char write_epoch_ = 1;  // its own cache line: every marking access reads it
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_REPLICA_H_
