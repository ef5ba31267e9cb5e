// Robustness of a device against malformed, inconsistent and out-of-order messages: a small valid
// scene is mutated with protobuf reflection, thousands of times from a fixed seed, and fed to
// in-process devices. Every call must return a status (an error names what it rejects), nothing
// may crash, hang or throw, and a rejected delta must leave the device rendering what it rendered
// before (state.proto: "Applied atomically"). The bugs this found have tests of their own below,
// so that they stay covered whatever a changed seed explores.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <iterator>
#include <limits>
#include <mutex>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <typeinfo>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/message.h"
#include "tessera/rt.h"
#include "tessera/scheduler/tiling.h"
#include "tessera/worker/inproc_device.h"
#include "testdata/replica_fuzz_scene.h"
#include "testdata/write_index_delta.h"

namespace tessera::fuzz {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// ---- Mutations through reflection.

// One field of a message in the tree, or one element of a repeated field.
struct Site {
  Message* message;
  const FieldDescriptor* field;
  int index;  // element of a repeated field; -1: the field as a whole
  std::string path;
};

void CollectSites(Message* m, const std::string& prefix, std::vector<Site>* out) {
  const Reflection* r = m->GetReflection();
  const auto* d = m->GetDescriptor();
  for (int i = 0; i < d->field_count(); ++i) {
    const FieldDescriptor* f = d->field(i);
    const std::string path = prefix + f->name();
    if (f->is_map()) continue;  // in an order protobuf randomizes per process: Mutator::Property
    if (f->is_repeated()) {
      out->push_back({m, f, -1, path});
      for (int k = 0; k < r->FieldSize(*m, f); ++k) {
        const std::string element = absl::StrCat(path, "[", k, "]");
        if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
          CollectSites(r->MutableRepeatedMessage(m, f, k), element + ".", out);
        } else {
          out->push_back({m, f, k, element});
        }
      }
    } else if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (!r->HasField(*m, f)) continue;
      out->push_back({m, f, -1, path});
      CollectSites(r->MutableMessage(m, f), path + ".", out);
    } else if (f->containing_oneof() == nullptr || r->HasField(*m, f)) {
      out->push_back({m, f, -1, path});
    }
  }
}

bool IsScalar(const Site& s) {
  return s.field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE &&
         (s.index >= 0 || !s.field->is_repeated());
}

// Fields that hold object ids.
bool IsReference(const Site& s) {
  static const std::set<std::string> kNames = {
      "id",        "object_id",    "ray_generation",       "exception", "miss",
      "buffer_id", "geometry",     "intersection_program", "materials", "closest_hit",
      "any_hit",   "acceleration", "bounding_box_program", "children",  "visit_program",
      "removed"};
  return s.field->cpp_type() == FieldDescriptor::CPPTYPE_UINT64 && IsScalar(s) &&
         kNames.count(s.field->name()) != 0;
}

class Mutator {
 public:
  explicit Mutator(std::mt19937& rng) : rng_(rng) {}

  // One random mutation of `m`; returns what it did.
  std::string Mutate(Message& m) {
    std::vector<Site> sites;
    CollectSites(&m, "", &sites);
    for (int attempt = 0; attempt < 20; ++attempt) {
      std::string done;
      switch (Pick(11)) {
        case 0:
        case 1:
          done = Extreme(Choose(sites, IsScalar));
          break;
        case 2:
          done = Clear(Choose(sites, [](const Site& s) { return s.index < 0; }));
          break;
        case 3:
          done = DeleteElement(Choose(sites, [](const Site& s) { return s.index < 0; }));
          break;
        case 4:
          done = DuplicateElement(Choose(sites, [](const Site& s) { return s.index < 0; }));
          break;
        case 5:
        case 6:
          done = Reference(Choose(sites, IsReference));
          break;
        case 7:
          done = SwapIds(m);
          break;
        case 8:
          done = Truncate(Choose(sites, [](const Site& s) {
            return IsScalar(s) && s.field->cpp_type() == FieldDescriptor::CPPTYPE_STRING;
          }));
          break;
        case 9:
          done = ChangeKind(m);
          break;
        case 10:
          done = Property(m);
          break;
      }
      if (!done.empty()) return done;
    }
    return "nothing";
  }

