#include "tessera/scheduler/dispatcher.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <map>
#include <mutex>
#include <thread>

#include "tessera/scheduler/tiling.h"

namespace tessera::scheduler {
namespace {

constexpr uint64_t kTileIndices = 4096;

using std::chrono::steady_clock;

// Runs tiles instantly and reports each as a 4-byte region at 4 * tile index; can be told to
// fail in several ways at its n-th call.
class FakeDevice : public Device {
 public:
  enum class Fault { kNone, kUnavailable, kCrash, kProgramError, kBlockUntilCancel };
  FakeDevice(Fault fault = Fault::kNone, int fault_at_call = 0)
      : fault_(fault), fault_at_call_(fault_at_call) {}

  DeviceInfo Info() const override { return {"fake", "fake", 1}; }
  int calls() const { return calls_; }
  // How long a faulting call runs before it fails (the device dies while running it).
  void set_fault_delay(std::chrono::milliseconds delay) { fault_delay_ = delay; }
  // Dead before any call reaches it (a worker killed at the same moment as another): its faulting
  // calls fail without saying they started, even when the request asks (report_start).
  void set_dead_before_start() { dead_before_start_ = true; }
  // The size of the batch each tile came in.
  std::map<uint32_t, int> batch_of_tile() const {
    std::lock_guard<std::mutex> lock(batches_mu_);
    return batch_of_tile_;
  }
  absl::Status Apply(const v1::StateDelta&) override { return absl::OkStatus(); }
  absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                      const std::function<void(v1::TileResult&&)>& on_result) override {
    const int call = calls_++;
    {
      std::lock_guard<std::mutex> lock(batches_mu_);
      for (const v1::Tile& t : request.tiles()) batch_of_tile_[t.index()] = request.tiles_size();
    }
    // A little time per call, as real devices take: with instant calls, one device's thread
    // could drain the queue before the others start.
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const bool faulting = fault_ != Fault::kNone && call >= fault_at_call_;
    if (request.report_start() && !(faulting && dead_before_start_)) {
      v1::TileResult started;
      started.set_tile_index(kHeartbeatTileIndex);
      started.set_started(true);
      on_result(std::move(started));
    }
    if (faulting) {
      std::this_thread::sleep_for(fault_delay_);
      switch (fault_) {
        case Fault::kUnavailable:
          return absl::UnavailableError("connection reset");
        case Fault::kCrash:
          return absl::AbortedError("crashed: signal 11 (SIGSEGV) in closest hit program 'ch'");
        case Fault::kProgramError:
          return absl::InvalidArgumentError("closest hit program 'ch': no such function");
        case Fault::kBlockUntilCancel: {
          // Says it finished the first tile, as a worker's heartbeat does, then runs on.
          v1::TileResult heartbeat;
          heartbeat.set_tile_index(kHeartbeatTileIndex);
          heartbeat.set_tiles_done(1);
          on_result(std::move(heartbeat));
          while (!cancel.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
          return absl::CancelledError("launch cancelled");
        }
        case Fault::kNone:
          break;
      }
    }
    v1::TileResult final_result;
    final_result.set_tile_index(kFinalTileIndex);
    for (const v1::Tile& t : request.tiles()) {
      v1::TileResult r;
      r.set_tile_index(t.index());
      on_result(std::move(r));
      v1::BufferRegion* region = final_result.add_regions();
      region->set_offset(4 * uint64_t{t.index()});
      region->set_data(std::string(4, static_cast<char>(t.index())));
    }
    on_result(std::move(final_result));
    return absl::OkStatus();
  }

 private:
  Fault fault_;
  int fault_at_call_;
  std::chrono::milliseconds fault_delay_{0};
  bool dead_before_start_ = false;
  std::atomic<int> calls_{0};
  mutable std::mutex batches_mu_;
  std::map<uint32_t, int> batch_of_tile_;
};

struct Outcome {
  absl::Status status;
  std::map<uint32_t, size_t> device_of_tile;  // from finished batches
  size_t tile_reports = 0;                    // tiles counted over finished batches
  std::vector<LostDevice> lost;
  int failed_device = -1;
};

Outcome RunAll(std::vector<FakeDevice*> fakes, size_t tiles, bool stable, int threads = 1,
               uint64_t min_indices_per_thread = 0, std::vector<float> costs = {},
               std::vector<float>* measured = nullptr) {
  std::vector<DispatchDevice> devices;
  for (size_t i = 0; i < fakes.size(); ++i) {
    devices.push_back({fakes[i], "fake" + std::to_string(i), threads, v1::LaunchRequest()});
  }
  // Tiles of 4096 launch indices: batches of up to 64 per device thread.
  Dispatcher dispatcher(std::move(devices), MakeTiles({tiles * kTileIndices}, {kTileIndices}),
                        stable, nullptr, min_indices_per_thread, std::move(costs));
  Outcome out;
  std::vector<FinishedBatch> batches;
  while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
  }
  for (const FinishedBatch& b : batches) {
    out.tile_reports += b.tiles;
    for (const v1::TileResult& r : b.results) {
      if (r.tile_index() == kFinalTileIndex) continue;
      EXPECT_EQ(out.device_of_tile.count(r.tile_index()), 0u) << "tile " << r.tile_index();
      out.device_of_tile[r.tile_index()] = b.device;
    }
    EXPECT_EQ(b.results.back().tile_index(), kFinalTileIndex);
  }
  out.status = dispatcher.status();
  if (measured != nullptr) *measured = dispatcher.tile_costs();
  out.lost = dispatcher.lost();
  out.failed_device = dispatcher.failed_device();
  return out;
}

// Three dimensions of 2^31 in at most kMaxTiles tiles: each tile covers 2^75 indices, which
// wrapped to 0 and killed the host with SIGFPE in Take. The launch starts and can be cancelled.
TEST(DispatcherTest, TilesOfMoreThan2To64IndicesDoNotCrash) {
  for (bool stable : {false, true}) {
    FakeDevice a(FakeDevice::Fault::kBlockUntilCancel), b(FakeDevice::Fault::kBlockUntilCancel);
    std::vector<DispatchDevice> devices;
    devices.push_back({&a, "a", 2, v1::LaunchRequest()});
    devices.push_back({&b, "b", 2, v1::LaunchRequest()});
    Dispatcher dispatcher(std::move(devices),
                          MakeTiles({1u << 31, 1u << 31, 1u << 31}, MaxTileSize(3)), stable);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    dispatcher.Cancel();
    std::vector<FinishedBatch> batches;
    while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
    }
    EXPECT_EQ(dispatcher.status().code(), absl::StatusCode::kCancelled);
  }
}

