#include "replica.h"

#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <unordered_set>

#include "absl/hash/hash.h"
#include "absl/strings/str_cat.h"
#include "module.h"
#include "tessera/detail/module_abi.h"
#include "tessera/detail/texture_view.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"
#include "tessera/v1/object_fields.h"
#include "written_scan.h"

namespace tessera::worker {
namespace {

Scope ToScope(const google::protobuf::RepeatedPtrField<v1::Variable>& vars) {
  Scope scope;
  for (const auto& v : vars) scope[v.name()] = Value{v.type(), v.data(), v.object_id()};
  return scope;
}

NodeRef ToRef(const v1::NodeRef& r) { return NodeRef{r.id(), r.type()}; }

template <typename T>
std::vector<T> ToVector(const google::protobuf::RepeatedField<T>& f) {
  return std::vector<T>(f.begin(), f.end());
}

// Bytes of memory this machine has: a buffer larger than that cannot be held, and allocating it
// lazily would only end the process later, when its pages are touched.
uint64_t PhysicalMemory() {
  static const uint64_t bytes = [] {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : ~uint64_t{0};
  }();
  return bytes;
}

absl::Status CheckBuffer(const v1::Buffer& b) {
  if (b.dims_size() > 3) {
    return absl::InvalidArgumentError(
        absl::StrCat("buffer #", b.id(), " has ", b.dims_size(), " dimensions (at most 3)"));
  }
  uint64_t count = 1;
  for (uint64_t d : b.dims()) {
    if (d != 0 && count > (uint64_t{1} << 40) / d) {
      return absl::InvalidArgumentError(absl::StrCat("buffer #", b.id(), " is too large"));
    }
    count *= d;
  }
  if (b.element_size() > kMaxElementBytes) {
    return absl::InvalidArgumentError(
        absl::StrCat("buffer #", b.id(), " has element size ", b.element_size()));
  }
  if (b.mip_level_count() > TESSERA_TEXTURE_MAX_LEVELS) {
    return absl::InvalidArgumentError(absl::StrCat("buffer #", b.id(), " has ", b.mip_level_count(),
                                                   " mip levels (at most ",
                                                   TESSERA_TEXTURE_MAX_LEVELS, ")"));
  }
  return absl::OkStatus();
}

// Enum values a device's texture views pass to the sampling functions must be ones they know.
absl::Status CheckSampler(const v1::TextureSampler& t) {
  auto bad = [&](const char* what, uint64_t value) {
    return absl::InvalidArgumentError(
        absl::StrCat("texture sampler #", t.id(), " has ", what, " ", value));
  };
  if (t.wrap_size() != 3) return bad("wrap mode count", t.wrap_size());
  for (uint32_t w : t.wrap()) {
    if (w > RT_WRAP_CLAMP_TO_BORDER) return bad("wrap mode", w);
  }
  if (t.min_filter() > RT_FILTER_LINEAR) return bad("minification filter", t.min_filter());
  if (t.mag_filter() > RT_FILTER_LINEAR) return bad("magnification filter", t.mag_filter());
  if (t.mip_filter() > RT_FILTER_NONE) return bad("mipmapping filter", t.mip_filter());
  if (t.read_mode() > RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB) return bad("read mode", t.read_mode());
  if (t.index_mode() > RT_TEXTURE_INDEX_ARRAY_INDEX) return bad("indexing mode", t.index_mode());
  return absl::OkStatus();
}

// Restored bounds hold 6 floats per primitive, and no more than one acceleration's data carries.
absl::Status CheckAcceleration(const v1::Acceleration& a) {
  uint64_t total = 0;
  for (int i = 0; i < a.cached_bounds_size(); ++i) {
    const v1::PrimitiveBounds& c = a.cached_bounds(i);
    const uint64_t expected = c.has_bounds() ? c.primitive_count() * 6 * sizeof(float) : 0;
    total += c.bounds().size();
    if (c.primitive_count() > kMaxCarriedBoundsBytes || c.bounds().size() != expected) {
      return absl::InvalidArgumentError(absl::StrCat(
          "acceleration #", a.id(), ": restored bounds of child ", i, " hold ", c.bounds().size(),
          " bytes for ", c.primitive_count(), " primitives (expected ", expected, ")"));
    }
  }
  if (total > kMaxCarriedBoundsBytes) {
    return absl::InvalidArgumentError(absl::StrCat("acceleration #", a.id(), ": ", total,
                                                   " bytes of restored bounds (at most ",
                                                   kMaxCarriedBoundsBytes, ")"));
  }
  return absl::OkStatus();
}

// Embree counts primitives in 32 bits (so does rtGeometrySetPrimitiveCount), and a user geometry
// keeps 24 bytes of bounds per primitive while its acceleration builds.
absl::Status CheckGeometry(const v1::Geometry& g) {
  constexpr uint64_t kMaxPrimitives = 0xFFFFFFFFu;
  if (g.primitive_count() > kMaxPrimitives) {
    return absl::InvalidArgumentError(absl::StrCat("geometry #", g.id(), " has ",
                                                   g.primitive_count(), " primitives (at most ",
                                                   kMaxPrimitives, ")"));
  }
  if (g.primitive_count() * 24 > PhysicalMemory()) {
    return absl::ResourceExhaustedError(
        absl::StrCat("geometry #", g.id(), " has ", g.primitive_count(),
                     " primitives, whose bounds need ", g.primitive_count() * 24,
                     " bytes; this device has ", PhysicalMemory(), " bytes of memory"));
  }
  return absl::OkStatus();
}

}  // namespace

// A buffer of a delta as the delta leaves it: its shape, and new storage where the shape or the
// marks change. Allocated while the delta is checked, so that a buffer this device cannot hold
// rejects the delta before anything changed.
struct Replica::StagedBuffer {
  BufferRec rec;            // shape; `data`, `written` and `written_blocks` when replaced
  uint64_t held_marks = 0;  // marks the replica holds for it (none when the delta removes it)
  bool reshaped = false;    // new contents: zeros, like a new buffer (the host resends INPUT ones)
  bool remarked = false;    // new marks
};

bool BufferRec::KeepsDepth() const {
  return ndims == 3 && (desc & (RT_BUFFER_LAYERED | RT_BUFFER_CUBEMAP)) != 0;
}

bool BufferRec::Gathered() const {
  return (desc & RT_BUFFER_OUTPUT) != 0 && ((desc & RT_BUFFER_GPU_LOCAL) == 0 || return_writes);
}

void Replica::SnapshotForLaunch() {
  for (auto& [id, b] : buffers) {
    if (b.Gathered() && (b.desc & RT_BUFFER_INPUT) != 0) {
      b.before.assign(b.data.begin(), b.data.end());
    } else {
      b.before.clear();
    }
  }
}

namespace {

// Packs runs of written elements into regions of at most this many data bytes, which the worker
// service sends as one message each (scheduler/transport/worker_wire.h kMaxRegionBytes).
constexpr size_t kPackedRegionBytes = size_t{4} << 20;

// Collects the runs of one buffer, then packs them into regions: sizes first, so that each
// region's data is allocated once, and the copies in parallel (one batch's regions can be the
// whole image; copying and first-touching tens of MiB on one thread held every launch up).
class RegionPacker {
 public:
  // `b` is not const: an INPUT_OUTPUT buffer's `before` becomes what was sent.
  RegionPacker(uint64_t id, BufferRec& b, v1::TileResult* out) : id_(id), b_(b), out_(out) {}
  // Adds the elements [begin, end).
  void Add(size_t begin, size_t end) {
    uint64_t offset = begin * b_.element_size;
    uint64_t bytes = (end - begin) * b_.element_size;
    while (bytes > 0) {
      if (regions_.empty() || regions_.back().bytes >= kPackedRegionBytes) {
        regions_.push_back(Region{runs_.size(), 0, 0});
      }
      Region& region = regions_.back();
      const uint64_t n = std::min<uint64_t>(bytes, kPackedRegionBytes - region.bytes);
      runs_.push_back({offset, n});
      region.bytes += n;
      region.run_end = runs_.size();
      offset += n;
      bytes -= n;
    }
  }
  // Appends the regions to the result.
  void Finish() {
    if (regions_.empty()) return;
    const int first = out_->regions_size();
    for (const Region& region : regions_) {
      v1::BufferRegion* r = out_->add_regions();
      r->set_buffer_id(id_);
      for (size_t i = region.run_begin; i < region.run_end; ++i) {
        r->add_run_offsets(runs_[i].offset);
        r->add_run_sizes(runs_[i].bytes);
      }
    }
    tbb::parallel_for(size_t{0}, regions_.size(), [&](size_t k) {
      const Region& region = regions_[k];
      std::string* data = out_->mutable_regions(first + static_cast<int>(k))->mutable_data();
      data->resize(region.bytes);
      char* to = data->data();
      const bool record = b_.before.size() == b_.data.size();
      for (size_t i = region.run_begin; i < region.run_end; ++i) {
        std::memcpy(to, b_.data.data() + runs_[i].offset, runs_[i].bytes);
        // The bytes sent, not the buffer again: a program may be rewriting them right now.
        if (record) std::memcpy(b_.before.data() + runs_[i].offset, to, runs_[i].bytes);
        to += runs_[i].bytes;
      }
    });
  }

