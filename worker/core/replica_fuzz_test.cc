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
#include <filesystem>
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
#include "tessera/worker/module_cache.h"
#include "testdata/write_index_delta.h"

namespace tessera {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;
using Variables = google::protobuf::RepeatedPtrField<v1::Variable>;

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";
constexpr uint64_t kSession = 1;
constexpr uint64_t kWidth = 8, kHeight = 6;
constexpr float kScale = 3.f;
// A mutated launch may ask for 2^64 launch indices: the watchdog cancels it after this long.
constexpr auto kLaunchLimit = std::chrono::seconds(2);

// The valid scene's objects (testing::WriteIndexDelta makes 1 and 2).
enum : uint64_t {
  kWriteIndex = 1,
  kOutput = 2,
  kCamera,
  kMiss,
  kException,
  kIntersect,
  kBounds,
  kClosestHit,
  kGeometry,
  kMaterial,
  kInstance,
  kGeometryAccel,
  kGeometryGroup,
  kTransform,
  kGroupAccel,
  kGroup,
  kInput,
  kVertices,
  kIndices,
  kTriangleGeometry,
  kTriangleInstance,
  kTriangleAccel,
  kTriangleGroup,
  kLastId = kTriangleGroup,
};

void AddValue(Variables* vars, const std::string& name, uint32_t type, const void* data,
              size_t size) {
  v1::Variable* v = vars->Add();
  v->set_name(name);
  v->set_type(type);
  v->set_data(data, size);
}

void AddObjectRef(Variables* vars, const std::string& name, uint32_t type, uint64_t id) {
  v1::Variable* v = vars->Add();
  v->set_name(name);
  v->set_type(type);
  v->set_object_id(id);
}

v1::Program* AddProgram(v1::StateDelta& d, uint64_t id, const std::string& function) {
  v1::Program* p = d.add_objects()->mutable_program();
  p->set_id(id);
  p->set_version(1);
  p->set_module_path(kModule);
  p->set_module_hash(d.objects(0).program().module_hash());
  p->set_function(function);
  return p;
}

v1::Acceleration* AddAcceleration(v1::StateDelta& d, uint64_t id) {
  v1::Acceleration* a = d.add_objects()->mutable_acceleration();
  a->set_id(id);
  a->set_version(1);
  a->set_builder("Bvh");
  a->set_traverser("Bvh");
  a->set_build_epoch(1);
  return a;
}

v1::Buffer* AddInput(v1::StateDelta& d, uint64_t id, uint32_t format, uint64_t element_size,
                     const void* data, size_t size) {
  v1::Buffer* b = d.add_objects()->mutable_buffer();
  b->set_id(id);
  b->set_version(1);
  b->set_desc(RT_BUFFER_INPUT);
  b->set_format(format);
  b->set_element_size(element_size);
  b->add_dims(size / element_size);
  v1::BufferChunk* chunk = d.add_chunks();
  chunk->set_buffer_id(id);
  chunk->set_data(data, size);
  chunk->set_hash(0x1234);
  return b;
}

// Entry point 0 writes (x, y, scale, 1) at every launch index (write_index); entry point 1 traces
// a camera ray into a Group of Transform → GeometryGroup → sphere and of a GeometryGroup of one
// native triangle (vertex and index buffers, acceleration properties). Another INPUT buffer and
// exception programs make every kind of object, and buffer chunks, travel.
v1::StateDelta SceneDelta() {
  v1::StateDelta d = testing::WriteIndexDelta(kModule, kSession, 1, kWidth, kHeight);
  v1::ContextState* c = d.mutable_context();
  c->set_entry_point_count(2);
  c->add_ray_generation(kCamera);
  c->add_exception(kException);
  c->add_exception(kException);
  c->add_miss(kMiss);
  c->set_exception_mask(1u << (RT_EXCEPTION_STACK_OVERFLOW - RT_EXCEPTION_PROGRAM_ID_INVALID));
  AddValue(c->mutable_variables(), "scale", RT_OBJECTTYPE_FLOAT, &kScale, sizeof(kScale));
  AddObjectRef(c->mutable_variables(), "top_object", RT_OBJECTTYPE_GROUP, kGroup);
  AddProgram(d, kCamera, "camera");
  AddProgram(d, kMiss, "miss");
  AddProgram(d, kException, "exception");
  AddProgram(d, kIntersect, "sphere_intersect");
  AddProgram(d, kBounds, "sphere_bounds");
  AddProgram(d, kClosestHit, "closest_hit");

  v1::Geometry* g = d.add_objects()->mutable_geometry();
  g->set_id(kGeometry);
  g->set_version(1);
  g->set_primitive_count(1);
  g->set_intersection_program(kIntersect);
  g->set_bounding_box_program(kBounds);
  const float sphere[4] = {0, 0, 0, 1};
  AddValue(g->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, sphere, sizeof(sphere));
  v1::Material* m = d.add_objects()->mutable_material();
  m->set_id(kMaterial);
  m->set_version(1);
  m->add_closest_hit(kClosestHit);
  m->add_any_hit(0);
  const float tint[3] = {1, 0.5f, 1};
  AddValue(m->mutable_variables(), "tint", RT_OBJECTTYPE_FLOAT3, tint, sizeof(tint));
  v1::GeometryInstance* gi = d.add_objects()->mutable_geometry_instance();
  gi->set_id(kInstance);
  gi->set_version(1);
  gi->set_geometry(kGeometry);
  gi->add_materials(kMaterial);
  AddAcceleration(d, kGeometryAccel);
  v1::GeometryGroup* gg = d.add_objects()->mutable_geometry_group();
  gg->set_id(kGeometryGroup);
  gg->set_version(1);
  gg->set_acceleration(kGeometryAccel);
  gg->add_children(kInstance);
  v1::Transform* t = d.add_objects()->mutable_transform();
  t->set_id(kTransform);
  t->set_version(1);
  const float matrix[16] = {1, 0, 0, 0.5f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  const float inverse[16] = {1, 0, 0, -0.5f, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) {
    t->add_matrix(matrix[i]);
    t->add_inverse(inverse[i]);
  }
  t->mutable_child()->set_id(kGeometryGroup);
  t->mutable_child()->set_type(RT_OBJECTTYPE_GEOMETRY_GROUP);
  AddAcceleration(d, kGroupAccel);
  v1::Group* group = d.add_objects()->mutable_group();
  group->set_id(kGroup);
  group->set_version(1);
  group->set_acceleration(kGroupAccel);
  v1::NodeRef* child = group->add_children();
  child->set_id(kTransform);
  child->set_type(RT_OBJECTTYPE_TRANSFORM);

  const float contents[4] = {1, 2, 3, 4};
  AddInput(d, kInput, RT_FORMAT_FLOAT, 4, contents, sizeof(contents));

  // A triangle in the bottom right corner, in front of the sphere.
  const float vertices[9] = {1, -2, 2, 2, -2, 2, 2, -1, 2};
  const int32_t indices[3] = {0, 1, 2};
  AddInput(d, kVertices, RT_FORMAT_FLOAT3, 12, vertices, sizeof(vertices));
  AddInput(d, kIndices, RT_FORMAT_INT3, 12, indices, sizeof(indices));
  v1::Geometry* tg = d.add_objects()->mutable_geometry();
  tg->set_id(kTriangleGeometry);
  tg->set_version(1);
  tg->set_primitive_count(1);
  tg->set_intersection_program(kIntersect);  // reports the attributes of the triangle's hits
  tg->set_bounding_box_program(kBounds);
  // The intersection program reports the triangle's normal where its rays meet this sphere, and
  // all of them do: a hit it does not report would shade with whatever attributes came before.
  const float around_triangle[4] = {1.5f, -1.5f, 2.f, 1.f};
  AddValue(tg->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, around_triangle,
           sizeof(around_triangle));
  AddObjectRef(tg->mutable_variables(), "vertices", RT_OBJECTTYPE_BUFFER, kVertices);
  AddObjectRef(tg->mutable_variables(), "indices", RT_OBJECTTYPE_BUFFER, kIndices);
  v1::GeometryInstance* ti = d.add_objects()->mutable_geometry_instance();
  ti->set_id(kTriangleInstance);
  ti->set_version(1);
  ti->set_geometry(kTriangleGeometry);
  ti->add_materials(kMaterial);
  v1::Acceleration* ta = AddAcceleration(d, kTriangleAccel);
  ta->set_builder("Trbvh");
  (*ta->mutable_properties())["vertex_buffer_name"] = "vertices";
  (*ta->mutable_properties())["index_buffer_name"] = "indices";
  (*ta->mutable_properties())["vertex_buffer_stride"] = "12";
  v1::GeometryGroup* tgg = d.add_objects()->mutable_geometry_group();
  tgg->set_id(kTriangleGroup);
  tgg->set_version(1);
  tgg->set_acceleration(kTriangleAccel);
  tgg->add_children(kTriangleInstance);
  v1::NodeRef* triangles = group->add_children();
  triangles->set_id(kTriangleGroup);
  triangles->set_type(RT_OBJECTTYPE_GEOMETRY_GROUP);
  return d;
}

v1::LaunchRequest ValidRequest(uint32_t entry, uint64_t launch_id) {
  v1::LaunchRequest r;
  r.set_session_id(kSession);
  r.set_launch_id(launch_id);
  r.set_entry_point(entry);
  r.add_dims(kWidth);
  r.add_dims(kHeight);
  for (v1::Tile& t : scheduler::MakeTiles({kWidth, kHeight}, {4, 4})) *r.add_tiles() = t;
  return r;
}

// Runs `call`; an exception escaping it fails the test (and reads as an INTERNAL status).
template <typename F>
absl::Status NoThrow(const std::string& what, F&& call) {
  try {
    return call();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << " threw " << typeid(e).name() << ": " << e.what();
  } catch (...) {
    ADD_FAILURE() << what << " threw";
  }
  return absl::InternalError("exception escaped");
}

// Sets `cancel` once `limit` has passed, unless destroyed first.
class Watchdog {
 public:
  Watchdog(std::atomic<bool>& cancel, std::chrono::milliseconds limit)
      : thread_([this, &cancel, limit] {
          std::unique_lock<std::mutex> lock(mu_);
          if (!cv_.wait_for(lock, limit, [this] { return done_; })) {
            fired_ = true;
            cancel = true;
          }
        }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      done_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  bool fired() {
    std::lock_guard<std::mutex> lock(mu_);
    return fired_;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool done_ = false, fired_ = false;
  std::thread thread_;
};

struct LaunchOutcome {
  absl::Status status;
  std::string output;          // the output buffer as the call's regions wrote it
  std::set<uint64_t> written;  // output elements (y * kWidth + x) the regions carried
  bool timed_out = false;      // the watchdog cancelled the call
};

LaunchOutcome RunLaunch(Device& device, const v1::LaunchRequest& request) {
  LaunchOutcome out;
  std::atomic<bool> cancel{false};
  std::mutex mu;
  Watchdog watchdog(cancel, kLaunchLimit);
  out.status = NoThrow("Launch", [&] {
    return device.Launch(request, cancel, [&](v1::TileResult&& t) {
      std::lock_guard<std::mutex> lock(mu);
      for (const v1::BufferRegion& r : t.regions()) {
        if (r.buffer_id() != kOutput) continue;
        testing::ApplyRegion(r, kOutput, &out.output);
        auto mark = [&](uint64_t offset, uint64_t size) {
          for (uint64_t e = offset / 16; e < (offset + size) / 16; ++e) out.written.insert(e);
        };
        if (r.run_offsets_size() == 0) mark(r.offset(), r.data().size());
        for (int i = 0; i < r.run_offsets_size() && i < r.run_sizes_size(); ++i) {
          mark(r.run_offsets(i), r.run_sizes(i));
        }
      }
    });
  });
  out.timed_out = watchdog.fired();
  return out;
}

std::unique_ptr<Device> DeviceWith(const v1::StateDelta& delta) {
  std::unique_ptr<Device> device = CreateInprocDevice(2, /*results_in_rounds=*/true);
  absl::Status s = device->Apply(delta);
  EXPECT_TRUE(s.ok()) << s;
  return device;
}

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

// ---- The tests.

class ReplicaFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    // Modules the devices receive go to a private cache directory.
    std::string pattern =
        (std::filesystem::temp_directory_path() / "tessera-replica-fuzz-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    module_cache_ = pattern;
    SetModuleCacheDirectory(module_cache_);
    scene_ = SceneDelta();
    for (uint32_t entry : {0u, 1u}) {
      std::unique_ptr<Device> device = DeviceWith(scene_);
      LaunchOutcome out = RunLaunch(*device, ValidRequest(entry, 1));
      ASSERT_TRUE(out.status.ok()) << out.status;
      ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
      reference_[entry] = out.output;
    }
  }
  void TearDown() override {
    SetModuleCacheDirectory("");
    std::error_code ec;
    std::filesystem::remove_all(module_cache_, ec);
  }

  // Whether `device` renders both entry points as the valid scene does.
  void ExpectRendersScene(Device& device, const std::string& context) {
    for (uint32_t entry : {0u, 1u}) {
      LaunchOutcome out = RunLaunch(device, ValidRequest(entry, ++launch_id_));
      EXPECT_TRUE(out.status.ok()) << context << ": " << out.status;
      EXPECT_TRUE(out.output == reference_[entry])
          << context << ": entry point " << entry << " renders differently";
    }
  }

  std::string module_cache_;
  v1::StateDelta scene_;
  std::string reference_[2];
  uint64_t launch_id_ = 100;
};

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

// ---- What the fuzzing found, each as its own case.

// The index of the first object of `d` with id `id`, or -1.
int ObjectIndex(const v1::StateDelta& d, uint64_t id) {
  for (int i = 0; i < d.objects_size(); ++i) {
    const v1::Object& o = d.objects(i);
    const Reflection* r = o.GetReflection();
    const FieldDescriptor* f = r->GetOneofFieldDescriptor(o, o.GetDescriptor()->oneof_decl(0));
    if (f == nullptr) continue;
    const Message& body = r->GetMessage(o, f);
    if (body.GetReflection()->GetUInt64(body, body.GetDescriptor()->field(0)) == id) return i;
  }
  return -1;
}

v1::Object* ObjectById(v1::StateDelta& d, uint64_t id) {
  const int i = ObjectIndex(d, id);
  return i < 0 ? nullptr : d.mutable_objects(i);
}

void EraseObject(v1::StateDelta& d, uint64_t id) {
  if (const int i = ObjectIndex(d, id); i >= 0) d.mutable_objects()->DeleteSubrange(i, 1);
}

// The scene as its second delta: everything again, sequence 2, modules already on the device.
v1::StateDelta SecondDelta(const v1::StateDelta& scene) {
  v1::StateDelta d = scene;
  d.set_sequence(2);
  d.clear_modules();
  return d;
}

// A rejected delta names what it rejects, leaves the device as it was and its sequence unused.
void ExpectRejected(Device& device, const v1::StateDelta& bad, absl::StatusCode code,
                    const std::string& names, const std::string& scene_reference,
                    const v1::StateDelta& scene) {
  const absl::Status s = NoThrow("Apply", [&] { return device.Apply(bad); });
  EXPECT_EQ(s.code(), code) << s;
  EXPECT_NE(s.message().find(names), std::string::npos) << s;
  LaunchOutcome out = RunLaunch(device, ValidRequest(1, 77));
  EXPECT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == scene_reference);
  EXPECT_TRUE(device.Apply(SecondDelta(scene)).ok());
}

// Embree asserts on a ray it cannot trace (components past 1.8e18, NaN), which ended the process.
// A transform with an infinite inverse made every object-space ray such a ray.
TEST_F(ReplicaFuzz, TransformWithInfiniteInverseRaisesInvalidRayInsteadOfAborting) {
  for (bool enabled : {false, true}) {
    v1::StateDelta d = scene_;
    ObjectById(d, kTransform)->mutable_transform()->set_inverse(4, INFINITY);
    if (enabled) {
      d.mutable_context()->set_exception_mask(
          1u << (RT_EXCEPTION_INVALID_RAY - RT_EXCEPTION_PROGRAM_ID_INVALID));
    }
    std::unique_ptr<Device> device = DeviceWith(d);
    LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
    ASSERT_TRUE(out.status.ok()) << out.status;
    ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
    const float* center =
        reinterpret_cast<const float*>(out.output.data()) + 4 * (kHeight / 2 * kWidth + kWidth / 2);
    // Disabled, nothing below the transform is hit: the miss program's blue.
    EXPECT_EQ(center[0], enabled ? float(RT_EXCEPTION_INVALID_RAY) : 0.f);
    EXPECT_EQ(center[2], enabled ? 0.f : 1.f);
  }
}

// Embree finds the triangle; its intersection program (the sphere's) never reports it. The hit is
// shaded with zeroed attributes, not with the normal an earlier hit of the thread left: the
// closest-hit program normalizes a zero normal, NaN, in every launch.
TEST_F(ReplicaFuzz, TriangleHitItsProgramDoesNotReportShadesWithZeroedAttributes) {
  v1::StateDelta d = scene_;
  const float far_away[4] = {100.f, 100.f, 100.f, 1.f};
  for (v1::Variable& v :
       *ObjectById(d, kTriangleGeometry)->mutable_geometry()->mutable_variables()) {
    if (v.name() == "sphere") v.set_data(far_away, sizeof(far_away));
  }
  std::unique_ptr<Device> device = DeviceWith(d);
  for (uint64_t launch = 1; launch <= 3; ++launch) {
    LaunchOutcome out = RunLaunch(*device, ValidRequest(1, launch));
    ASSERT_TRUE(out.status.ok()) << out.status;
    ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
    const float* triangle = reinterpret_cast<const float*>(out.output.data()) + 4 * (kWidth - 1);
    EXPECT_TRUE(std::isnan(triangle[0])) << "launch " << launch << ": " << triangle[0];
  }
}

// Session 0 means "none yet" to a replica: one that took it would take any session after it.
TEST_F(ReplicaFuzz, SessionZeroIsRefused) {
  std::unique_ptr<Device> device = CreateInprocDevice(2, /*results_in_rounds=*/true);
  v1::StateDelta d = scene_;
  d.set_session_id(0);
  absl::Status s = device->Apply(d);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << s;
  EXPECT_NE(s.message().find("session 0"), std::string::npos) << s;
  EXPECT_TRUE(device->Apply(scene_).ok());
  d = scene_;
  d.set_session_id(scene_.session_id() + 1);
  d.set_sequence(scene_.sequence() + 1);
  EXPECT_EQ(device->Apply(d).code(), absl::StatusCode::kFailedPrecondition);
}

// Tile origins and sizes are 64-bit on the wire and launch indices 32-bit: an origin of 2^32 ran
// row 0, a size of 2^32 + 1 ran one column.
TEST_F(ReplicaFuzz, TileBeyondThirtyTwoBitsIsClippedNotWrapped) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::LaunchRequest request = ValidRequest(0, 1);
  request.clear_tiles();
  v1::Tile* outside = request.add_tiles();
  outside->add_origin(0);
  outside->add_origin(uint64_t{1} << 32);
  outside->add_size(4);
  outside->add_size(4);
  v1::Tile* wide = request.add_tiles();
  wide->set_index(1);
  wide->add_origin(4);
  wide->add_origin(0);
  wide->add_size((uint64_t{1} << 32) + 1);
  wide->add_size(2);
  LaunchOutcome out = RunLaunch(*device, request);
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_EQ(out.written, (std::set<uint64_t>{4, 5, 6, 7, 12, 13, 14, 15}));
}

TEST_F(ReplicaFuzz, TileOfAnotherDimensionalityIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::LaunchRequest request = ValidRequest(0, 1);
  request.mutable_tiles(2)->mutable_origin()->RemoveLast();
  request.mutable_tiles(2)->mutable_size()->RemoveLast();
  LaunchOutcome out = RunLaunch(*device, request);
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument) << out.status;
  EXPECT_NE(out.status.message().find("tile 2 has 1 origin"), std::string::npos) << out.status;
  EXPECT_TRUE(out.written.empty());
}

