// Real tessera-worker processes driven through the transport (GrpcDevice, WorkerProcess): health on
// an ephemeral TCP port, refusal of non-loopback addresses, deltas rejected and recovered from,
// tiles and whole-buffer final results across the process boundary.
#include "transport/worker_process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "tessera/rt.h"
#include "transport/grpc_device.h"
#include "transport/result_arena.h"
#include "transport/worker_wire.h"
#include "write_index_delta.h"

namespace tessera::e2e {
namespace {

using transport::GrpcDevice;
using transport::WorkerProcess;

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";

// Sets an environment variable (or unsets it: null) for a scope, then restores what it was:
// tools/sanitize.sh names a TESSERA_WORKER_LOG_DIR for every test, to read workers' logs for
// sanitizer reports, and the tests of where logs go must neither see it nor lose it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    Set(value);
  }
  ~ScopedEnv() { Set(had_ ? old_.c_str() : nullptr); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

  void Set(const char* value) {
    if (value != nullptr) {
      setenv(name_, value, 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

std::unique_ptr<WorkerProcess> Spawn(WorkerProcess::Options options) {
  auto process = WorkerProcess::Spawn(std::move(options));
  EXPECT_TRUE(process.ok()) << process.status();
  return process.ok() ? *std::move(process) : nullptr;
}

v1::StateDelta WriteIndexDelta(uint64_t sequence, uint64_t w, uint64_t h) {
  return ::tessera::testing::WriteIndexDelta(kModule, 77, sequence, w, h);
}

// Two tiles side by side over a w×h launch.
v1::LaunchRequest TwoTiles(uint64_t w, uint64_t h) {
  v1::LaunchRequest request;
  request.set_session_id(77);
  request.set_launch_id(5);
  request.add_dims(w);
  request.add_dims(h);
  for (uint32_t i = 0; i < 2; ++i) {
    v1::Tile* tile = request.add_tiles();
    tile->set_index(i);
    tile->add_origin(i * (w / 2));
    tile->add_origin(0);
    tile->add_size(i == 0 ? w / 2 : w - w / 2);
    tile->add_size(h);
  }
  return request;
}

TEST(WorkerProcessTest, WorkerOnAnEphemeralPortAnswersHealth) {
  WorkerProcess::Options options;
  options.listen = "127.0.0.1:0";
  options.threads = 1;
  std::unique_ptr<WorkerProcess> worker = Spawn(options);
  ASSERT_NE(worker, nullptr);
  const std::string& address = worker->address();
  ASSERT_EQ(address.rfind("127.0.0.1:", 0), 0u) << address;
  EXPECT_NE(address, "127.0.0.1:0");  // the real port

  auto device = GrpcDevice::Connect(address);
  ASSERT_TRUE(device.ok()) << device.status();
  EXPECT_EQ((*device)->health().pid, worker->pid());
  EXPECT_EQ((*device)->health().thread_count, 1);
  EXPECT_FALSE((*device)->health().version.empty());
  DeviceInfo info = (*device)->Info();
  EXPECT_EQ(info.name, "worker");
  EXPECT_EQ(info.address, address);
  EXPECT_EQ(info.thread_count, 1);
  auto again = (*device)->Health();
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(again->pid, worker->pid());
}

// Spawning a worker runs none of the application's pthread_atfork handlers (gRPC's, when its
// fork support is on, stop and restart its threads; others may be as costly), and a worker spawned
// while the application has signals blocked or caught still starts and stops normally.
std::atomic<int> g_atfork_calls{0};

TEST(WorkerProcessTest, SpawningRunsNoAtforkHandlers) {
  static const bool kRegistered = [] {
    pthread_atfork([] { ++g_atfork_calls; }, nullptr, nullptr);
    return true;
  }();
  (void)kRegistered;
  struct sigaction caught;
  std::memset(&caught, 0, sizeof(caught));
  caught.sa_handler = [](int) {};
  struct sigaction saved;
  ASSERT_EQ(sigaction(SIGTERM, &caught, &saved), 0);
  sigset_t block;
  sigset_t old_mask;
  sigemptyset(&block);
  sigaddset(&block, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &block, &old_mask);
  const int before = g_atfork_calls.load();
  WorkerProcess::Options options;
  options.threads = 1;
  std::unique_ptr<WorkerProcess> worker = Spawn(options);
  pthread_sigmask(SIG_SETMASK, &old_mask, nullptr);
  sigaction(SIGTERM, &saved, nullptr);
  ASSERT_NE(worker, nullptr);
  EXPECT_EQ(g_atfork_calls.load(), before);
  const pid_t pid = worker->pid();
  kill(pid, SIGTERM);  // default action in the worker, whatever the host does with SIGTERM
  // Exited and not yet reaped (the WorkerProcess reaps it): a zombie.
  auto state = [pid] {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(stat, line);
    const size_t paren = line.rfind(')');
    return paren == std::string::npos || paren + 2 >= line.size() ? '?' : line[paren + 2];
  };
  for (int i = 0; i < 500 && state() != 'Z'; ++i) usleep(10000);
  EXPECT_EQ(state(), 'Z') << "the worker did not stop on SIGTERM";
}

TEST(WorkerProcessTest, NonLoopbackAddressWithoutTlsAndTokenIsRefused) {
  WorkerProcess::Options options;
  options.listen = "0.0.0.0:0";
  auto process = WorkerProcess::Spawn(options);
  ASSERT_FALSE(process.ok());
  EXPECT_EQ(process.status().code(), absl::StatusCode::kUnavailable);
  // The reason comes from the worker's stderr.
  EXPECT_NE(process.status().message().find("--tls-cert"), std::string::npos) << process.status();
  EXPECT_NE(process.status().message().find("exited with status 2"), std::string::npos)
      << process.status();
}

TEST(WorkerProcessTest, AMalformedListenAddressIsRefused) {
  // gRPC alone would listen on port 34463 (99999 wrapped), on 443 (no port), or at an empty
  // unix path that no host can name, and report that as success.
  for (const char* listen : {"127.0.0.1:99999", "127.0.0.1", "unix:"}) {
    WorkerProcess::Options options;
    options.listen = listen;
    auto process = WorkerProcess::Spawn(options);
    ASSERT_FALSE(process.ok()) << listen << " was taken";
    EXPECT_NE(process.status().message().find(std::string("--listen ") + listen + ":"),
              std::string::npos)
        << process.status();
    EXPECT_NE(process.status().message().find("exited with status 2"), std::string::npos)
        << process.status();
  }
}

TEST(WorkerProcessTest, AnUnservableThreadCountIsRefusedAtStart) {
  // TBB crashed the worker at its first launch with an arena of this many threads.
  WorkerProcess::Options options;
  options.extra_args = {"--threads", "2147483647"};
  auto process = WorkerProcess::Spawn(options);
  ASSERT_FALSE(process.ok());
  EXPECT_NE(process.status().message().find("--threads"), std::string::npos) << process.status();
}

TEST(WorkerProcessTest, AWorkerThatNeverListensTimesOutWithItsStderr) {
  char dir[] = "/tmp/tessera-e2e-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string script = std::string(dir) + "/silent-worker";
  {
    FILE* f = std::fopen(script.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("#!/bin/sh\necho starting up >&2\nexec sleep 30\n", f);
    std::fclose(f);
  }
  ASSERT_EQ(chmod(script.c_str(), 0755), 0);
  WorkerProcess::Options options;
  options.binary = script;
  options.start_timeout = absl::Milliseconds(300);
  auto process = WorkerProcess::Spawn(options);
  unlink(script.c_str());
  rmdir(dir);
  ASSERT_FALSE(process.ok());
  EXPECT_EQ(process.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_NE(process.status().message().find("did not report listening within"), std::string::npos)
      << process.status();
  EXPECT_NE(process.status().message().find("starting up"), std::string::npos) << process.status();
}

TEST(WorkerProcessTest, ATakenPortIsNotShared) {
  WorkerProcess::Options options;
  options.listen = "127.0.0.1:0";
  std::unique_ptr<WorkerProcess> first = Spawn(options);
  ASSERT_NE(first, nullptr);
  options.listen = first->address();
  auto second = WorkerProcess::Spawn(options);
  ASSERT_FALSE(second.ok()) << "two workers listen on " << first->address();
  EXPECT_NE(second.status().message().find("cannot bind: Address already in use"),
            std::string::npos)
      << second.status();
}

TEST(WorkerProcessTest, ATakenUnixSocketIsNotTakenOver) {
  char dir[] = "/tmp/tessera-e2e-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  WorkerProcess::Options options;
  options.listen = std::string("unix:") + dir + "/w.sock";
  std::unique_ptr<WorkerProcess> first = Spawn(options);
  ASSERT_NE(first, nullptr);
  auto second = WorkerProcess::Spawn(options);
  EXPECT_FALSE(second.ok()) << "a second worker took over " << options.listen;
  if (!second.ok()) {
    EXPECT_NE(second.status().message().find("another process is listening"), std::string::npos)
        << second.status();
  }
  // The first still answers there.
  auto device = GrpcDevice::Connect(options.listen);
  ASSERT_TRUE(device.ok()) << device.status();
  EXPECT_EQ((*device)->health().pid, first->pid());
  device->reset();
  first.reset();
  std::filesystem::remove_all(dir);
}

TEST(WorkerProcessTest, NoWorkerAtTheAddressIsUnavailable) {
  auto device = GrpcDevice::Connect("unix:/nonexistent/tessera-e2e.sock", absl::Seconds(5));
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.status().code(), absl::StatusCode::kUnavailable) << device.status();
  EXPECT_NE(device.status().message().find("unix:/nonexistent/tessera-e2e.sock"), std::string::npos)
      << device.status();
}

TEST(WorkerProcessTest, OutOfOrderDeltaIsRejectedAndTheNextValidOneWorks) {
  std::unique_ptr<WorkerProcess> worker = Spawn({});
  ASSERT_NE(worker, nullptr);
  EXPECT_EQ(worker->address().rfind("unix:", 0), 0u) << worker->address();
  const pid_t pid = worker->pid();
  auto connected = GrpcDevice::Connect(std::move(worker));
  ASSERT_TRUE(connected.ok()) << connected.status();
  GrpcDevice& device = **connected;

  absl::Status s = device.Apply(WriteIndexDelta(2, 8, 8));  // 1 expected
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << s;
  EXPECT_NE(s.message().find("out of order"), std::string::npos) << s;
  EXPECT_NE(s.message().find(device.address()), std::string::npos) << s;
  ASSERT_TRUE(device.Apply(WriteIndexDelta(1, 8, 8)).ok());
  s = device.Apply(WriteIndexDelta(3, 16, 16));  // 2 expected
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << s;
  ASSERT_TRUE(device.Apply(WriteIndexDelta(2, 10, 6)).ok());
  EXPECT_EQ(kill(pid, 0), 0) << "the worker stays up";

  std::atomic<bool> cancel{false};
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(device
                  .Launch(TwoTiles(10, 6), cancel,
                          [&](v1::TileResult&& r) { results.push_back(std::move(r)); })
                  .ok());
  // Tiles that neither print nor raise send nothing of their own: one result, the contents.
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results.back().tile_index(), kFinalTileIndex);
  ASSERT_EQ(results.back().regions_size(), 1);
  const std::string& bytes = results.back().regions(0).data();
  ASSERT_EQ(bytes.size(), 10u * 6u * 16u);
  std::vector<float> f(bytes.size() / 4);
  std::memcpy(f.data(), bytes.data(), bytes.size());
  EXPECT_EQ(f[4 * (5 * 10 + 9)], 9.f);
  EXPECT_EQ(f[4 * (5 * 10 + 9) + 1], 5.f);
}

// A worker someone else runs outlives its hosts: a device that goes (its context destroyed)
// ends its session there, so the worker holds no replica for it any more.
TEST(WorkerProcessTest, ADeviceThatGoesEndsItsSessionOnARunningWorker) {
  std::unique_ptr<WorkerProcess> worker = Spawn({});
  ASSERT_NE(worker, nullptr);
  const std::string address = worker->address();
  {
    auto device = GrpcDevice::Connect(address);
    ASSERT_TRUE(device.ok()) << device.status();
    ASSERT_TRUE((*device)->Apply(WriteIndexDelta(1, 8, 8)).ok());
  }
  auto device = GrpcDevice::Connect(address);
  ASSERT_TRUE(device.ok()) << device.status();
  std::atomic<bool> cancel{false};
  absl::Status s = (*device)->Launch(TwoTiles(8, 8), cancel, [](v1::TileResult&&) {});
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << s;
  EXPECT_NE(s.message().find("no state for session"), std::string::npos) << s;
}

TEST(WorkerProcessTest, LargeWrittenRegionsArriveInBoundedMessages) {
  std::unique_ptr<WorkerProcess> worker = Spawn({});
  ASSERT_NE(worker, nullptr);
  auto device = GrpcDevice::Connect(std::move(worker));
  ASSERT_TRUE(device.ok()) << device.status();
  constexpr uint64_t kW = 1024, kH = 700;  // 11 MiB: three messages on the wire
  const absl::Status applied = (*device)->Apply(WriteIndexDelta(1, kW, kH));
  ASSERT_TRUE(applied.ok()) << applied;
  std::atomic<bool> cancel{false};
  std::vector<v1::TileResult> finals;
  const absl::Status launched =
      (*device)->Launch(TwoTiles(kW, kH), cancel, [&](v1::TileResult&& r) {
        if (r.tile_index() == kFinalTileIndex) finals.push_back(std::move(r));
      });
  ASSERT_TRUE(launched.ok()) << launched;
  // Several messages, each within the bound, that together hold the whole buffer.
  EXPECT_GE(finals.size(), 3u);
  std::string buffer;
  for (const v1::TileResult& piece : finals) {
    for (const v1::BufferRegion& region : piece.regions()) {
      EXPECT_LE(region.data().size(), transport::kMaxRegionBytes);
      ::tessera::testing::ApplyRegion(region, 2, &buffer);
    }
  }
  ASSERT_EQ(buffer.size(), kW * kH * 16);
  float last[4];
  std::memcpy(last, buffer.data() + (kW * kH - 1) * 16, 16);
  EXPECT_EQ(last[0], kW - 1.f);
  EXPECT_EQ(last[1], kH - 1.f);
}

TEST(WorkerProcessTest, StartupWarningsReachTheHostOnce) {
  // Every worker inherits the malformed value and warns about it while starting.
  ASSERT_EQ(setenv("TESSERA_MODULE_CACHE_MAX_MB", "plenty", 1), 0);
  ::testing::internal::CaptureStderr();
  WorkerProcess::Options second;
  second.index = 1;
  std::unique_ptr<WorkerProcess> a = Spawn({}), b = Spawn(second);
  const std::string err = ::testing::internal::GetCapturedStderr();
  unsetenv("TESSERA_MODULE_CACHE_MAX_MB");
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  const std::string warning = "TESSERA_MODULE_CACHE_MAX_MB='plenty' is not a positive number";
  const size_t first = err.find(warning);
  ASSERT_NE(first, std::string::npos) << err;
  EXPECT_EQ(err.find(warning, first + 1), std::string::npos) << "said once: " << err;
  EXPECT_NE(err.find("local worker 0 at startup"), std::string::npos) << err;
}

TEST(WorkerProcessTest, LogsStayInTheLogDirectoryWhenOneIsNamed) {
  const std::string dir = ::testing::TempDir() + "/worker_logs_" + std::to_string(getpid());
  ScopedEnv log_dir("TESSERA_WORKER_LOG_DIR", dir.c_str());
  std::string first, second;
  {
    std::unique_ptr<WorkerProcess> a = Spawn({}), b = Spawn({});  // same index, two spawns
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    first = a->log_path();
    second = b->log_path();
  }
  EXPECT_EQ(first.rfind(dir + "/tessera-worker-", 0), 0u) << first;
  EXPECT_NE(first, second) << "a respawn gets its own log";
  EXPECT_EQ(access(first.c_str(), F_OK), 0) << "kept after the worker is gone";
  EXPECT_EQ(access(second.c_str(), F_OK), 0);
  std::filesystem::remove_all(dir);

  // A directory that cannot take logs costs the logs, not the worker.
  log_dir.Set("/proc/no/such/dir");
  ::testing::internal::CaptureStderr();
  std::unique_ptr<WorkerProcess> c = Spawn({});
  const std::string err = ::testing::internal::GetCapturedStderr();
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->log_path().rfind("/proc/", 0), std::string::npos) << c->log_path();
  EXPECT_NE(err.find("TESSERA_WORKER_LOG_DIR=/proc/no/such/dir"), std::string::npos) << err;
}

// A host killed by a signal leaves its workers' directories behind (no atexit handler runs); the
// next host to spawn workers in that temporary directory removes those whose host is gone.
TEST(WorkerProcessTest, DirectoriesOfHostsThatAreGoneAreRemoved) {
  char tmp[] = "/tmp/tessera-sweep-XXXXXX";
  ASSERT_NE(mkdtemp(tmp), nullptr);
  const std::string base = tmp;
  pid_t gone = fork();  // a pid that no longer exists once reaped
  if (gone == 0) _exit(0);
  ASSERT_GT(gone, 0);
  ASSERT_EQ(waitpid(gone, nullptr, 0), gone);
  auto make = [&](const std::string& name, long host) {
    const std::string dir = base + "/" + name;
    EXPECT_EQ(mkdir(dir.c_str(), 0700), 0);
    std::ofstream(dir + "/w0.log") << "log";
    if (host > 0) std::ofstream(dir + "/host.pid") << host << "\n";
    return dir;
  };
  const std::string stale = make("tessera-w-stale1", gone);
  const std::string live = make("tessera-w-live01", getpid());
  const std::string unnamed = make("tessera-w-older1", 0);
  const char* old_tmp = std::getenv("TMPDIR");
  const std::string saved = old_tmp != nullptr ? old_tmp : "";
  setenv("TMPDIR", base.c_str(), 1);
  std::unique_ptr<WorkerProcess> worker;
  {
    ScopedEnv no_log_dir("TESSERA_WORKER_LOG_DIR", nullptr);  // the log is in the directory
    worker = Spawn({});
  }
  if (old_tmp != nullptr) {
    setenv("TMPDIR", saved.c_str(), 1);
  } else {
    unsetenv("TMPDIR");
  }
  ASSERT_NE(worker, nullptr);
  EXPECT_FALSE(std::filesystem::exists(stale)) << "its host is gone";
  EXPECT_TRUE(std::filesystem::exists(live)) << "its host (this one) runs";
  EXPECT_TRUE(std::filesystem::exists(unnamed)) << "no host named: left alone";
  EXPECT_EQ(worker->log_path().rfind(base + "/tessera-w-", 0), 0u) << worker->log_path();
  worker.reset();
  std::filesystem::remove_all(base);
}

TEST(WorkerProcessTest, DestructionStopsTheWorker) {
  ScopedEnv no_log_dir("TESSERA_WORKER_LOG_DIR", nullptr);  // the log goes with its directory
  std::unique_ptr<WorkerProcess> worker = Spawn({});
  ASSERT_NE(worker, nullptr);
  const pid_t pid = worker->pid();
  const std::string log = worker->log_path();
  ASSERT_EQ(kill(pid, 0), 0);
  worker.reset();
  EXPECT_EQ(kill(pid, 0), -1) << "reaped, not a zombie";
  EXPECT_EQ(errno, ESRCH);
  EXPECT_NE(access(log.c_str(), F_OK), 0) << "its directory is removed";
}

// A worker this host spawned shares memory with it: written regions come back through it, the
// same bytes as through the socket; TESSERA_RESULT_ARENA=0 keeps them in the messages.
std::string LaunchThroughWorker(bool arena, uint64_t* restored) {
  if (!arena) setenv("TESSERA_RESULT_ARENA", "0", 1);
  std::unique_ptr<WorkerProcess> worker = Spawn({});
  unsetenv("TESSERA_RESULT_ARENA");
  if (worker == nullptr) return "";
  EXPECT_EQ(worker->result_arena() != nullptr, arena);
  auto connected = GrpcDevice::Connect(std::move(worker));
  EXPECT_TRUE(connected.ok()) << connected.status();
  if (!connected.ok()) return "";
  GrpcDevice& device = **connected;
  EXPECT_TRUE(device.Apply(WriteIndexDelta(1, 128, 96)).ok());
  std::atomic<bool> cancel{false};
  std::string image(128 * 96 * 16, '\0');
  absl::Status s = device.Launch(TwoTiles(128, 96), cancel, [&](v1::TileResult&& r) {
    for (const v1::BufferRegion& region : r.regions()) {
      EXPECT_EQ(region.arena_size(), 0u) << "restored before the host sees it";
      if (region.run_offsets_size() == 0) {
        image.replace(region.offset(), region.data().size(), region.data());
        continue;
      }
      size_t at = 0;
      for (int i = 0; i < region.run_offsets_size(); ++i) {
        image.replace(region.run_offsets(i), region.run_sizes(i), region.data(), at,
                      region.run_sizes(i));
        at += region.run_sizes(i);
      }
    }
  });
  EXPECT_TRUE(s.ok()) << s;
  *restored = device.process()->result_arena() != nullptr
                  ? device.process()->result_arena()->restored_bytes()
                  : 0;
  return image;
}

TEST(WorkerProcessTest, SpawnedWorkersReturnRegionsThroughSharedMemory) {
  uint64_t through_arena = 0, through_socket = 0;
  const std::string a = LaunchThroughWorker(true, &through_arena);
  const std::string b = LaunchThroughWorker(false, &through_socket);
  EXPECT_EQ(through_arena, 128u * 96u * 16u);
  EXPECT_EQ(through_socket, 0u);
  EXPECT_EQ(a, b);
  std::vector<float> f(a.size() / 4);
  std::memcpy(f.data(), a.data(), a.size());
  EXPECT_EQ(f[4 * (95 * 128 + 127)], 127.f);
  EXPECT_EQ(f[4 * (95 * 128 + 127) + 1], 95.f);
}

}  // namespace
}  // namespace tessera::e2e
