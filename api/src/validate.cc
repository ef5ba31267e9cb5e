#include "validate.h"

#include <algorithm>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/strings/str_cat.h"
#include "acceleration.h"
#include "buffer.h"
#include "buffer_format.h"
#include "context.h"
#include "geometry.h"
#include "nodes.h"
#include "status.h"
#include "tessera/scheduler/device.h"
#include "texture_sampler.h"

namespace tessera::api {
namespace {

// A problem with `object`: the message names it; the code is decided by the caller.
struct Problem {
  bool mapped = false;
  std::string message;
};

std::string Missing(const Object& o, const std::string& what) {
  return absl::StrCat(o.Describe(), ": ", what);
}

// Whether `count` elements laid out as `where` says fit buffer `b`.
bool Fits(const Object* b, const GeometryTriangles::Array& where, uint64_t count) {
  return StridedFits(static_cast<const Buffer*>(b)->byte_size(), where.offset, count, where.stride,
                     where.element_bytes);
}

template <typename Fail>
bool CheckTriangles(const GeometryTriangles& g, Fail&& fail) {
  if (!g.primitive_count_set()) return fail("primitive count is not set");
  if (g.vertex_buffer() == nullptr) return fail("vertices are not set");
  if (!Fits(g.vertex_buffer(), g.vertices(), g.vertex_count())) {
    return fail(absl::StrCat(g.vertex_count(), " vertices every ", g.vertices().stride,
                             " bytes from byte ", g.vertices().offset, " do not fit ",
                             g.vertex_buffer()->Describe()));
  }
  if (g.index_buffer() == nullptr) {
    if (uint64_t{g.primitive_count()} * 3 > g.vertex_count()) {
      return fail(absl::StrCat(g.primitive_count(), " triangles without indices need ",
                               uint64_t{g.primitive_count()} * 3, " vertices, not ",
                               g.vertex_count()));
    }
  } else if (!Fits(g.index_buffer(), g.indices(), g.primitive_count())) {
    return fail(absl::StrCat("the indices of ", g.primitive_count(), " triangles every ",
                             g.indices().stride, " bytes from byte ", g.indices().offset,
                             " do not fit ", g.index_buffer()->Describe()));
  }
  if (g.material_count() > 1 && g.material_index_buffer() == nullptr) {
    return fail(absl::StrCat(g.material_count(), " materials but no material indices"));
  }
  if (g.material_index_buffer() != nullptr &&
      !Fits(g.material_index_buffer(), g.material_indices(), g.primitive_count())) {
    return fail(absl::StrCat("the material indices of ", g.primitive_count(),
                             " triangles do not fit ", g.material_index_buffer()->Describe()));
  }
  return true;
}

// Checks `o` alone (its edges are walked separately).
bool CheckSelf(Object& o, Problem* problem) {
  auto fail = [&](std::string what) {
    problem->message = Missing(o, what);
    return false;
  };
  switch (o.kind()) {
    case Kind::kContext: {
      auto& c = static_cast<Context&>(o);
      for (unsigned i = 0; i < c.entry_point_count(); ++i) {
        if (c.ray_generation(i) == nullptr) {
          return fail(absl::StrCat("entry point ", i, " has no ray generation program"));
        }
      }
      return true;
    }
    case Kind::kBuffer: {
      auto& b = static_cast<Buffer&>(o);
      if (b.format() == RT_FORMAT_UNKNOWN) return fail("format is not set");
      if (b.element_size() == 0) return fail("RT_FORMAT_USER buffer has no element size");
      if (!b.sized()) return fail("size is not set");
      if (b.mapped()) {
        problem->mapped = true;
        return fail("buffer is still mapped (unmap it before validating or launching)");
      }
      return true;
    }
    case Kind::kGeometry: {
      auto& g = static_cast<Geometry&>(o);
      if (g.intersection_program() == nullptr) return fail("intersection program is not set");
      if (g.bounding_box_program() == nullptr) return fail("bounding box program is not set");
      if (!g.primitive_count_set()) return fail("primitive count is not set");
      return true;
    }
    case Kind::kGeometryTriangles:
      return CheckTriangles(static_cast<GeometryTriangles&>(o), fail);
    case Kind::kGeometryInstance: {
      auto& gi = static_cast<GeometryInstance&>(o);
      if (gi.geometry() == nullptr) return fail("geometry is not set");
      if (gi.material_count() == 0) return fail("material count is 0");
      if (gi.geometry()->kind() == Kind::kGeometryTriangles) {
        const unsigned n = static_cast<GeometryTriangles*>(gi.geometry())->material_count();
        if (gi.material_count() != n) {
          return fail(absl::StrCat("material count is ", gi.material_count(), " but its ",
                                   gi.geometry()->Describe(), " has ", n, " materials"));
        }
      }
      for (unsigned i = 0; i < gi.material_count(); ++i) {
        if (gi.material(i) == nullptr) return fail(absl::StrCat("material ", i, " is not set"));
      }
      return true;
    }
    case Kind::kGeometryGroup:
    case Kind::kGroup: {
      auto& n = static_cast<AcceleratedNode&>(o);
      if (n.acceleration() == nullptr) return fail("acceleration is not set");
      for (unsigned i = 0; i < n.child_count(); ++i) {
        if (n.child(i) == nullptr) return fail(absl::StrCat("child ", i, " is not set"));
      }
      return true;
    }
    case Kind::kSelector: {
      auto& s = static_cast<Selector&>(o);
      if (s.visit_program() == nullptr) return fail("visit program is not set");
      for (unsigned i = 0; i < s.child_count(); ++i) {
        if (s.child(i) == nullptr) return fail(absl::StrCat("child ", i, " is not set"));
      }
      return true;
    }
    case Kind::kTransform: {
      auto& t = static_cast<Transform&>(o);
      if (t.child() == nullptr) return fail("child is not set");
      Matrix4 unused;
      if (!Invert(t.matrix(), &unused)) return fail("matrix is not invertible");
      return true;
    }
    case Kind::kAcceleration: {
      absl::Status s = static_cast<Acceleration&>(o).CheckComplete();
      if (!s.ok()) return fail(std::string(s.message()));
      return true;
    }
    case Kind::kTextureSampler: {
      absl::Status s = static_cast<TextureSampler&>(o).CheckComplete();
      if (!s.ok()) return fail(std::string(s.message()));
      return true;
    }
    default:
      return true;
  }
}

// Node children that traversal follows (cycles among them would never terminate).
std::vector<Object*> TraversalChildren(Object& o) {
  std::vector<Object*> out;
  switch (o.kind()) {
    case Kind::kGroup: {
      auto& g = static_cast<Group&>(o);
      for (unsigned i = 0; i < g.child_count(); ++i) out.push_back(g.child(i));
      break;
    }
    case Kind::kSelector: {
      auto& s = static_cast<Selector&>(o);
      for (unsigned i = 0; i < s.child_count(); ++i) out.push_back(s.child(i));
      break;
    }
    case Kind::kTransform:
      out.push_back(static_cast<Transform&>(o).child());
      break;
    default:
      break;
  }
  return out;
}

class Walker {
 public:
  // Visits everything reachable from `root`; stops at the first problem.
  bool Walk(Object& root) {
    std::vector<Object*> stack{&root};
    seen_.insert(&root);
    while (!stack.empty()) {
      Object* o = stack.back();
      stack.pop_back();
      order_.push_back(o);
      bool ok = true;
      o->VisitEdges([&](Object* target, const EdgeRole& role) {
        if (!ok) return;
        if (!target->alive()) {
          problem_.message = absl::StrCat(o->Describe(), ": ", role.Format(),
                                          " refers to destroyed ", target->Describe());
          ok = false;
          return;
        }
        if (seen_.insert(target).second) stack.push_back(target);
      });
      if (!ok || !CheckSelf(*o, &problem_)) return false;
    }
    return CheckCycles();
  }