TEST(DispatcherTest, DynamicAssignmentRunsEveryTileOnce) {
  FakeDevice a, b, c;
  Outcome out = RunAll({&a, &b, &c}, 100, /*stable=*/false);
  ASSERT_TRUE(out.status.ok()) << out.status;
  EXPECT_EQ(out.device_of_tile.size(), 100u);
  EXPECT_EQ(out.tile_reports, 100u);
  EXPECT_TRUE(out.lost.empty());
}

// A light launch asks for large calls: the launch goes out in a guided share of the whole launch
// per call (an eighth over two devices), not in calls that shrink as the queue drains.
TEST(DispatcherTest, ALightLaunchTakesFewCalls) {
  FakeDevice a, b;
  Outcome guided = RunAll({&a, &b}, 100, /*stable=*/false);
  ASSERT_TRUE(guided.status.ok()) << guided.status;
  EXPECT_GT(a.calls() + b.calls(), 8);
  FakeDevice c, d;
  Outcome light = RunAll({&c, &d}, 100, /*stable=*/false, 1, /*min_indices_per_thread=*/1 << 22);
  ASSERT_TRUE(light.status.ok()) << light.status;
  EXPECT_EQ(light.device_of_tile.size(), 100u);
  EXPECT_EQ(c.calls() + d.calls(), 8);
}