// Every level of rtTrace takes native stack: a large stack size let programs nest until a thread's
// stack ran out (SIGSEGV near 12,000 levels), and 2^40 bytes asked for 2^33 frames (length_error
// escaped Launch).
TEST_F(ReplicaFuzz, StackSizeNestsNoDeeperThanTheDeviceLimit) {
  v1::StateDelta d = scene_;
  d.mutable_context()->set_stack_size(uint64_t{1} << 40);
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == reference_[1]);

  // A sphere every 3 units along the camera rays, each hit tracing on: 16,000 levels.
  ObjectById(d, kClosestHit)->mutable_program()->set_function("recursive_hit");
  const int depth = 16000;
  AddValue(d.mutable_context()->mutable_variables(), "max_depth", RT_OBJECTTYPE_INT, &depth, 4);
  v1::GeometryInstance base = ObjectById(d, kInstance)->geometry_instance();
  v1::GeometryGroup* gg = ObjectById(d, kGeometryGroup)->mutable_geometry_group();
  for (int k = 1; k <= depth / 2; ++k) {
    v1::GeometryInstance* gi = d.add_objects()->mutable_geometry_instance();
    *gi = base;
    gi->set_id(1000 + k);
    const float sphere[4] = {0, 0, 3.f * k, 1};
    AddValue(gi->mutable_variables(), "sphere", RT_OBJECTTYPE_FLOAT4, sphere, sizeof(sphere));
    gg->add_children(gi->id());
  }
  device = DeviceWith(d);
  out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  const float* center =
      reinterpret_cast<const float*>(out.output.data()) + 4 * (kHeight / 2 * kWidth + kWidth / 2);
  EXPECT_EQ(center[0], float(RT_EXCEPTION_STACK_OVERFLOW));
}