 private:
  uint64_t Pick(uint64_t n) { return std::uniform_int_distribution<uint64_t>(0, n - 1)(rng_); }
  template <typename T>
  T PickOf(std::initializer_list<T> values) {
    return *(values.begin() + Pick(values.size()));
  }
  template <typename Pred>
  const Site* Choose(const std::vector<Site>& sites, Pred pred) {
    std::vector<const Site*> fit;
    for (const Site& s : sites) {
      if (pred(s)) fit.push_back(&s);
    }
    return fit.empty() ? nullptr : fit[Pick(fit.size())];
  }

  static uint64_t GetU64(const Site& s) {
    const Reflection* r = s.message->GetReflection();
    return s.index >= 0 ? r->GetRepeatedUInt64(*s.message, s.field, s.index)
                        : r->GetUInt64(*s.message, s.field);
  }
  static void SetU64(const Site& s, uint64_t v) {
    const Reflection* r = s.message->GetReflection();
    s.index >= 0 ? r->SetRepeatedUInt64(s.message, s.field, s.index, v)
                 : r->SetUInt64(s.message, s.field, v);
  }

  std::string Extreme(const Site* s) {
    if (s == nullptr) return "";
    const Reflection* r = s->message->GetReflection();
    Message* m = s->message;
    const FieldDescriptor* f = s->field;
    const int i = s->index;
    switch (f->cpp_type()) {
      case FieldDescriptor::CPPTYPE_UINT64: {
        const uint64_t old = GetU64(*s);
        const uint64_t v = PickOf<uint64_t>(
            {0, 1, 2, 3, 0xFFFFFFFFu, uint64_t{1} << 32, uint64_t{1} << 40, uint64_t{1} << 62,
             ~uint64_t{0}, ~uint64_t{0} - 1, uint64_t(-16), old + 1, old - 1, old * 2});
        SetU64(*s, v);
        return absl::StrCat(s->path, " = ", v);
      }
      case FieldDescriptor::CPPTYPE_UINT32: {
        const uint32_t old = i >= 0 ? r->GetRepeatedUInt32(*m, f, i) : r->GetUInt32(*m, f);
        uint32_t v =
            PickOf<uint32_t>({0, 1, 2, 3, 0x3EE, 0x400, 1u << 31, ~0u, ~0u - 1, old + 1, old - 1});
        if (f->name() == "type" && Pick(2) == 0) {  // another RTobjecttype
          v = RT_OBJECTTYPE_UNKNOWN +
              static_cast<uint32_t>(Pick(RT_OBJECTTYPE_PROGRAM + 1 - RT_OBJECTTYPE_UNKNOWN));
        }
        i >= 0 ? r->SetRepeatedUInt32(m, f, i, v) : r->SetUInt32(m, f, v);
        return absl::StrCat(s->path, " = ", v);
      }
      case FieldDescriptor::CPPTYPE_INT32: {
        const int32_t v = PickOf<int32_t>({0, 1, -1, -2, 2, std::numeric_limits<int32_t>::min(),
                                           std::numeric_limits<int32_t>::max()});
        i >= 0 ? r->SetRepeatedInt32(m, f, i, v) : r->SetInt32(m, f, v);
        return absl::StrCat(s->path, " = ", v);
      }
      case FieldDescriptor::CPPTYPE_FLOAT: {
        const float v = PickOf<float>(
            {0.f, -0.f, 1.f, -1.f, std::nanf(""), INFINITY, -INFINITY, 1e38f, -1e38f, 1e-40f});
        i >= 0 ? r->SetRepeatedFloat(m, f, i, v) : r->SetFloat(m, f, v);
        return absl::StrCat(s->path, " = ", v);
      }
      case FieldDescriptor::CPPTYPE_BOOL: {
        const bool v = !(i >= 0 ? r->GetRepeatedBool(*m, f, i) : r->GetBool(*m, f));
        i >= 0 ? r->SetRepeatedBool(m, f, i, v) : r->SetBool(m, f, v);
        return absl::StrCat(s->path, " = ", v);
      }
      case FieldDescriptor::CPPTYPE_STRING: {
        std::string v = i >= 0 ? r->GetRepeatedString(*m, f, i) : r->GetString(*m, f);
        switch (Pick(4)) {
          case 0:
            v.clear();
            break;
          case 1:
            v += '\xff';
            break;
          case 2:
            if (!v.empty()) v[Pick(v.size())] ^= static_cast<char>(1 + Pick(255));
            break;
          case 3:
            v += v;
            break;
        }
        i >= 0 ? r->SetRepeatedString(m, f, i, v) : r->SetString(m, f, v);
        return absl::StrCat(s->path, " = '", v.substr(0, 40), "' (", v.size(), " bytes)");
      }
      default:
        return "";
    }
  }

