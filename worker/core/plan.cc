#include "plan.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <map>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "runtime.h"
#include "tessera/rt.h"
#include "tessera/scheduler/device.h"
#include "texture_views.h"

namespace tessera::worker {

Mat MulMat(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return c;
}

namespace {

// Whether `code` begins with `pattern`, read byte by byte: no byte past the first that differs
// (a one-byte function may end its mapping).
template <size_t N>
bool Starts(const unsigned char* code, const unsigned char (&pattern)[N]) {
  for (size_t i = 0; i < N; ++i) {
    if (code[i] != pattern[i]) return false;
  }
  return true;
}

}  // namespace

bool EmptyProgramCode(const void* function) {
#if defined(__x86_64__)
  if (function == nullptr) return false;
  const auto* code = static_cast<const unsigned char*>(function);
  static constexpr unsigned char kEndbr64[] = {0xf3, 0x0f, 0x1e, 0xfa};
  if (Starts(code, kEndbr64)) code += sizeof(kEndbr64);
  static constexpr unsigned char kRet[] = {0xc3};
  static constexpr unsigned char kRepRet[] = {0xf3, 0xc3};
  // push %rbp; mov %rsp,%rbp; nop; pop %rbp; ret
  static constexpr unsigned char kFrame[] = {0x55, 0x48, 0x89, 0xe5, 0x90, 0x5d, 0xc3};
  return Starts(code, kRet) || Starts(code, kRepRet) || Starts(code, kFrame);
#else
  (void)function;
  return false;  // the patterns are x86-64 code
#endif
}

namespace {

// Bytes of OptiX stack one nested rtTrace costs; the context's stack size divided by this is the
// deepest trace allowed (default 1024 bytes: 8 levels). See docs/COMPATIBILITY.md.
constexpr uint64_t kStackBytesPerTrace = 128;
// The deepest nesting a device allows whatever the stack size: every level also takes native
// stack (a release build ran out of a thread's 8 MiB near 12,000 levels; sanitizers take several
// times more per level) and a frame per thread (a stack size of 2^40 asked for 2^33 frames).
constexpr uint64_t kMaxTraceDepth = 1024;

void CollectRoots(const Scope& scope, std::vector<uint64_t>& roots) {
  for (const auto& [name, v] : scope) {
    if (v.object_id != 0 &&
        (v.type == RT_OBJECTTYPE_GROUP || v.type == RT_OBJECTTYPE_GEOMETRY_GROUP ||
         v.type == RT_OBJECTTYPE_TRANSFORM || v.type == RT_OBJECTTYPE_SELECTOR ||
         v.type == RT_OBJECTTYPE_OBJECT)) {
      roots.push_back(v.object_id);
    }
  }
}

// Moves the slot values all of a module's bindings share into the module's invariants.
void SplitInvariants(LaunchPlan& plan) {
  std::unordered_map<const Module*, std::vector<BoundProgram*>> by_module;
  for (BoundProgram& b : plan.programs) by_module[b.module].push_back(&b);
  for (auto& [module, bindings] : by_module) {
    if (plan.invariants.size() <= static_cast<size_t>(module->index())) {
      plan.invariants.resize(module->index() + 1);
    }
    ModuleInvariants& inv = plan.invariants[module->index()];
    // Every binding lists every user variable and buffer slot of its module, in order.
    const BoundProgram& first = *bindings.front();
    for (size_t i = 0; i < first.copies.size(); ++i) {
      const BoundProgram::Copy& c = first.copies[i];
      bool same = true;
      const size_t merged = inv.merged.size();
      for (const BoundProgram* b : bindings) {
        const BoundProgram::Copy& o = b->copies[i];
        if (o.var != c.var || (o.src != c.src && std::memcmp(o.src, c.src, c.size) != 0)) {
          same = false;
          break;
        }
        if (o.src != c.src && (inv.merged.size() == merged || inv.merged.back().other != o.src)) {
          inv.merged.push_back({c.src, o.src, c.size});
        }
      }
      if (same) {
        inv.copies.push_back(c);
      } else {
        inv.merged.resize(merged);
      }
    }
    auto is_invariant_copy = [&](const BoundProgram::Copy& c) {
      for (const auto& i : inv.copies)
        if (i.var == c.var) return true;
      return false;
    };
    for (BoundProgram* b : bindings) {
      b->copies.erase(std::remove_if(b->copies.begin(), b->copies.end(), is_invariant_copy),
                      b->copies.end());
    }
  }
}

// Binds the programs that rtCallableProgram variables name (OptiX guide, "Callable Programs"):
// each with its own scope and then its caller's scopes after the caller's own, once per caller
// kind and scopes; a program that calls itself, directly or not, reuses its binding.
class CallableBinder {
 public:
  CallableBinder(const Replica& replica, LaunchPlan& plan) : replica_(replica), plan_(plan) {}

