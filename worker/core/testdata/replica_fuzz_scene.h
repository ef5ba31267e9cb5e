// What the replica fuzz test and the regression tests it led to share: a small valid scene that
// uses every kind of object, launches guarded by a watchdog, and a fixture that renders the scene
// once for reference.
#ifndef TESSERA_WORKER_CORE_TESTDATA_REPLICA_FUZZ_SCENE_H_
#define TESSERA_WORKER_CORE_TESTDATA_REPLICA_FUZZ_SCENE_H_

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <typeinfo>

#include "absl/status/status.h"
#include "tessera/worker/inproc_device.h"

namespace tessera::fuzz {

using Variables = google::protobuf::RepeatedPtrField<v1::Variable>;

inline const std::string kModule =
    std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";
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
              size_t size);
void AddObjectRef(Variables* vars, const std::string& name, uint32_t type, uint64_t id);
v1::Program* AddProgram(v1::StateDelta& d, uint64_t id, const std::string& function);
v1::Acceleration* AddAcceleration(v1::StateDelta& d, uint64_t id);
v1::Buffer* AddInput(v1::StateDelta& d, uint64_t id, uint32_t format, uint64_t element_size,
                     const void* data, size_t size);
// Entry point 0 writes (x, y, scale, 1) at every launch index (write_index); entry point 1 traces
// a camera ray into a Group of Transform → GeometryGroup → sphere and of a GeometryGroup of one
// native triangle (vertex and index buffers, acceleration properties). Another INPUT buffer and
// exception programs make every kind of object, and buffer chunks, travel.
v1::StateDelta SceneDelta();
v1::LaunchRequest ValidRequest(uint32_t entry, uint64_t launch_id);

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

// `limit`: when the watchdog cancels the launch. A valid launch that is slow by design (a thousand
// nested traces) takes a longer one: the sanitizers (tools/sanitize.sh) slow it past 2 s.
LaunchOutcome RunLaunch(Device& device, const v1::LaunchRequest& request,
                        std::chrono::milliseconds limit = kLaunchLimit);
std::unique_ptr<Device> DeviceWith(const v1::StateDelta& delta);

// The index of the first object of `d` with id `id`, or -1.
int ObjectIndex(const v1::StateDelta& d, uint64_t id);
v1::Object* ObjectById(v1::StateDelta& d, uint64_t id);
void EraseObject(v1::StateDelta& d, uint64_t id);

class ReplicaFuzz : public ::testing::Test {
 protected:
  // Modules the devices receive go to the test binary's private cache (module_store_test.cc).
  void SetUp() override {
    scene_ = SceneDelta();
    for (uint32_t entry : {0u, 1u}) {
      std::unique_ptr<Device> device = DeviceWith(scene_);
      LaunchOutcome out = RunLaunch(*device, ValidRequest(entry, 1));
      ASSERT_TRUE(out.status.ok()) << out.status;
      ASSERT_EQ(out.output.size(), kWidth * kHeight * 16);
      reference_[entry] = out.output;
    }
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

  v1::StateDelta scene_;
  std::string reference_[2];
  uint64_t launch_id_ = 100;
};

}  // namespace tessera::fuzz

#endif  // TESSERA_WORKER_CORE_TESTDATA_REPLICA_FUZZ_SCENE_H_