  std::string Clear(const Site* s) {
    if (s == nullptr) return "";
    s->message->GetReflection()->ClearField(s->message, s->field);
    return "clear " + s->path;
  }

  std::string DeleteElement(const Site* s) {
    if (s == nullptr || !s->field->is_repeated()) return "";
    const Reflection* r = s->message->GetReflection();
    const int n = r->FieldSize(*s->message, s->field);
    if (n == 0) return "";
    const int k = static_cast<int>(Pick(n));
    for (int j = k; j + 1 < n; ++j) r->SwapElements(s->message, s->field, j, j + 1);
    r->RemoveLast(s->message, s->field);
    return absl::StrCat("delete ", s->path, "[", k, "]");
  }

  std::string DuplicateElement(const Site* s) {
    if (s == nullptr || !s->field->is_repeated()) return "";
    const Reflection* r = s->message->GetReflection();
    Message* m = s->message;
    const FieldDescriptor* f = s->field;
    const int n = r->FieldSize(*m, f);
    if (n == 0) return "";
    const int k = static_cast<int>(Pick(n));
    switch (f->cpp_type()) {
      case FieldDescriptor::CPPTYPE_MESSAGE: {
        std::unique_ptr<Message> copy(r->GetRepeatedMessage(*m, f, k).New());
        copy->CopyFrom(r->GetRepeatedMessage(*m, f, k));
        r->AddMessage(m, f)->CopyFrom(*copy);
        break;
      }
      case FieldDescriptor::CPPTYPE_UINT64:
        r->AddUInt64(m, f, r->GetRepeatedUInt64(*m, f, k));
        break;
      case FieldDescriptor::CPPTYPE_INT32:
        r->AddInt32(m, f, r->GetRepeatedInt32(*m, f, k));
        break;
      case FieldDescriptor::CPPTYPE_FLOAT:
        r->AddFloat(m, f, r->GetRepeatedFloat(*m, f, k));
        break;
      default:
        return "";
    }
    return absl::StrCat("duplicate ", s->path, "[", k, "]");
  }

  // An id field pointed at another object (of any kind) or at none the device knows.
  std::string Reference(const Site* s) {
    if (s == nullptr) return "";
    const uint64_t v =
        Pick(3) == 0 ? PickOf<uint64_t>({0, kLastId + 1, 1000, ~uint64_t{0}}) : 1 + Pick(kLastId);
    SetU64(*s, v);
    return absl::StrCat(s->path, " = #", v);
  }

  static Message* ObjectBody(v1::Object& o) {
    const Reflection* r = o.GetReflection();
    const FieldDescriptor* f = r->GetOneofFieldDescriptor(o, o.GetDescriptor()->oneof_decl(0));
    return f == nullptr ? nullptr : r->MutableMessage(&o, f);
  }