 private:
  struct Run {
    uint64_t offset, bytes;
  };
  struct Region {
    size_t run_begin, run_end;
    uint64_t bytes;
  };
  const uint64_t id_;
  BufferRec& b_;
  v1::TileResult* const out_;
  std::vector<Run> runs_;
  std::vector<Region> regions_;
};

}  // namespace

void Replica::TakeWrittenRegions(v1::TileResult* out, unsigned char after, unsigned char upto,
                                 bool last) {
  constexpr size_t kBlock = size_t{1} << TESSERA_WRITTEN_BLOCK_SHIFT;
  // The final collection of a call ends it while every thread of the device is idle, and its
  // serial scan was 0.9 ms of a 21 ms 16-thread launch (1M elements): groups of blocks are
  // scanned in parallel then. Collections while the call traces stay serial, off the tracers.
  constexpr size_t kBlocksPerGroup = 16;
  // Marks may be raised concurrently (never to an epoch in range unless `last`): read each once.
  auto load = [](const unsigned char* m) { return __atomic_load_n(m, __ATOMIC_RELAXED); };
  const MarkRange range{after, upto, last};
  for (auto& [id, b] : buffers) {
    if (b.written.empty()) continue;
    unsigned char* marks = b.written.data();
    unsigned char* blocks = b.written_blocks.data();
    const size_t n = b.written.size();
    const size_t size = b.element_size;
    // Only elements that changed since the host last heard of them: the rest were read, or
    // rewritten with the value every device already has.
    const bool compare = b.before.size() == b.data.size();
    // Touched blocks first (a batch touches a small part of a large buffer), then runs of taken
    // elements inside them. A block's mark is its highest element's: one marked up to `after`
    // holds nothing new.
    auto scan = [&](size_t first_block, size_t end_block, std::vector<ElementRun>& runs) {
      for (size_t block = first_block; block < end_block; ++block) {
        const unsigned char block_mark = load(blocks + block);
        const size_t begin = block * kBlock, end = std::min(n, begin + kBlock);
        if (block_mark > after) {
          ForEachTakenRun(marks, begin, end, range, [&](size_t first, size_t stop) {
            if (compare) {
              AppendChanged(b.data.data(), b.before.data(), size, first, stop, runs);
            } else {
              AppendRun(runs, first, stop);
            }
          });
        }
        if (last && block_mark != 0) {
          std::memset(marks + begin, 0, end - begin);
          blocks[block] = 0;
        }
      }
    };
    const size_t block_count = b.written_blocks.size();
    std::vector<ElementRun> runs;
    if (last && block_count >= 2 * kBlocksPerGroup) {
      // Each group's runs in order, joined where they touch: the same runs as one serial scan.
      std::vector<std::vector<ElementRun>> groups((block_count + kBlocksPerGroup - 1) /
                                                  kBlocksPerGroup);
      tbb::parallel_for(size_t{0}, groups.size(), [&](size_t g) {
        scan(g * kBlocksPerGroup, std::min(block_count, (g + 1) * kBlocksPerGroup), groups[g]);
      });
      for (const std::vector<ElementRun>& group : groups) {
        for (const ElementRun& r : group) AppendRun(runs, r.begin, r.end);
      }
    } else {
      scan(0, block_count, runs);
    }
    RegionPacker packer(id, b, out);
    for (const ElementRun& r : runs) packer.Add(r.begin, r.end);
    packer.Finish();
  }
}

absl::Status Replica::Apply(const v1::StateDelta& delta) {
  // ---- Check everything before changing anything.
  if (delta.session_id() == 0) {
    // 0 is "no session yet" here: a replica that took it would accept any session after it.
    return absl::InvalidArgumentError("state delta for session 0 (hosts number sessions from 1)");
  }
  if (session_id_ != 0 && delta.session_id() != session_id_) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta for session ", delta.session_id(), " sent to session ", session_id_));
  }
  if (delta.sequence() != sequence_ + 1) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta ", delta.sequence(), " out of order (expected ", sequence_ + 1, ")"));
  }
  const std::unordered_set<uint64_t> removed(delta.removed().begin(), delta.removed().end());
  std::unordered_map<uint64_t, v1::Object::KindCase> kinds;  // of the delta's objects, by id
  std::unordered_map<uint64_t, StagedBuffer> staged;         // by buffer id
  for (const auto& o : delta.objects()) {
    if (o.kind_case() == v1::Object::KIND_NOT_SET) {
      return absl::InvalidArgumentError("state delta holds an object of no kind");
    }
    // An id names one object: lookups by id (references, removals, graph nodes) must not find
    // two of different kinds.
    const uint64_t id = v1::ObjectId(o);
    if (id == 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          "state delta holds a ", v1::ObjectKindName(o.kind_case()), " with id 0 (none)"));
    }
    v1::Object::KindCase held = kinds.emplace(id, o.kind_case()).first->second;
    if (held == o.kind_case() && removed.count(id) == 0) held = KindOf(id);
    if (held != o.kind_case() && held != v1::Object::KIND_NOT_SET) {
      return absl::InvalidArgumentError(absl::StrCat(v1::ObjectKindName(o.kind_case()), " #", id,
                                                     " has the id of a ",
                                                     v1::ObjectKindName(held)));
    }
    if (o.has_buffer()) {
      if (absl::Status s = CheckBuffer(o.buffer()); !s.ok()) return s;
      Stage(o.buffer(), removed.count(id) != 0, staged);
    }
    if (o.has_geometry()) {
      if (absl::Status s = CheckGeometry(o.geometry()); !s.ok()) return s;
    }
    if (o.has_texture_sampler()) {
      if (absl::Status s = CheckSampler(o.texture_sampler()); !s.ok()) return s;
    }
    if (o.has_acceleration()) {
      if (absl::Status s = CheckAcceleration(o.acceleration()); !s.ok()) return s;
    }
    if (o.has_transform() &&
        (o.transform().matrix_size() != 16 || o.transform().inverse_size() != 16)) {
      return absl::InvalidArgumentError(
          absl::StrCat("transform #", o.transform().id(), " needs 16 matrix and inverse values"));
    }
  }
  for (const auto& c : delta.chunks()) {
    uint64_t bytes = 0;
    if (auto it = staged.find(c.buffer_id()); it != staged.end()) {
      bytes = it->second.rec.Bytes();
    } else if (auto b = buffers.find(c.buffer_id()); b != buffers.end()) {
      if (removed.count(c.buffer_id()) != 0) {
        return absl::InvalidArgumentError(
            absl::StrCat("buffer chunk for buffer #", c.buffer_id(), ", which this delta removes"));
      }
      bytes = b->second.Bytes();
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat("buffer chunk for unknown buffer #", c.buffer_id()));
    }
    if (c.offset() > bytes || c.data().size() > bytes - c.offset()) {
      return absl::OutOfRangeError(absl::StrCat("buffer chunk [", c.offset(), ", +",
                                                c.data().size(), ") outside buffer #",
                                                c.buffer_id(), " of ", bytes, " bytes"));
    }
  }
  // It stores the modules the delta carries (not replica state, and harmless to keep).
  if (absl::Status s = ModuleCache::Get().Receive(delta); !s.ok()) return s;
  // Last, as the costliest: a delta rejected for anything else allocates nothing.
  if (absl::Status s = Allocate(staged); !s.ok()) return s;

  // ---- Apply.
  std::vector<ValueWrite> writes;
  const DeltaScope scope = Classify(delta, &writes);
  session_id_ = delta.session_id();
  sequence_ = delta.sequence();
  ++generation_;
  if (scope != DeltaScope::kEverything) {
    WriteValues(writes);
    if (scope == DeltaScope::kGraph) {
      ++structure_generation_;
      for (uint64_t id : delta.removed()) RemoveObject(id);
      for (const auto& o : delta.objects()) {
        if (IsGraphKind(o.kind_case())) ApplyObject(o);
      }
    }
    WriteChunks(delta);
    return absl::OkStatus();
  }
  ++structure_generation_;
  ++bindings_generation_;
  const v1::ContextState& c = delta.context();
  context_.entry_point_count = c.entry_point_count();
  context_.ray_type_count = c.ray_type_count();
  context_.ray_generation = ToVector(c.ray_generation());
  context_.exception = ToVector(c.exception());
  context_.miss = ToVector(c.miss());
  context_.stack_size = c.stack_size();
  context_.print_enabled = c.print_enabled();
  context_.print_buffer_size = c.print_buffer_size();
  for (int i = 0; i < 3; ++i) {
    context_.print_index[i] = i < c.print_launch_index_size() ? c.print_launch_index(i) : -1;
  }
  context_.exception_mask = c.exception_mask();
  context_.user_exceptions = c.user_exceptions();
  context_.num_threads = c.num_threads();
  context_.accuracy_flags = c.accuracy_flags();
  context_.vars = ToScope(c.variables());

  for (uint64_t id : delta.removed()) RemoveObject(id);
  for (const auto& o : delta.objects()) ApplyObject(o);
  for (auto& [id, staged_buffer] : staged) {
    BufferRec& from = staged_buffer.rec;
    BufferRec& r = buffers[id];
    r.desc = from.desc;
    r.return_writes = from.return_writes;
    r.format = from.format;
    r.element_size = from.element_size;
    r.ndims = from.ndims;
    r.dims = from.dims;
    r.mip_levels = from.mip_levels;
    if (staged_buffer.reshaped) r.data = std::move(from.data);
    if (staged_buffer.remarked) {
      r.written = std::move(from.written);
      r.written_blocks = std::move(from.written_blocks);
    }
  }
  WriteChunks(delta);
  return absl::OkStatus();
}