// With what an earlier launch measured, batches are cut to like costs: the expensive first
// tiles go out a few at a time, not in a batch of as many tiles as the cheap ones.
TEST(DispatcherTest, BatchesAreCutByTheCostsAnEarlierLaunchMeasured) {
  FakeDevice a, b;
  std::vector<float> measured;
  Outcome first = RunAll({&a, &b}, 200, /*stable=*/false, 1, 0, {}, &measured);
  ASSERT_TRUE(first.status.ok()) << first.status;
  ASSERT_EQ(measured.size(), 200u);
  for (float c : measured) EXPECT_GT(c, 0.f);
  std::map<uint32_t, int> batches = a.batch_of_tile();
  for (const auto& [tile, size] : b.batch_of_tile()) batches[tile] = size;
  EXPECT_GE(batches[0], 20);  // a guided share of tiles: 200 / (4 * 2)

  std::vector<float> costs(200, 1.f);
  for (int i = 0; i < 20; ++i) costs[i] = 10.f;
  FakeDevice c, d;
  Outcome second = RunAll({&c, &d}, 200, /*stable=*/false, 1, 0, costs);
  ASSERT_TRUE(second.status.ok()) << second.status;
  EXPECT_EQ(second.device_of_tile.size(), 200u);
  batches = c.batch_of_tile();
  for (const auto& [tile, size] : d.batch_of_tile()) batches[tile] = size;
  EXPECT_LE(batches[0], 5);  // a guided share of the cost: 380 / (4 * 2) is 5 tiles of 10

  // Tiles nearly free last time do not make a batch larger than counting tiles would: what was
  // cheap may not be now.
  std::fill(costs.begin(), costs.end(), 1e-6f);
  for (int i = 150; i < 200; ++i) costs[i] = 10.f;
  FakeDevice e, f;
  Outcome third = RunAll({&e, &f}, 200, /*stable=*/false, 1, 0, costs);
  ASSERT_TRUE(third.status.ok()) << third.status;
  batches = e.batch_of_tile();
  for (const auto& [tile, size] : f.batch_of_tile()) batches[tile] = size;
  EXPECT_LE(batches[0], 25);  // the count's share: 200 / (4 * 2)
}

TEST(DispatcherTest, StableOwnershipKeepsTileIOnDeviceIModN) {
  FakeDevice a, b, c;
  Outcome out = RunAll({&a, &b, &c}, 50, /*stable=*/true, /*threads=*/4);
  ASSERT_TRUE(out.status.ok()) << out.status;
  ASSERT_EQ(out.device_of_tile.size(), 50u);
  for (const auto& [tile, device] : out.device_of_tile) EXPECT_EQ(device, tile % 3) << tile;
}

TEST(DispatcherTest, LostDeviceTilesRunOnTheOthers) {
  for (bool stable : {false, true}) {
    // Dynamic: lost at its first call (fast fakes may leave it no second one); stable: at its
    // second, after it finished one batch.
    // Stable ownership gives each device 100 tiles, more than one batch holds (64 of them).
    const size_t tiles = stable ? 300 : 60;
    FakeDevice a, b(FakeDevice::Fault::kUnavailable, /*fault_at_call=*/stable ? 1 : 0), c;
    Outcome out = RunAll({&a, &b, &c}, tiles, stable);
    ASSERT_TRUE(out.status.ok()) << out.status;
    EXPECT_EQ(out.device_of_tile.size(), tiles);
    EXPECT_EQ(out.tile_reports, tiles);
    ASSERT_EQ(out.lost.size(), 1u);
    EXPECT_EQ(out.lost[0].device, 1u);
    EXPECT_NE(out.lost[0].reason.message().find("connection reset"), std::string::npos);
    if (stable) {
      // Device 1 finished its first batch (tiles 1, 4, 7, ...); the rest moved by index over
      // the survivors {0, 2}.
      for (const auto& [tile, device] : out.device_of_tile) {
        if (tile % 3 != 1) {
          EXPECT_EQ(device, tile % 3);
        } else if (device != 1) {
          EXPECT_EQ(device, tile % 2 == 0 ? 0u : 2u) << tile;
        }
      }
    }
  }
}

TEST(DispatcherTest, EveryDeviceLostIsUnavailable) {
  FakeDevice a(FakeDevice::Fault::kUnavailable), b(FakeDevice::Fault::kUnavailable);
  Outcome out = RunAll({&a, &b}, 10, false);
  EXPECT_EQ(out.status.code(), absl::StatusCode::kUnavailable);
  EXPECT_NE(out.status.message().find("every device was lost"), std::string::npos);
  EXPECT_NE(out.status.message().find("fake0"), std::string::npos);
}

TEST(DispatcherTest, CrashFailsTheLaunchNamingTheProgram) {
  FakeDevice a, b(FakeDevice::Fault::kCrash);
  Outcome out = RunAll({&a, &b}, 40, false);
  EXPECT_EQ(out.status.code(), absl::StatusCode::kAborted);
  EXPECT_NE(out.status.message().find("closest hit program"), std::string::npos);
  EXPECT_EQ(out.failed_device, 1);
  ASSERT_EQ(out.lost.size(), 1u);
}