  std::string SwapIds(Message& m) {
    auto* delta = dynamic_cast<v1::StateDelta*>(&m);
    if (delta == nullptr || delta->objects_size() < 2) return "";
    const int a = static_cast<int>(Pick(delta->objects_size()));
    const int b = static_cast<int>(Pick(delta->objects_size()));
    Message* x = ObjectBody(*delta->mutable_objects(a));
    Message* y = ObjectBody(*delta->mutable_objects(b));
    if (a == b || x == nullptr || y == nullptr) return "";
    const FieldDescriptor* fx = x->GetDescriptor()->FindFieldByName("id");
    const FieldDescriptor* fy = y->GetDescriptor()->FindFieldByName("id");
    const uint64_t ix = x->GetReflection()->GetUInt64(*x, fx);
    const uint64_t iy = y->GetReflection()->GetUInt64(*y, fy);
    x->GetReflection()->SetUInt64(x, fx, iy);
    y->GetReflection()->SetUInt64(y, fy, ix);
    return absl::StrCat("swap ids of objects[", a, "] and objects[", b, "]");
  }

  std::string Truncate(const Site* s) {
    if (s == nullptr) return "";
    const Reflection* r = s->message->GetReflection();
    std::string v = s->index >= 0 ? r->GetRepeatedString(*s->message, s->field, s->index)
                                  : r->GetString(*s->message, s->field);
    if (v.empty()) return "";
    v.resize(Pick(v.size()));
    s->index >= 0 ? r->SetRepeatedString(s->message, s->field, s->index, v)
                  : r->SetString(s->message, s->field, v);
    return absl::StrCat("truncate ", s->path, " to ", v.size(), " bytes");
  }

  // An object becomes one of another kind with the same id (a buffer where a program was).
  std::string ChangeKind(Message& m) {
    auto* delta = dynamic_cast<v1::StateDelta*>(&m);
    if (delta == nullptr || delta->objects_size() == 0) return "";
    const int k = static_cast<int>(Pick(delta->objects_size()));
    v1::Object& o = *delta->mutable_objects(k);
    Message* body = ObjectBody(o);
    if (body == nullptr) return "";
    const uint64_t id = body->GetReflection()->GetUInt64(*body, body->GetDescriptor()->field(0));
    const auto* oneof = o.GetDescriptor()->oneof_decl(0);
    const FieldDescriptor* kind = oneof->field(static_cast<int>(Pick(oneof->field_count())));
    Message* fresh = o.GetReflection()->MutableMessage(&o, kind);
    fresh->GetReflection()->SetUInt64(fresh, fresh->GetDescriptor()->field(0), id);
    return absl::StrCat("objects[", k, "] becomes an empty ", kind->name(), " #", id);
  }

  // An acceleration property set to what is no stride, or no buffer's name, or removed.
  std::string Property(Message& m) {
    auto* delta = dynamic_cast<v1::StateDelta*>(&m);
    if (delta == nullptr) return "";
    std::vector<v1::Acceleration*> accelerations;
    for (v1::Object& o : *delta->mutable_objects()) {
      if (o.has_acceleration()) accelerations.push_back(o.mutable_acceleration());
    }
    if (accelerations.empty()) return "";
    v1::Acceleration* a = accelerations[Pick(accelerations.size())];
    const std::string key =
        PickOf<const char*>({"vertex_buffer_name", "index_buffer_name", "vertex_buffer_stride",
                             "index_buffer_stride", "refit"});
    if (Pick(4) == 0) {
      a->mutable_properties()->erase(key);
      return absl::StrCat("erase property ", key, " of acceleration #", a->id());
    }
    const std::string value =
        PickOf<const char*>({"", "0", "1", "11", "12", "24", "-12", "1v", "99999999999999999999",
                             "4294967296", "vertices", "indices", "output"});
    (*a->mutable_properties())[key] = value;
    return absl::StrCat("acceleration #", a->id(), " property ", key, " = '", value, "'");
  }

  std::mt19937& rng_;
};