void Replica::RemoveObject(uint64_t id) {
  programs.erase(id);
  buffers.erase(id);
  geometries.erase(id);
  materials.erase(id);
  instances.erase(id);
  accelerations.erase(id);
  geometry_groups.erase(id);
  groups.erase(id);
  transforms.erase(id);
  selectors.erase(id);
  texture_samplers.erase(id);
}

// Records of an existing id are assigned in place: their addresses, which plans hold (a
// Transform's matrix, say), stay.
void Replica::ApplyObject(const v1::Object& o) {
  switch (o.kind_case()) {
    case v1::Object::kProgram: {
      const auto& p = o.program();
      programs[p.id()] = ProgramRec{p.module_path(), p.module_hash(), p.function(),
                                    ToScope(p.variables()), p.has_id()};
      break;
    }
    case v1::Object::kBuffer:
      break;  // Apply stages buffers
    case v1::Object::kGeometry: {
      const auto& g = o.geometry();
      geometries[g.id()] = GeometryRec{g.primitive_count(),
                                       g.intersection_program(),
                                       g.bounding_box_program(),
                                       ToScope(g.variables()),
                                       g.has_triangles(),
                                       g.triangles(),
                                       absl::HashOf(g.triangles().SerializeAsString())};
      break;
    }
    case v1::Object::kMaterial: {
      const auto& m = o.material();
      materials[m.id()] =
          MaterialRec{ToVector(m.closest_hit()), ToVector(m.any_hit()), ToScope(m.variables())};
      break;
    }
    case v1::Object::kGeometryInstance: {
      const auto& gi = o.geometry_instance();
      instances[gi.id()] =
          InstanceRec{gi.geometry(), ToVector(gi.materials()), ToScope(gi.variables())};
      break;
    }
    case v1::Object::kGeometryGroup: {
      const auto& gg = o.geometry_group();
      geometry_groups[gg.id()] = GeometryGroupRec{gg.acceleration(), ToVector(gg.children())};
      break;
    }
    case v1::Object::kGroup: {
      const auto& g = o.group();
      GroupRec r{g.acceleration(), {}};
      for (const auto& ch : g.children()) r.children.push_back(ToRef(ch));
      groups[g.id()] = std::move(r);
      break;
    }
    case v1::Object::kTransform: {
      const auto& t = o.transform();
      TransformRec r;
      for (int i = 0; i < 16; ++i) {
        r.matrix[i] = t.matrix(i);
        r.inverse[i] = t.inverse(i);
      }
      r.child = ToRef(t.child());
      transforms[t.id()] = r;
      break;
    }
    case v1::Object::kSelector: {
      const auto& s = o.selector();
      SelectorRec r{s.visit_program(), {}, ToScope(s.variables())};
      for (const auto& ch : s.children()) r.children.push_back(ToRef(ch));
      selectors[s.id()] = std::move(r);
      break;
    }
    case v1::Object::kAcceleration: {
      const auto& a = o.acceleration();
      AccelRec r{a.builder(), a.traverser(), {}, a.build_epoch(), {}};
      for (const auto& [k, v] : a.properties()) r.properties[k] = v;
      for (const v1::PrimitiveBounds& c : a.cached_bounds()) {  // sizes checked before
        CachedBounds& cb = r.cached_bounds.emplace_back();
        cb.primitive_count = c.primitive_count();
        cb.has_bounds = c.has_bounds();
        cb.bounds.resize(c.bounds().size() / sizeof(float));
        std::memcpy(cb.bounds.data(), c.bounds().data(), c.bounds().size());
      }
      accelerations[a.id()] = std::move(r);
      break;
    }
    case v1::Object::kTextureSampler: {
      const auto& t = o.texture_sampler();
      SamplerRec r;
      r.buffer = t.buffer();
      for (int i = 0; i < 3; ++i) r.wrap[i] = t.wrap(i);
      r.min_filter = t.min_filter();
      r.mag_filter = t.mag_filter();
      r.mip_filter = t.mip_filter();
      r.max_anisotropy = t.max_anisotropy();
      r.mip_level_clamp_min = t.mip_level_clamp_min();
      r.mip_level_clamp_max = t.mip_level_clamp_max();
      r.mip_level_bias = t.mip_level_bias();
      r.read_mode = t.read_mode();
      r.index_mode = t.index_mode();
      texture_samplers[t.id()] = r;
      break;
    }
    case v1::Object::kOptix7ProgramGroup:
    case v1::Object::kOptix7Pipeline:
      break;  // OptiX 7 state lives beside the replica (optix7_session.h)
    case v1::Object::KIND_NOT_SET:
      break;
  }
}