// Buffer storage was allocated while the delta was being applied: std::bad_alloc escaped Apply
// with the sequence taken and the objects before the buffer applied.
TEST_F(ReplicaFuzz, BufferTooLargeForTheDeviceIsRejectedAndTheStateKept) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  ObjectById(bad, kOutput)->mutable_buffer()->set_dims(0, 0xFFFFFFFFu);
  ExpectRejected(*device, bad, absl::StatusCode::kResourceExhausted, "buffer #2", reference_[1],
                 scene_);
}

// The chunk passed the bounds check against the buffer the device held, then the delta removed
// that buffer and the copy went into an empty one (SIGSEGV).
TEST_F(ReplicaFuzz, ChunkForABufferTheDeltaRemovesIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  bad.add_removed(kInput);
  EraseObject(bad, kInput);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "buffer #17", reference_[1],
                 scene_);
  // Buffers the delta removes and sends again start afresh and take their chunks.
  v1::StateDelta again = SecondDelta(scene_);
  again.set_sequence(3);
  again.add_removed(kInput);
  again.add_removed(kOutput);
  ASSERT_TRUE(device->Apply(again).ok());
  EXPECT_TRUE(RunLaunch(*device, ValidRequest(0, 1)).output == reference_[0]);
}

// dlsym finds the module's dependencies' symbols and its data too: a program named `getpid` ran
// libc's, `close` closed a file descriptor of the process, `output` jumped into data (SIGSEGV).
TEST_F(ReplicaFuzz, ProgramsAreOnlyGlobalFunctionsOfTheModule) {
  for (const char* function :
       {"getpid", "output", "tessera_module_init", "_ZN5optix6bufferI6float4Li2EEC1Ev"}) {
    v1::StateDelta d = scene_;
    ObjectById(d, kWriteIndex)->mutable_program()->set_function(function);
    std::unique_ptr<Device> device = DeviceWith(d);
    LaunchOutcome out = RunLaunch(*device, ValidRequest(0, 1));
    EXPECT_EQ(out.status.code(), absl::StatusCode::kNotFound) << function << ": " << out.status;
    EXPECT_NE(out.status.message().find(absl::StrCat("'", function, "'")), std::string::npos)
        << out.status;
  }
}