  // With a worklist, not recursion: a chain of thousands of callable programs, each calling the
  // next, must not use up the plan thread's stack.
  absl::Status Resolve(BoundProgram& first) {
    std::vector<BoundProgram*> pending{&first};
    while (!pending.empty()) {
      BoundProgram& caller = *pending.back();
      pending.pop_back();
      for (BoundProgram::Callable& c : caller.callables) {
        if (c.program == 0) continue;  // calling it fails, naming the variable (callable.cc)
        Key key{c.program, caller.kind, caller.outer};
        if (auto it = bound_.find(key); it != bound_.end()) {
          c.target = it->second;
          continue;
        }
        absl::StatusOr<BoundProgram> b =
            Bind(replica_, caller.kind, c.program, caller.outer, plan_.attributes, true);
        if (!b.ok()) {
          return absl::Status(
              b.status().code(),
              absl::StrCat(caller.name, ", rtCallableProgram '",
                           caller.module->variables()[c.var].name, "': ", b.status().message()));
        }
        plan_.programs.push_back(std::move(*b));  // a deque: bindings keep their addresses
        BoundProgram& callee = plan_.programs.back();
        bound_.emplace(std::move(key), &callee);
        c.target = &callee;
        pending.push_back(&callee);
      }
    }
    return absl::OkStatus();
  }

 private:
  using Key = std::tuple<uint64_t, ProgramKind, std::vector<const Scope*>>;
  const Replica& replica_;
  LaunchPlan& plan_;
  std::map<Key, const BoundProgram*> bound_;
};

// Resolves every graph node once, so traversal never searches the replica.
void IndexNodes(LaunchPlan& plan) {
  const Replica& r = *plan.replica;
  // Only scenes this plan built or checked: a cached one that no object variable reaches may
  // hold geometries of instances since changed, pointing into an earlier, freed plan.
  auto scene = [&](uint64_t id) -> const SceneEntry* {
    const SceneEntry* e = plan.scenes->Find(id);
    return e != nullptr && e->plan_serial == plan.serial ? e : nullptr;
  };
  for (const auto& [id, g] : r.geometry_groups) {
    NodeInfo& n = plan.nodes[id];
    n.type = RT_OBJECTTYPE_GEOMETRY_GROUP;
    n.scene = scene(id);
  }
  for (const auto& [id, g] : r.groups) {
    NodeInfo& n = plan.nodes[id];
    n.type = RT_OBJECTTYPE_GROUP;
    n.scene = scene(id);
  }
  for (const auto& [id, s] : r.selectors) {
    NodeInfo& n = plan.nodes[id];
    n.type = RT_OBJECTTYPE_SELECTOR;
    auto v = plan.visits.find(id);
    n.visit = v == plan.visits.end() ? nullptr : v->second;
    n.children = s.children;
  }
  for (const auto& [id, t] : r.transforms) {
    NodeInfo& n = plan.nodes[id];
    n.type = RT_OBJECTTYPE_TRANSFORM;
    n.transform = &t;
  }
  for (auto& [id, n] : plan.nodes) {
    if (n.transform != nullptr) n.child = plan.Node(n.transform->child.id);
    for (const NodeRef& c : n.children) n.child_nodes.push_back(plan.Node(c.id));
    if (n.type == RT_OBJECTTYPE_GROUP && n.scene != nullptr) {
      for (const auto& c : n.scene->children) c->node = plan.Node(c->child.id);
    }
  }
}

// Bytes of one material index in RTformat `format`, or 0 for a format that cannot hold one.
unsigned MaterialIndexBytes(uint32_t format) {
  switch (format) {
    case RT_FORMAT_UNSIGNED_BYTE:
      return 1;
    case RT_FORMAT_UNSIGNED_SHORT:
      return 2;
    case RT_FORMAT_UNSIGNED_INT:
      return 4;
    default:
      return 0;
  }
}

// Resolves the per-triangle material indices of built-in triangles and checks every one against
// the instance's materials, so that a hit reads its material without a check.
absl::Status PlanMaterialIndices(const Replica& r, uint64_t instance_id, const InstanceRec& gi,
                                 const GeometryRec& g, InstancePlan& ip) {
  const v1::TriangleMesh& m = g.mesh;
  const std::string what =
      absl::StrCat("geometry triangles #", gi.geometry, " of instance #", instance_id);
  if (m.material_index_buffer() == 0) return absl::OkStatus();
  const BufferRec* b = r.Find(r.buffers, m.material_index_buffer());
  if (b == nullptr) {
    return absl::NotFoundError(
        absl::StrCat(what, ": material index buffer #", m.material_index_buffer(), " is unknown"));
  }
  const unsigned bytes = MaterialIndexBytes(m.material_index_format());
  if (bytes == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(what, ": material index format ", m.material_index_format(),
                     " is not RT_FORMAT_UNSIGNED_BYTE, _SHORT or _INT"));
  }
  const uint64_t stride = m.material_index_stride() != 0 ? m.material_index_stride() : bytes;
  const uint64_t n = g.primitive_count;
  if (stride < bytes || !StridedFits(b->data.size(), m.material_index_offset(), n, stride, bytes)) {
    return absl::OutOfRangeError(
        absl::StrCat(what, ": ", n, " material indices of ", bytes, " bytes every ", stride,
                     " from byte ", m.material_index_offset(), " do not fit buffer #",
                     m.material_index_buffer(), " (", b->data.size(), " bytes)"));
  }
  ip.material_indices = b->data.data() + m.material_index_offset();
  ip.material_index_stride = stride;
  ip.material_index_bytes = bytes;
  ip.material_index_buffer = m.material_index_buffer();
  for (uint64_t i = 0; i < n; ++i) {
    if (unsigned k = ip.StoredMaterial(static_cast<unsigned>(i)); k >= gi.materials.size()) {
      ip.material_indices = nullptr;
      return absl::OutOfRangeError(absl::StrCat(what, ": triangle ", i, " has material index ", k,
                                                " but the instance has ", gi.materials.size(),
                                                " materials"));
    }
  }
  return absl::OkStatus();
}

}  // namespace