void Replica::WriteChunks(const v1::StateDelta& delta) {
  for (const auto& ch : delta.chunks()) {
    if (ch.data().empty()) continue;
    BufferRec& b = buffers.at(ch.buffer_id());
    std::memcpy(b.data.data() + ch.offset(), ch.data().data(), ch.data().size());
  }
}

v1::Object::KindCase Replica::KindOf(uint64_t id) const {
  if (programs.count(id) != 0) return v1::Object::kProgram;
  if (buffers.count(id) != 0) return v1::Object::kBuffer;
  if (geometries.count(id) != 0) return v1::Object::kGeometry;
  if (materials.count(id) != 0) return v1::Object::kMaterial;
  if (instances.count(id) != 0) return v1::Object::kGeometryInstance;
  if (accelerations.count(id) != 0) return v1::Object::kAcceleration;
  if (geometry_groups.count(id) != 0) return v1::Object::kGeometryGroup;
  if (groups.count(id) != 0) return v1::Object::kGroup;
  if (transforms.count(id) != 0) return v1::Object::kTransform;
  if (selectors.count(id) != 0) return v1::Object::kSelector;
  if (texture_samplers.count(id) != 0) return v1::Object::kTextureSampler;
  return v1::Object::KIND_NOT_SET;
}

void Replica::Stage(const v1::Buffer& b, bool removed,
                    std::unordered_map<uint64_t, StagedBuffer>& staged) const {
  auto [it, first] = staged.try_emplace(b.id());
  BufferRec& r = it->second.rec;
  if (first) {  // the shape the device holds, unless the delta removes the buffer first
    auto held = buffers.find(b.id());
    if (held != buffers.end() && !removed) {
      r.desc = held->second.desc;
      r.format = held->second.format;
      r.element_size = held->second.element_size;
      r.ndims = held->second.ndims;
      r.dims = held->second.dims;
      r.mip_levels = held->second.mip_levels;
      it->second.held_marks = held->second.written.size();
    }
  }
  r.desc = b.desc();
  r.return_writes = b.return_writes();
  r.format = b.format();
  r.element_size = b.element_size();
  r.mip_levels = b.mip_level_count() > 1 ? b.mip_level_count() : 1;
  r.ndims = b.dims_size();
  r.dims = {0, 1, 1};
  for (int i = 0; i < b.dims_size(); ++i) r.dims[i] = b.dims(i);
  if (r.ndims == 0) r.dims[0] = 0;
  // The host sends a buffer's description again only when it reallocated the buffer
  // (rtBufferSetSize, SetFormat, SetElementSize), which zeroes its contents even at the same
  // shape: so does this copy, which programs read for OUTPUT buffers (the host resends the
  // contents of INPUT ones).
  it->second.reshaped = true;
}