// A scene kept from the last plan was reused without checking its geometries' programs: with the
// intersection program gone, traversal called through a null program (SIGSEGV).
TEST_F(ReplicaFuzz, KeptSceneWhoseGeometryLostItsIntersectionProgramFailsTheLaunch) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  ASSERT_TRUE(RunLaunch(*device, ValidRequest(1, 1)).status.ok());
  v1::StateDelta d = SecondDelta(scene_);
  ObjectById(d, kGeometry)->mutable_geometry()->set_intersection_program(0);
  ASSERT_TRUE(device->Apply(d).ok());
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 2));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kFailedPrecondition) << out.status;
  EXPECT_NE(out.status.message().find("geometry #9"), std::string::npos) << out.status;
}

// The plan gave every material a hit group per ray type of the context: 2^31 ray types threw
// std::bad_alloc out of Launch.
TEST_F(ReplicaFuzz, RayTypeCountCostsNothingPastTheMaterialsPrograms) {
  v1::StateDelta d = scene_;
  d.mutable_context()->set_ray_type_count(1u << 31);
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_TRUE(out.output == reference_[1]);
}

// primitive_count * 6 bounds overflowed (std::length_error escaped Launch); Embree counts
// primitives in 32 bits.
TEST_F(ReplicaFuzz, PrimitiveCountPastThirtyTwoBitsIsRejected) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  for (uint64_t count : {uint64_t{1} << 32, ~uint64_t{0}}) {
    v1::StateDelta bad = SecondDelta(scene_);
    ObjectById(bad, kGeometry)->mutable_geometry()->set_primitive_count(count);
    ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "geometry #9", reference_[1],
                   scene_);
    device = DeviceWith(scene_);
  }
}