  const Problem& problem() const { return problem_; }
  const std::vector<Object*>& order() const { return order_; }

 private:
  // Also checks the levels below every node against what devices traverse (kMaxGraphLevels):
  // a node's height is 0 without traversal children, else one more than its highest child's.
  bool CheckCycles() {
    enum Color { kWhite, kGray, kBlack };
    absl::flat_hash_map<Object*, Color> color;
    absl::flat_hash_map<Object*, int> height;
    for (Object* start : order_) {
      if (!IsNodeKind(start->kind()) || color[start] != kWhite) continue;
      // Iterative DFS: (node, next child index).
      // Each frame lists its node's children once: listing them again at every step made a
      // Group of N children cost O(N^2) per launch (1.2 s for 20,000 Transforms).
      struct Frame {
        Object* node;
        std::vector<Object*> children;
        size_t next;
      };
      std::vector<Frame> stack;
      stack.push_back(Frame{start, TraversalChildren(*start), 0});
      color[start] = kGray;
      while (!stack.empty()) {
        Frame& frame = stack.back();
        Object* node = frame.node;
        const std::vector<Object*>& children = frame.children;
        if (frame.next >= children.size()) {
          color[node] = kBlack;
          int h = 0;
          for (Object* child : children) {
            if (child != nullptr) h = std::max(h, height[child] + 1);
          }
          height[node] = h;
          if (h > kMaxGraphLevels) {
            problem_.message =
                absl::StrCat(node->Describe(), ": the graph below it is ", h,
                             " levels deep; devices traverse at most ", kMaxGraphLevels,
                             " levels of groups, selectors and transforms");
            return false;
          }
          stack.pop_back();
          continue;
        }
        Object* child = children[frame.next++];
        if (child == nullptr) continue;
        Color& c = color[child];
        if (c == kGray) {
          problem_.message = absl::StrCat(node->Describe(), ": child ", child->Describe(),
                                          " is also its ancestor (the node graph has a cycle)");
          return false;
        }
        if (c == kWhite) {
          c = kGray;
          stack.push_back(Frame{child, TraversalChildren(*child), 0});  // frame is stale now
        }
      }
    }
    return true;
  }

