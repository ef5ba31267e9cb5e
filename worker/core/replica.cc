#include "replica.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "absl/strings/str_cat.h"
#include "module.h"
#include "tessera/detail/module_abi.h"
#include "tessera/rt.h"

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
  if (b.element_size() > (1u << 20)) {
    return absl::InvalidArgumentError(
        absl::StrCat("buffer #", b.id(), " has element size ", b.element_size()));
  }
  return absl::OkStatus();
}

}  // namespace

bool BufferRec::Gathered() const {
  return (desc & RT_BUFFER_OUTPUT) != 0 && (desc & RT_BUFFER_GPU_LOCAL) == 0;
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
  // Marks may be raised concurrently (never to an epoch in range unless `last`): read each once.
  auto load = [](const unsigned char* m) { return __atomic_load_n(m, __ATOMIC_RELAXED); };
  auto taken = [&](unsigned char m) { return m > after && (last || m <= upto); };
  for (auto& [id, b] : buffers) {
    if (b.written.empty()) continue;
    unsigned char* marks = b.written.data();
    unsigned char* blocks = b.written_blocks.data();
    const size_t n = b.written.size();
    const size_t size = b.element_size;
    const bool compare = b.before.size() == b.data.size();
    // Only elements that changed since the host last heard of them: the rest were read, or
    // rewritten with the value every device already has.
    auto changed = [&](size_t e) {
      return std::memcmp(b.data.data() + e * size, b.before.data() + e * size, size) != 0;
    };
    RegionPacker packer(id, b, out);
    // Touched blocks first (a batch touches a small part of a large buffer), then runs of taken
    // elements inside them. A block's mark is its highest element's: one marked up to `after`
    // holds nothing new.
    bool open = false;
    size_t run_begin = 0, run_end = 0;  // the run being built, [begin, end)
    for (size_t block = 0; block < b.written_blocks.size(); ++block) {
      const unsigned char block_mark = load(blocks + block);
      const size_t begin = block * kBlock, end = std::min(n, begin + kBlock);
      if (block_mark > after) {
        for (size_t e = begin; e < end; ++e) {
          if (!taken(load(marks + e)) || (compare && !changed(e))) continue;
          if (!open || run_end != e) {
            if (open) packer.Add(run_begin, run_end);
            run_begin = e;
            open = true;
          }
          run_end = e + 1;
        }
      }
      if (last && block_mark != 0) {
        std::memset(marks + begin, 0, end - begin);
        blocks[block] = 0;
      }
    }
    if (open) packer.Add(run_begin, run_end);
    packer.Finish();
  }
}