void MaterialOutOfRange(const InstancePlan& ip, unsigned primitive, unsigned material) {
  const std::string why =
      ip.material_indices == nullptr
          ? std::string()
          : absl::StrCat(" (material index buffer #", ip.material_index_buffer,
                         " changed after the launch's plan checked it: did a program write it?)");
  throw FatalError{absl::OutOfRangeError(
      absl::StrCat("geometry triangles #", ip.geometry, " of instance #", ip.id, ": triangle ",
                   primitive, " has material index ", material, " but the instance has ",
                   ip.materials.size(), " materials", why))};
}

unsigned InstancePlan::IndexedMaterial(unsigned primitive) const {
  const unsigned char* p = material_indices + size_t{primitive} * material_index_stride;
  if (material_index_bytes == 1) return *p;
  if (material_index_bytes == 2) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

bool LaunchPlan::ExceptionEnabled(unsigned code) const {
  if (code >= RT_EXCEPTION_USER) return user_exceptions;
  if (code < RT_EXCEPTION_PROGRAM_ID_INVALID || code > RT_EXCEPTION_INTERNAL_ERROR) return false;
  return (exception_mask >> (code - RT_EXCEPTION_PROGRAM_ID_INVALID)) & 1u;
}

uint32_t LaunchPlan::NodeType(uint64_t id) const {
  if (replica->groups.count(id)) return RT_OBJECTTYPE_GROUP;
  if (replica->geometry_groups.count(id)) return RT_OBJECTTYPE_GEOMETRY_GROUP;
  if (replica->transforms.count(id)) return RT_OBJECTTYPE_TRANSFORM;
  if (replica->selectors.count(id)) return RT_OBJECTTYPE_SELECTOR;
  return 0;
}

namespace {
std::atomic<uint64_t> g_next_serial{1};
}  // namespace

bool RefreshValues(LaunchPlan& plan, SceneCache& scenes) {
  for (const ModuleInvariants& inv : plan.invariants) {
    for (const ModuleInvariants::Merged& m : inv.merged) {
      if (std::memcmp(m.kept, m.other, m.size) != 0) return false;
    }
  }
  const uint64_t serial = g_next_serial++;
  scenes.Reserial(plan.serial, serial);
  plan.serial = serial;
  plan.generation = plan.replica->generation();
  return true;
}

absl::StatusOr<std::unique_ptr<LaunchPlan>> MakePlan(const Replica& replica, SceneCache& scenes,
                                                     const std::atomic<bool>* cancel) {
  auto plan = std::make_unique<LaunchPlan>();
  plan->serial = g_next_serial++;
  plan->generation = replica.generation();
  plan->structure_generation = replica.structure_generation();
  plan->bindings_generation = replica.bindings_generation();
  plan->replica = &replica;
  plan->scenes = &scenes;
  const ContextRec& ctx = replica.context();
  plan->max_depth = std::clamp<uint64_t>(ctx.stack_size / kStackBytesPerTrace, 1, kMaxTraceDepth);
  plan->ray_type_count = ctx.ray_type_count;
  plan->exception_mask = ctx.exception_mask;
  plan->accuracy_flags = ctx.accuracy_flags;
  plan->user_exceptions = ctx.user_exceptions;
  plan->print_enabled = ctx.print_enabled;
  plan->print_index = ctx.print_index;
  plan->print_buffer_size = ctx.print_buffer_size;

  PlanTextures(replica, plan->textures);

  CallableBinder callables(replica, *plan);
  auto bind = [&](ProgramKind kind, uint64_t id,
                  std::vector<const Scope*> scopes) -> absl::StatusOr<const BoundProgram*> {
    if (id == 0) return nullptr;
    absl::StatusOr<BoundProgram> b = Bind(replica, kind, id, scopes, plan->attributes);
    if (!b.ok()) return b.status();
    plan->programs.push_back(std::move(*b));
    BoundProgram& bound = plan->programs.back();
    if (absl::Status s = callables.Resolve(bound); !s.ok()) return s;
    return &bound;
  };
  const Scope* context_scope = &ctx.vars;
  auto bind_all = [&](ProgramKind kind, const std::vector<uint64_t>& ids,
                      std::vector<const BoundProgram*>& out) -> absl::Status {
    for (uint64_t id : ids) {
      absl::StatusOr<const BoundProgram*> b = bind(kind, id, {context_scope});
      if (!b.ok()) return b.status();
      out.push_back(*b);
    }
    return absl::OkStatus();
  };
  if (auto s = bind_all(ProgramKind::kRayGeneration, ctx.ray_generation, plan->ray_generation);
      !s.ok()) {
    return s;
  }
  if (auto s = bind_all(ProgramKind::kException, ctx.exception, plan->exception); !s.ok()) return s;
  if (auto s = bind_all(ProgramKind::kMiss, ctx.miss, plan->miss); !s.ok()) return s;

  std::vector<uint64_t> roots;
  // Visit programs search their own scope, then the selector's (Table 5: no context).
  for (const auto& [id, sel] : replica.selectors) {
    absl::StatusOr<const BoundProgram*> visit = bind(ProgramKind::kVisit, sel.visit, {&sel.vars});
    if (!visit.ok()) {
      plan->node_problems.emplace(id, visit.status());
    } else if (*visit == nullptr) {
      plan->node_problems.emplace(id, absl::FailedPreconditionError(
                                          absl::StrCat("selector #", id, " has no visit program")));
    } else {
      plan->visits.emplace(id, *visit);
    }
    CollectRoots(sel.vars, roots);
  }
  CollectRoots(ctx.vars, roots);
  for (const auto& [id, p] : replica.programs) CollectRoots(p.vars, roots);

  // Plans one instance. An instance no graph reaches any more stays on the device (the host
  // removes objects only when they are destroyed) and must not fail launches: what is wrong with
  // it becomes its `problem`, reported when a scene holds it.
  auto plan_instance = [&](uint64_t id, const InstanceRec& gi, InstancePlan& ip) -> absl::Status {
    const GeometryRec* g = replica.Find(replica.geometries, gi.geometry);
    if (g == nullptr) {
      return absl::NotFoundError(
          absl::StrCat("geometry instance #", id, " has no geometry on the device"));
    }
    CollectRoots(g->vars, roots);
    if (g->builtin_triangles) {
      ip.builtin_triangles = true;
      ip.primitive_index_offset = g->mesh.primitive_index_offset();
      ip.geometry = gi.geometry;
      auto attr = bind(ProgramKind::kAttribute, g->mesh.attribute_program(),
                       {&gi.vars, &g->vars, context_scope});
      if (!attr.ok()) return attr.status();
      ip.attribute = *attr;
      if (absl::Status s = PlanMaterialIndices(replica, id, gi, *g, ip); !s.ok()) return s;
    } else {
      auto is =
          bind(ProgramKind::kIntersection, g->intersection, {&gi.vars, &g->vars, context_scope});
      if (!is.ok()) return is.status();
      auto bb = bind(ProgramKind::kBoundingBox, g->bounds, {&gi.vars, &g->vars, context_scope});
      if (!bb.ok()) return bb.status();
      ip.intersection = *is;
      ip.bounds = *bb;
    }
    for (uint64_t mid : gi.materials) {
      const MaterialRec* m = replica.Find(replica.materials, mid);
      if (m == nullptr) {
        return absl::NotFoundError(
            absl::StrCat("geometry instance #", id, " uses unknown material #", mid));
      }
      CollectRoots(m->vars, roots);
      // Hit groups for the ray types the material has programs for, not for the context's
      // count of them: that may be anything up to 2^32.
      const size_t types =
          std::min<size_t>(ctx.ray_type_count, std::max(m->closest_hit.size(), m->any_hit.size()));
      std::vector<HitGroup> groups(types);
      for (uint32_t rt = 0; rt < types; ++rt) {
        uint64_t ch = rt < m->closest_hit.size() ? m->closest_hit[rt] : 0;
        uint64_t ah = rt < m->any_hit.size() ? m->any_hit[rt] : 0;
        auto chb = bind(ProgramKind::kClosestHit, ch, {&gi.vars, &m->vars, context_scope});
        if (!chb.ok()) return chb.status();
        auto ahb = bind(ProgramKind::kAnyHit, ah, {&gi.vars, &m->vars, context_scope});
        if (!ahb.ok()) return ahb.status();
        // Calling an empty any-hit program can change nothing: leaving it out spares the
        // geometry its filter callback and keeps its builder's full quality.
        const BoundProgram* any_hit =
            *ahb != nullptr && EmptyProgramCode((*ahb)->function) ? nullptr : *ahb;
        groups[rt] = HitGroup{*chb, any_hit};
        ip.has_any_hit = ip.has_any_hit || any_hit != nullptr;
        if (any_hit != nullptr) ip.any_hit_types |= uint64_t{1} << std::min(rt, 63u);
      }
      ip.materials.push_back(std::move(groups));
    }
    return absl::OkStatus();
  };
  for (const auto& [id, gi] : replica.instances) {
    InstancePlan ip;
    ip.id = id;
    ip.problem = plan_instance(id, gi, ip);
    CollectRoots(gi.vars, roots);
    plan->instances.emplace(id, std::move(ip));
  }
  PlanBindless(
      replica, context_scope, plan->attributes,
      [&](BoundProgram b) -> absl::StatusOr<const BoundProgram*> {
        plan->programs.push_back(std::move(b));
        BoundProgram& bound = plan->programs.back();
        if (absl::Status s = callables.Resolve(bound); !s.ok()) return s;
        return &bound;
      },
      plan->bindless);
  SplitInvariants(*plan);
  plan->attribute_bytes = plan->attributes.used();
  plan->barycentrics_offset = plan->attributes.Find(kTriangleBarycentrics);
  plan->bind_problems = plan->node_problems;
  plan->roots = std::move(roots);
  if (absl::Status s = scenes.Update(*plan, plan->roots, cancel); !s.ok()) return s;
  IndexNodes(*plan);
  return plan;
}

absl::Status RefreshGraph(LaunchPlan& plan, SceneCache& scenes, const std::atomic<bool>* cancel) {
  // A new serial: scenes the update checks are stamped with it, and threads drop what they
  // cached of the nodes.
  plan.serial = g_next_serial++;
  plan.structure_generation = plan.replica->structure_generation();
  plan.nodes.clear();
  plan.node_problems = plan.bind_problems;
  if (absl::Status s = scenes.Update(plan, plan.roots, cancel); !s.ok()) return s;
  IndexNodes(plan);
  return absl::OkStatus();
}

}  // namespace tessera::worker