// Ids name objects for references and removals; one id for two kinds of object, or id 0 (none),
// is an inconsistent delta.
TEST_F(ReplicaFuzz, OneIdNamesOneObject) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  v1::StateDelta bad = SecondDelta(scene_);
  ObjectById(bad, kInput)->mutable_buffer()->set_id(kCamera);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument,
                 "buffer #3 has the id of a program", reference_[1], scene_);
  device = DeviceWith(scene_);
  bad = SecondDelta(scene_);
  ObjectById(bad, kGroup)->mutable_group()->set_id(0);
  ExpectRejected(*device, bad, absl::StatusCode::kInvalidArgument, "group with id 0", reference_[1],
                 scene_);
  // The same id as another kind is fine once the delta removes the old object.
  device = DeviceWith(scene_);
  v1::StateDelta reuse = SecondDelta(scene_);
  EraseObject(reuse, kMiss);
  ObjectById(reuse, kInput)->mutable_buffer()->set_id(kMiss);
  reuse.add_removed(kMiss);
  reuse.mutable_context()->clear_miss();
  reuse.clear_chunks();
  const absl::Status reused = device->Apply(reuse);
  EXPECT_TRUE(reused.ok()) << reused;
}

// Scenes stay cached across plans, pointing into the plan that built or checked them; a node that
// no object variable reaches is not checked, and a program that traced it anyway (its id passed
// as a plain 8-byte value) used the freed plan of an earlier launch.
TEST_F(ReplicaFuzz, NodeNoObjectVariableReachesIsNotTraced) {
  std::unique_ptr<Device> device = DeviceWith(scene_);
  ASSERT_TRUE(RunLaunch(*device, ValidRequest(1, 1)).status.ok());
  v1::StateDelta d = SecondDelta(scene_);
  for (v1::Variable& v : *d.mutable_context()->mutable_variables()) {
    if (v.name() != "top_object") continue;
    const uint64_t id = kGroup;
    v.set_type(RT_OBJECTTYPE_USER);
    v.set_object_id(0);
    v.set_data(&id, sizeof(id));
  }
  ASSERT_TRUE(device->Apply(d).ok());
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 2));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kFailedPrecondition) << out.status;
  EXPECT_NE(out.status.message().find("#16"), std::string::npos) << out.status;
}