absl::Status Replica::Allocate(std::unordered_map<uint64_t, StagedBuffer>& staged) const {
  for (auto& [id, s] : staged) {
    BufferRec& r = s.rec;
    const uint64_t marks = r.Gathered() ? r.Elements() : 0;
    s.remarked = marks != s.held_marks;
    const uint64_t bytes = (s.reshaped ? r.Bytes() : 0) + (s.remarked ? marks : 0);
    if (bytes > PhysicalMemory()) {
      return absl::ResourceExhaustedError(absl::StrCat("buffer #", id, " needs ", bytes,
                                                       " bytes; this device has ", PhysicalMemory(),
                                                       " bytes of memory"));
    }
    try {
      if (s.reshaped) r.data.assign(r.Bytes(), 0);
      if (s.remarked) {
        r.written.assign(marks, 0);
        r.written_blocks.assign((marks + (uint64_t{1} << TESSERA_WRITTEN_BLOCK_SHIFT) - 1) >>
                                    TESSERA_WRITTEN_BLOCK_SHIFT,
                                0);
      }
    } catch (const std::bad_alloc&) {
      return absl::ResourceExhaustedError(
          absl::StrCat("buffer #", id, ": cannot allocate ", bytes, " bytes"));
    }
  }
  return absl::OkStatus();
}

}  // namespace tessera::worker