// Mutations of a launch request that the generic ones reach rarely: tiles outside the grid or of
// the wrong dimensionality, dims of zero or past 32 bits, entry points out of range.
std::string MutateRequest(v1::LaunchRequest& r, std::mt19937& rng, Mutator& generic) {
  auto pick = [&](uint64_t n) { return std::uniform_int_distribution<uint64_t>(0, n - 1)(rng); };
  const uint64_t kHuge[] = {0,           1, 0xFFFFFFFFu, uint64_t{1} << 32, (uint64_t{1} << 32) + 1,
                            ~uint64_t{0}};
  auto huge = [&] { return kHuge[pick(std::size(kHuge))]; };
  switch (pick(9)) {
    case 0:
      r.set_session_id(pick(2) ? kSession + 1 : 0);
      return absl::StrCat("session_id = ", r.session_id());
    case 1:
      r.set_entry_point(pick(2) ? 2 : ~0u);
      return absl::StrCat("entry_point = ", r.entry_point());
    case 2:
      if (r.dims_size() == 0) return "";
      r.set_dims(static_cast<int>(pick(r.dims_size())), huge());
      return "dims = " + absl::StrJoin(r.dims(), "x");
    case 3: {
      v1::Tile* t = r.add_tiles();
      t->set_index(r.tiles_size() - 1);
      t->add_origin(pick(2) ? kWidth + pick(4) : huge());
      t->add_origin(pick(kHeight));
      t->add_size(4);
      t->add_size(4);
      return absl::StrCat("tile at (", t->origin(0), ", ", t->origin(1), ")");
    }
    case 4: {
      if (r.tiles_size() == 0) return "";
      *r.add_tiles() = r.tiles(static_cast<int>(pick(r.tiles_size())));
      return "duplicate tile";
    }
    case 5: {
      if (r.tiles_size() == 0) return "";
      v1::Tile* t = r.mutable_tiles(static_cast<int>(pick(r.tiles_size())));
      if (pick(2) && t->origin_size() > 0 && t->size_size() > 0) {
        t->mutable_origin()->RemoveLast();
        t->mutable_size()->RemoveLast();
      } else {
        t->add_origin(pick(2));
        t->add_size(pick(3));
      }
      return absl::StrCat("tile ", t->index(), " with ", t->origin_size(), " dimensions");
    }
    case 6: {
      if (r.tiles_size() == 0) return "";
      v1::Tile* t = r.mutable_tiles(static_cast<int>(pick(r.tiles_size())));
      auto* field = pick(2) ? t->mutable_size() : t->mutable_origin();
      if (field->empty()) return "";
      field->Set(static_cast<int>(pick(field->size())), huge());
      return absl::StrCat("tile ", t->index(), " origin ", absl::StrJoin(t->origin(), ","),
                          " size ", absl::StrJoin(t->size(), ","));
    }
    case 7:
      if (pick(2)) {
        r.add_dims(pick(3));
        r.add_dims(1);
      } else {
        r.clear_dims();
      }
      return absl::StrCat("launch of ", r.dims_size(), " dimensions");
    default:
      return "request: " + generic.Mutate(r);
  }
}

// Which launch indices of the valid 8x6 grid a request's tiles cover (tiles of two dimensions).
std::set<uint64_t> Covered(const v1::LaunchRequest& r) {
  std::set<uint64_t> covered;
  for (const v1::Tile& t : r.tiles()) {
    const uint64_t x0 = t.origin(0), y0 = t.origin(1);
    const uint64_t x1 = x0 >= kWidth ? x0 : std::min(kWidth, x0 + std::min(t.size(0), kWidth));
    const uint64_t y1 = y0 >= kHeight ? y0 : std::min(kHeight, y0 + std::min(t.size(1), kHeight));
    for (uint64_t y = y0; y < y1; ++y) {
      for (uint64_t x = x0; x < x1; ++x) covered.insert(y * kWidth + x);
    }
  }
  return covered;
}

// Whether the delta runs the bounding box program as a program of another kind. It writes six
// floats through its second argument, which other kinds are not passed: like a program of the
// wrong signature in OptiX, that is undefined, and no message can tell (modules do not record
// signatures), so the fuzzing leaves it out.
bool RunsBoundsProgramAsAnotherKind(const v1::StateDelta& d) {
  std::set<uint64_t> bounds;
  bool replaced = false;  // the delta sends program kBounds again
  for (const v1::Object& o : d.objects()) {
    if (!o.has_program()) continue;
    if (o.program().function() == "sphere_bounds") bounds.insert(o.program().id());
    replaced = replaced || o.program().id() == kBounds;
  }
  if (!replaced) bounds.insert(kBounds);
  auto any = [&](const auto& ids) {
    for (uint64_t id : ids) {
      if (bounds.count(id) != 0) return true;
    }
    return false;
  };
  const v1::ContextState& c = d.context();
  bool found = any(c.ray_generation()) || any(c.exception()) || any(c.miss());
  for (const v1::Object& o : d.objects()) {
    found =
        found || (o.has_geometry() && bounds.count(o.geometry().intersection_program()) != 0) ||
        (o.has_material() && (any(o.material().closest_hit()) || any(o.material().any_hit()))) ||
        (o.has_selector() && bounds.count(o.selector().visit_program()) != 0);
  }
  return found;
}