  absl::flat_hash_set<Object*> seen_;
  std::vector<Object*> order_;
  Problem problem_;
};

absl::Status ToStatus(const Problem& p, RTresult code) {
  return RtError(p.mapped ? RT_ERROR_ALREADY_MAPPED : code, p.message);
}

}  // namespace

absl::Status ValidateContext(Context& context) {
  Walker walker;
  if (!walker.Walk(context)) return ToStatus(walker.problem(), RT_ERROR_INVALID_CONTEXT);
  // Programs reach samplers by id (rtTextureSamplerGetId) without any variable naming them.
  for (const auto& [id, object] : context.objects()) {
    if (object->kind() == Kind::kTextureSampler &&
        static_cast<TextureSampler*>(object)->id_taken() && !walker.Walk(*object)) {
      return ToStatus(walker.problem(), RT_ERROR_INVALID_CONTEXT);
    }
  }
  return absl::OkStatus();
}

const std::vector<Object*>& Context::Reachable() {
  if (reachable_clock_ != structure_clock_) {
    reachable_ = CollectReachable(*this);
    reachable_clock_ = structure_clock_;
  }
  return reachable_;
}

absl::Status Context::ValidateOnce() {
  // Mapping is no change devices see (applications map their output after every launch), but
  // validation reports a mapped buffer it reaches, naming it.
  const bool mapped = std::any_of(objects().begin(), objects().end(), [](const auto& entry) {
    return entry.second->kind() == Kind::kBuffer && static_cast<Buffer*>(entry.second)->mapped();
  });
  if (validated_clock_ == structure_clock_ && !mapped) return absl::OkStatus();
  TS_RETURN_IF_ERROR(ValidateContext(*this));
  validated_clock_ = structure_clock_;
  return absl::OkStatus();
}

absl::Status ValidateObject(Object& object) {
  Walker walker;
  if (!walker.Walk(object)) return ToStatus(walker.problem(), RT_ERROR_INVALID_VALUE);
  return absl::OkStatus();
}

std::vector<Object*> CollectReachable(Context& context) {
  std::vector<Object*> out;
  absl::flat_hash_set<Object*> seen{&context};
  std::vector<Object*> stack{&context};
  while (!stack.empty()) {
    Object* o = stack.back();
    stack.pop_back();
    if (o != &context) out.push_back(o);
    o->VisitEdges([&](Object* target, const EdgeRole&) {
      if (target->alive() && seen.insert(target).second) stack.push_back(target);
    });
  }
  return out;
}

}  // namespace tessera::api