absl::Status Replica::Apply(const v1::StateDelta& delta) {
  // ---- Check everything before changing anything.
  if (session_id_ != 0 && delta.session_id() != session_id_) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta for session ", delta.session_id(), " sent to session ", session_id_));
  }
  if (delta.sequence() != sequence_ + 1) {
    return absl::FailedPreconditionError(absl::StrCat(
        "state delta ", delta.sequence(), " out of order (expected ", sequence_ + 1, ")"));
  }
  std::unordered_map<uint64_t, uint64_t> new_sizes;  // buffer id -> bytes after this delta
  for (const auto& o : delta.objects()) {
    if (o.kind_case() == v1::Object::KIND_NOT_SET) {
      return absl::InvalidArgumentError("state delta holds an object of no kind");
    }
    if (o.has_buffer()) {
      if (absl::Status s = CheckBuffer(o.buffer()); !s.ok()) return s;
      uint64_t bytes = o.buffer().element_size();
      for (uint64_t d : o.buffer().dims()) bytes *= d;
      if (o.buffer().dims_size() == 0) bytes = 0;
      new_sizes[o.buffer().id()] = bytes;
    }
    if (o.has_transform() &&
        (o.transform().matrix_size() != 16 || o.transform().inverse_size() != 16)) {
      return absl::InvalidArgumentError(
          absl::StrCat("transform #", o.transform().id(), " needs 16 matrix and inverse values"));
    }
  }
  for (const auto& c : delta.chunks()) {
    uint64_t bytes = 0;
    if (auto it = new_sizes.find(c.buffer_id()); it != new_sizes.end()) {
      bytes = it->second;
    } else if (auto b = buffers.find(c.buffer_id()); b != buffers.end()) {
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
  // Last: it stores the modules the delta carries (not replica state, and harmless to keep).
  if (absl::Status s = ModuleCache::Get().Receive(delta); !s.ok()) return s;

  // ---- Apply.
  session_id_ = delta.session_id();
  sequence_ = delta.sequence();
  ++generation_;
  const v1::ContextState& c = delta.context();
  context_.entry_point_count = c.entry_point_count();
  context_.ray_type_count = c.ray_type_count();
  context_.ray_generation = ToVector(c.ray_generation());
  context_.exception = ToVector(c.exception());
  context_.miss = ToVector(c.miss());
  context_.stack_size = c.stack_size();
  context_.print_enabled = c.print_enabled();
  for (int i = 0; i < 3; ++i) {
    context_.print_index[i] = i < c.print_launch_index_size() ? c.print_launch_index(i) : -1;
  }
  context_.exception_mask = c.exception_mask();
  context_.user_exceptions = c.user_exceptions();
  context_.num_threads = c.num_threads();
  context_.vars = ToScope(c.variables());

  for (uint64_t id : delta.removed()) {
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
  }
  for (const auto& o : delta.objects()) {
    switch (o.kind_case()) {
      case v1::Object::kProgram: {
        const auto& p = o.program();
        programs[p.id()] =
            ProgramRec{p.module_path(), p.module_hash(), p.function(), ToScope(p.variables())};
        break;
      }
      case v1::Object::kBuffer: {
        const auto& b = o.buffer();
        BufferRec& r = buffers[b.id()];
        const uint32_t old_format = r.format;
        const uint64_t old_element_size = r.element_size;
        const std::array<uint64_t, 3> old_dims = r.dims;
        r.desc = b.desc();
        r.format = b.format();
        r.element_size = b.element_size();
        r.ndims = b.dims_size();
        r.dims = {0, 1, 1};
        for (int i = 0; i < b.dims_size(); ++i) r.dims[i] = b.dims(i);
        if (r.ndims == 0) r.dims[0] = 0;
        if (r.format != old_format || r.element_size != old_element_size || r.dims != old_dims) {
          // A new shape starts zeroed, like a new buffer; the host resends INPUT contents.
          r.data.assign(r.Bytes(), 0);
        }
        if (r.written.size() != (r.Gathered() ? r.Elements() : 0)) {
          const uint64_t elements = r.Gathered() ? r.Elements() : 0;
          r.written.assign(elements, 0);
          r.written_blocks.assign((elements + (uint64_t{1} << TESSERA_WRITTEN_BLOCK_SHIFT) - 1) >>
                                      TESSERA_WRITTEN_BLOCK_SHIFT,
                                  0);
        }
        break;
      }
      case v1::Object::kGeometry: {
        const auto& g = o.geometry();
        geometries[g.id()] = GeometryRec{g.primitive_count(), g.intersection_program(),
                                         g.bounding_box_program(), ToScope(g.variables())};
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
        AccelRec r{a.builder(), a.traverser(), {}, a.build_epoch()};
        for (const auto& [k, v] : a.properties()) r.properties[k] = v;
        accelerations[a.id()] = std::move(r);
        break;
      }
      case v1::Object::KIND_NOT_SET:
        break;
    }
  }
  for (const auto& ch : delta.chunks()) {
    BufferRec& b = buffers[ch.buffer_id()];
    std::memcpy(b.data.data() + ch.offset(), ch.data().data(), ch.data().size());
  }
  return absl::OkStatus();
}

}  // namespace tessera::worker