// Whether a buffer of the delta takes more than 256 MiB (contents and write marks) but no more
// than this machine's memory: the device then allocates and clears it, which is right but slow,
// and not what this test is after (BufferTooLargeForTheDeviceIsRejectedAndTheStateKept is).
bool AllocatesALotOfMemory(const v1::StateDelta& d) {
  const uint64_t memory = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
  for (const v1::Object& o : d.objects()) {
    if (!o.has_buffer() || o.buffer().dims_size() == 0) continue;
    const v1::Buffer& b = o.buffer();
    // In doubles: past 2^64 reads as large, which is all this needs.
    double elements = 1;
    for (uint64_t n : b.dims()) elements *= double(n);
    const bool marked = (b.desc() & RT_BUFFER_OUTPUT) != 0 && (b.desc() & RT_BUFFER_GPU_LOCAL) == 0;
    const double bytes = elements * double(b.element_size()) + (marked ? elements : 0);
    if (bytes > double(256 << 20) && bytes <= double(memory)) return true;
  }
  return false;
}

TEST_F(ReplicaFuzz, ValidSceneRendersIndicesTheSphereAndTheTriangle) {
  const float* p = reinterpret_cast<const float*>(reference_[0].data());
  for (uint64_t y = 0; y < kHeight; ++y) {
    for (uint64_t x = 0; x < kWidth; ++x) {
      const float* e = p + 4 * (y * kWidth + x);
      EXPECT_EQ(e[0], x);
      EXPECT_EQ(e[1], y);
      EXPECT_EQ(e[2], kScale);
    }
  }
  const float* camera = reinterpret_cast<const float*>(reference_[1].data());
  const float* center = camera + 4 * (kHeight / 2 * kWidth + kWidth / 2);  // on the sphere
  const float* corner = camera;                                            // misses: blue
  const float* triangle = camera + 4 * (kWidth - 1);                       // bottom right
  EXPECT_GT(center[0], 0.f);
  EXPECT_EQ(corner[0], 0.f);
  EXPECT_EQ(corner[2], 1.f);
  EXPECT_GT(triangle[0], 0.f);  // shaded with the normal the sphere's program reports for it
  EXPECT_LT(triangle[2], 1.f);
}