TEST(DispatcherTest, ProgramErrorFailsWithoutRetrying) {
  FakeDevice a(FakeDevice::Fault::kProgramError), b(FakeDevice::Fault::kProgramError);
  Outcome out = RunAll({&a, &b}, 40, false);
  EXPECT_EQ(out.status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_TRUE(out.lost.empty());
}

TEST(DispatcherTest, TileLosingTwoDevicesFailsTheLaunch) {
  // Every device is lost at its first call: the one tile hops to a second device, loses that one
  // too, and the rule stops it there (a program that kills workers would kill them all).
  FakeDevice a(FakeDevice::Fault::kUnavailable), b(FakeDevice::Fault::kUnavailable),
      c(FakeDevice::Fault::kUnavailable);
  std::vector<DispatchDevice> devices = {{&a, "a", 1, {}}, {&b, "b", 1, {}}, {&c, "c", 1, {}}};
  Dispatcher dispatcher(std::move(devices), MakeTiles({1}, {1}), /*stable_ownership=*/false);
  std::vector<FinishedBatch> batches;
  while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
  }
  EXPECT_EQ(dispatcher.status().code(), absl::StatusCode::kAborted);
  EXPECT_NE(dispatcher.status().message().find("tile 0 was running alone on"), std::string::npos)
      << dispatcher.status();
  EXPECT_EQ(dispatcher.lost().size(), 2u);
}

// Two or three workers killed at one moment: the first loss makes its tile a suspect, and the
// next device takes it alone but is already dead (it never says it started the call). That is no
// evidence against the tile: it runs on the device that is left and the launch succeeds.
TEST(DispatcherTest, SimultaneousLossesNeverBlameATile) {
  for (int dead : {2, 3}) {
    FakeDevice a(FakeDevice::Fault::kUnavailable), b(FakeDevice::Fault::kUnavailable),
        c(FakeDevice::Fault::kUnavailable), d;
    for (FakeDevice* f : {&a, &b, &c}) f->set_dead_before_start();
    std::vector<FakeDevice*> fakes = {&a, &b};
    if (dead == 3) fakes.push_back(&c);
    fakes.push_back(&d);
    for (size_t tiles : {size_t{1}, size_t{40}}) {
      for (bool stable : {false, true}) {
        Outcome out = RunAll(fakes, tiles, stable);
        ASSERT_TRUE(out.status.ok()) << dead << " dead, " << tiles << " tiles: " << out.status;
        // With stable ownership tile 0 starts on the first dead device and its suspect moves to
        // the next by index, so every dead device gets it; shared queues may give it to the
        // healthy one first.
        if (stable) {
          EXPECT_EQ(out.lost.size(), static_cast<size_t>(dead));
        }
        EXPECT_EQ(out.device_of_tile.size(), tiles);
        for (const auto& [tile, device] : out.device_of_tile) {
          EXPECT_EQ(device, fakes.size() - 1) << "tile " << tile;
        }
      }
    }
  }
}

// Two devices lost independently, each while running a batch of many tiles (two workers killed
// in one launch): their tiles run on the others, one per call, and the launch succeeds.
TEST(DispatcherTest, TwoIndependentLossesCostTimeNotTheLaunch) {
  for (bool stable : {false, true}) {
    FakeDevice a(FakeDevice::Fault::kUnavailable), b(FakeDevice::Fault::kUnavailable), c, d;
    a.set_fault_delay(std::chrono::milliseconds(40));
    b.set_fault_delay(std::chrono::milliseconds(40));
    Outcome out = RunAll({&a, &b, &c, &d}, 200, stable);
    ASSERT_TRUE(out.status.ok()) << out.status;
    EXPECT_EQ(out.lost.size(), 2u);
    EXPECT_EQ(out.device_of_tile.size(), 200u);
    EXPECT_EQ(out.tile_reports, 200u);
    // The lost batches' tiles ran one per call.
    std::map<uint32_t, int> c_batches = c.batch_of_tile(), d_batches = d.batch_of_tile();
    size_t solo = 0;
    for (const auto& [tile, size] : c_batches) solo += size == 1;
    for (const auto& [tile, size] : d_batches) solo += size == 1;
    EXPECT_GT(solo, 0u);
  }
}

// Runs its calls one at a time, numbering them, but takes a while to return every odd-numbered
// call's results after running it, as a worker does when sending: the next call runs and returns
// meanwhile.
class OverlappingDevice : public Device {
 public:
  DeviceInfo Info() const override { return {"overlapping", "overlapping", 1}; }
  absl::Status Apply(const v1::StateDelta&) override { return absl::OkStatus(); }
  absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>&,
                      const std::function<void(v1::TileResult&&)>& on_result) override {
    uint64_t sequence;
    {
      std::lock_guard<std::mutex> running(run_mu_);
      sequence = ++calls_;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (sequence % 2 == 1) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    v1::TileResult final_result;
    final_result.set_tile_index(kFinalTileIndex);
    final_result.set_call_sequence(sequence);
    for (const v1::Tile& t : request.tiles()) {
      final_result.add_regions()->set_offset(t.index());
    }
    on_result(std::move(final_result));
    return absl::OkStatus();
  }

 private:
  std::mutex run_mu_;
  uint64_t calls_ = 0;
};