// The message read the offending index from Embree's index buffer after releasing the geometry
// that held it (heap-use-after-free: it named a vertex no buffer had).
TEST_F(ReplicaFuzz, TriangleUsingAVertexPastTheVertexBufferNamesIt) {
  v1::StateDelta d = scene_;
  (*ObjectById(d, kTriangleAccel)
        ->mutable_acceleration()
        ->mutable_properties())["vertex_buffer_name"] =
      "indices";  // one "vertex" of 12 bytes: the indices 0, 1, 2
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kOutOfRange) << out.status;
  EXPECT_NE(out.status.message().find("geometry instance #21: triangle 0 uses vertex 1 but the "
                                      "vertex buffer holds 1"),
            std::string::npos)
      << out.status;
}

// std::stoul threw std::invalid_argument out of Launch for a stride property that is no number.
TEST_F(ReplicaFuzz, StridePropertyThatIsNoNumberFailsTheLaunch) {
  v1::StateDelta d = scene_;
  (*ObjectById(d, kTriangleAccel)
        ->mutable_acceleration()
        ->mutable_properties())["vertex_buffer_stride"] = "twelve";
  std::unique_ptr<Device> device = DeviceWith(d);
  LaunchOutcome out = RunLaunch(*device, ValidRequest(1, 1));
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument) << out.status;
  EXPECT_NE(out.status.message().find("acceleration #22"), std::string::npos) << out.status;
  EXPECT_NE(out.status.message().find("vertex_buffer_stride"), std::string::npos) << out.status;
}

}  // namespace
}  // namespace tessera