TEST_F(ReplicaFuzz, MutatedDeltasAndLaunchesFailCleanlyAndKeepTheState) {
  constexpr int kIterations = 6000;
  std::mt19937 rng(20240611);
  Mutator mutator(rng);
  auto pick = [&](uint64_t n) { return std::uniform_int_distribution<uint64_t>(0, n - 1)(rng); };
  // A device holding the valid scene, and the sequence its next delta must carry.
  std::unique_ptr<Device> base = DeviceWith(scene_);
  uint64_t next_sequence = 2;
  int rejected = 0, accepted = 0, skipped = 0, launches_failed = 0, timed_out = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int iteration = 0; iteration < kIterations && !HasFatalFailure(); ++iteration) {
    const uint64_t mode = pick(8);
    std::string what = absl::StrCat("iteration ", iteration, ":");
    if (mode < 6) {
      // A mutated delta onto the device with the valid state (incremental) or a new one (first).
      const bool incremental = mode < 5;
      v1::StateDelta delta = scene_;
      delta.set_sequence(incremental ? next_sequence : 1);
      if (incremental && pick(2)) delta.clear_modules();  // the device has them already
      for (uint64_t n = 1 + pick(3); n > 0; --n) {
        absl::StrAppend(&what, " ", mutator.Mutate(delta), ";");
      }
      if (RunsBoundsProgramAsAnotherKind(delta) || AllocatesALotOfMemory(delta)) {
        ++skipped;
        continue;
      }
      std::unique_ptr<Device> fresh;
      if (!incremental) fresh = CreateInprocDevice(2, /*results_in_rounds=*/pick(2) == 0);
      Device& device = incremental ? *base : *fresh;
      const absl::Status applied = NoThrow(what, [&] { return device.Apply(delta); });
      if (!applied.ok()) {
        ++rejected;
        EXPECT_FALSE(applied.message().empty()) << what;
        if (incremental) {
          ExpectRendersScene(device, what);
          if (pick(4) == 0) {  // the rejected delta did not take its sequence number
            v1::StateDelta valid = scene_;
            valid.set_sequence(next_sequence);
            valid.clear_modules();
            EXPECT_TRUE(device.Apply(valid).ok()) << what << ": valid delta refused afterwards";
            ++next_sequence;
          }
        } else if (pick(4) == 0) {  // the new device holds nothing, and takes the valid scene
          EXPECT_FALSE(RunLaunch(device, ValidRequest(0, ++launch_id_)).status.ok()) << what;
          EXPECT_TRUE(device.Apply(scene_).ok()) << what;
          ExpectRendersScene(device, what);
        }
        continue;
      }
      ++accepted;
      // Whatever state it made must launch or fail with a message, as must a mutated request.
      for (int k = 0; k < 2; ++k) {
        v1::LaunchRequest request = ValidRequest(static_cast<uint32_t>(pick(2)), ++launch_id_);
        std::string launch_what = what;
        if (k == 1) absl::StrAppend(&launch_what, " ", MutateRequest(request, rng, mutator));
        LaunchOutcome out = RunLaunch(device, request);
        timed_out += out.timed_out;
        if (!out.status.ok()) {
          ++launches_failed;
          EXPECT_FALSE(out.status.message().empty()) << launch_what;
        }
      }
      if (incremental) {  // its state is no longer the valid scene
        base = DeviceWith(scene_);
        next_sequence = 2;
      }
    } else {
      // A mutated launch request on the valid state.
      const uint32_t entry = static_cast<uint32_t>(pick(2));
      v1::LaunchRequest request = ValidRequest(entry, ++launch_id_);
      for (uint64_t n = 1 + pick(2); n > 0; --n) {
        absl::StrAppend(&what, " ", MutateRequest(request, rng, mutator), ";");
      }
      LaunchOutcome out = RunLaunch(*base, request);
      timed_out += out.timed_out;
      if (!out.status.ok()) {
        ++launches_failed;
        EXPECT_FALSE(out.status.message().empty()) << what;
      }
      bool plain = entry == 0 && request.entry_point() == 0 && request.dims_size() == 2 &&
                   request.dims(0) == kWidth && request.dims(1) == kHeight;
      for (const v1::Tile& t : request.tiles()) {
        plain = plain && t.origin_size() == 2 && t.size_size() == 2;
      }
      if (out.status.ok() && plain) {
        // Exactly the launch indices of the tiles ran, each writing its own index.
        EXPECT_EQ(out.written, Covered(request)) << what;
        for (uint64_t e : out.written) {
          if (out.output.size() < 16 * (e + 1)) break;
          const float* v = reinterpret_cast<const float*>(out.output.data() + 16 * e);
          EXPECT_EQ(v[0], e % kWidth) << what;
          EXPECT_EQ(v[1], e / kWidth) << what;
        }
      }
      if (!out.status.ok() || out.timed_out) ExpectRendersScene(*base, what);
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "%d iterations in %.1f s: %d deltas rejected, %d accepted, %d left out, %d launches "
      "failed, %d cut short by the watchdog\n",
      kIterations, seconds, rejected, accepted, skipped, launches_failed, timed_out);
  // The mutations must reach both sides, or the test exercises less than it claims.
  EXPECT_GT(rejected, kIterations / 10);
  EXPECT_GT(accepted, kIterations / 20);
}

}  // namespace
}  // namespace tessera::fuzz