TEST(DispatcherTest, BatchesComeInTheOrderTheirDeviceRanThem) {
  OverlappingDevice a, b;
  std::vector<DispatchDevice> devices = {{&a, "a", 1, {}}, {&b, "b", 1, {}}};
  Dispatcher dispatcher(std::move(devices), MakeTiles({64 * kTileIndices}, {kTileIndices}), false);
  std::vector<FinishedBatch> batches;
  while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
  }
  ASSERT_TRUE(dispatcher.status().ok()) << dispatcher.status();
  std::vector<uint64_t> last(2, 0);
  size_t tiles = 0;
  for (const FinishedBatch& batch : batches) {
    EXPECT_EQ(batch.sequence, last[batch.device] + 1) << "device " << batch.device;
    last[batch.device] = batch.sequence;
    tiles += batch.tiles;
  }
  EXPECT_EQ(tiles, 64u);
  EXPECT_GE(last[0] + last[1], 4u) << "several calls per device, so that order could break";
}

TEST(DispatcherTest, CancelStopsRunningCallsPromptly) {
  FakeDevice a(FakeDevice::Fault::kBlockUntilCancel), b(FakeDevice::Fault::kBlockUntilCancel);
  std::vector<DispatchDevice> devices = {{&a, "a", 1, {}}, {&b, "b", 1, {}}};
  std::atomic<uint64_t> progress{0};
  Dispatcher dispatcher(std::move(devices), MakeTiles({100 * kTileIndices}, {kTileIndices}), false,
                        &progress);
  std::vector<FinishedBatch> batches;
  EXPECT_FALSE(dispatcher.Wait(steady_clock::now() + std::chrono::milliseconds(20), &batches));
  const uint64_t reported = progress.load();
  EXPECT_GT(reported, 0u);  // the calls' heartbeats
  const auto start = steady_clock::now();
  dispatcher.Cancel();
  while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
  }
  EXPECT_LT(steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_EQ(dispatcher.status().code(), absl::StatusCode::kCancelled);
  EXPECT_TRUE(batches.empty());
  // Progress goes down only when a device is lost, not when the launch is cancelled.
  EXPECT_EQ(progress.load(), reported);
}

// A process that may start no more threads (RLIMIT_NPROC, as an unprivileged user) gets a
// failed launch saying so, not std::terminate from a half-built dispatcher.
TEST(DispatcherTest, ThreadsThatCannotStartFailTheLaunch) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to become an unprivileged user with no threads";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    alarm(30);
    // nobody (65534) runs nothing here: with RLIMIT_NPROC 1 it may not create another thread.
    const rlimit one{1, 1};
    if (setgid(65534) != 0 || setuid(65534) != 0 || setrlimit(RLIMIT_NPROC, &one) != 0) _exit(3);
    // Whatever escapes must end the child here, not run the rest of the suite in it.
    int code = 2;
    try {
      FakeDevice a, b;
      std::vector<DispatchDevice> devices;
      devices.push_back({&a, "fake0", 1, v1::LaunchRequest()});
      devices.push_back({&b, "fake1", 1, v1::LaunchRequest()});
      Dispatcher dispatcher(std::move(devices), MakeTiles({8 * kTileIndices}, {kTileIndices}),
                            false);
      std::vector<FinishedBatch> batches;
      while (!dispatcher.Wait(steady_clock::time_point::max(), &batches)) {
      }
      const absl::Status status = dispatcher.status();
      code = status.code() == absl::StatusCode::kResourceExhausted &&
                     status.message().find("could not start the launch's 4 dispatch threads") !=
                         std::string::npos
                 ? 0
                 : 1;
    } catch (...) {
    }
    _exit(code);
  }
  int wstatus = 0;
  ASSERT_EQ(waitpid(child, &wstatus, 0), child);
  ASSERT_TRUE(WIFEXITED(wstatus)) << "the child died of signal " << WTERMSIG(wstatus);
  EXPECT_EQ(WEXITSTATUS(wstatus), 0)
      << "1: wrong status, 2: an exception escaped, 3: could not drop privileges";
}

}  // namespace
}  // namespace tessera::scheduler
