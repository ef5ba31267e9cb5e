// Bounded workers: sessions dropped when idle, a limit on how many a worker holds, what Health
// says about them, and a server that refuses floods (server_options.h) instead of starting a
// thread per call or answering every ping.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server_options.h"
#include "tessera/worker/module_cache.h"
#include "transport/worker_wire.h"
#include "worker_service.h"
#include "write_index_delta.h"

namespace tessera::worker {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";

v1::StateDelta Delta(uint64_t session, uint64_t sequence, uint64_t w = 8, uint64_t h = 8) {
  return ::tessera::testing::WriteIndexDelta(kModule, session, sequence, w, h);
}

std::vector<v1::ApplyChunk> Messages(const v1::StateDelta& delta) {
  std::vector<v1::ApplyChunk> messages;
  transport::WriteApplyStream(delta, [&](const v1::ApplyChunk& m) {
    messages.push_back(m);
    return true;
  });
  return messages;
}

class SessionLimitsTest : public ::testing::Test {
 protected:
  void TearDown() override {
    if (server_ != nullptr) server_->Shutdown();
    std::error_code ec;
    if (!module_cache_.empty()) std::filesystem::remove_all(module_cache_, ec);
  }

  // A worker service with `limits` behind a server configured as tessera-worker configures it.
  void Start(SessionLimits limits) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "tessera-limits-test-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    module_cache_ = pattern;
    SetModuleCacheDirectory(module_cache_);
    service_ = std::make_unique<WorkerService>(1, nullptr, limits);
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
    builder.RegisterService(service_.get());
    ConfigureServer(&builder, limits.max_sessions);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    stub_ = v1::Worker::NewStub(Channel());
  }

  // A channel of its own connection (gRPC shares one between channels with the same arguments).
  std::shared_ptr<grpc::Channel> Channel(grpc::ChannelArguments args = grpc::ChannelArguments()) {
    args.SetMaxReceiveMessageSize(transport::kMaxMessageBytes);
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
    return grpc::CreateCustomChannel("127.0.0.1:" + std::to_string(port_),
                                     grpc::InsecureChannelCredentials(), args);
  }

  grpc::Status Apply(const v1::StateDelta& delta) {
    grpc::ClientContext context;
    v1::ApplyReply reply;
    auto writer = stub_->Apply(&context, &reply);
    for (const v1::ApplyChunk& m : Messages(delta)) {
      if (!writer->Write(m)) break;
    }
    writer->WritesDone();
    return writer->Finish();
  }

  grpc::Status Launch(uint64_t session, uint64_t w = 8, uint64_t h = 8) {
    v1::LaunchRequest request;
    request.set_session_id(session);
    request.set_launch_id(1);
    request.add_dims(w);
    request.add_dims(h);
    v1::Tile* tile = request.add_tiles();
    tile->add_origin(0);
    tile->add_origin(0);
    tile->add_size(w);
    tile->add_size(h);
    grpc::ClientContext context;
    auto reader = stub_->Launch(&context, request);
    v1::TileResult result;
    while (reader->Read(&result)) {
    }
    return reader->Finish();
  }

  grpc::Status EndSession(uint64_t session) {
    grpc::ClientContext context;
    v1::EndSessionRequest request;
    request.set_session_id(session);
    v1::EndSessionReply reply;
    return stub_->EndSession(&context, request, &reply);
  }

  v1::HealthReply Health() {
    grpc::ClientContext context;
    v1::HealthReply reply;
    EXPECT_TRUE(stub_->Health(&context, v1::HealthRequest(), &reply).ok());
    return reply;
  }

  // Waits up to `limit` for the worker to hold `count` sessions.
  bool WaitForSessions(uint32_t count, std::chrono::milliseconds limit) {
    const auto end = Clock::now() + limit;
    while (Clock::now() < end) {
      if (Health().sessions() == count) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return Health().sessions() == count;
  }

  std::string module_cache_;
  std::unique_ptr<WorkerService> service_;
  int port_ = 0;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Worker::Stub> stub_;
};

SessionLimits Limits(double idle_seconds, int max_sessions) {
  SessionLimits limits;
  limits.idle_timeout = absl::Seconds(idle_seconds);
  limits.max_sessions = max_sessions;
  return limits;
}

TEST_F(SessionLimitsTest, AnIdleSessionIsDroppedAndItsHostIsToldWhyWhenItComesBack) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(1, 64)));
  ASSERT_TRUE(Apply(Delta(7, 1)).ok());
  ASSERT_TRUE(Launch(7).ok());
  ASSERT_EQ(Health().sessions(), 1u);
  // Dropped within 1.25 timeouts of its last call.
  ASSERT_TRUE(WaitForSessions(0, std::chrono::milliseconds(3000)));

  // The host that comes back loses the device (UNAVAILABLE) and starts a new session.
  grpc::Status s = Launch(7);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  for (const char* part : {"tessera-worker@", "dropped session 7", "without a call",
                           "--session-idle-timeout 1", "starts the session afresh"}) {
    EXPECT_NE(s.error_message().find(part), std::string::npos) << part << ": " << s.error_message();
  }
  s = Apply(Delta(7, 2));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  ASSERT_TRUE(Apply(Delta(7, 1)).ok());
  EXPECT_TRUE(Launch(7).ok());

  // A session the worker never held is still a host's mistake, not a lost device.
  s = Launch(99);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION) << s.error_message();
  s = Apply(Delta(99, 2));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION) << s.error_message();
  EXPECT_NE(s.error_message().find("out of order"), std::string::npos) << s.error_message();
}

// A call under way keeps its session, however long it takes: here a state update whose messages
// stop coming for twice the timeout.
TEST_F(SessionLimitsTest, ASessionInACallIsNotDropped) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(1, 64)));
  ASSERT_TRUE(Apply(Delta(8, 1)).ok());
  grpc::ClientContext context;
  v1::ApplyReply reply;
  auto writer = stub_->Apply(&context, &reply);
  const std::vector<v1::ApplyChunk> messages = Messages(Delta(8, 2, 6, 6));
  ASSERT_TRUE(writer->Write(messages.front()));
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  const v1::HealthReply during = Health();
  ASSERT_EQ(during.sessions(), 1u);
  EXPECT_TRUE(during.session_list(0).busy());
  EXPECT_EQ(during.session_list(0).idle_seconds(), 0.0);
  for (size_t i = 1; i < messages.size(); ++i) ASSERT_TRUE(writer->Write(messages[i]));
  writer->WritesDone();
  grpc::Status s = writer->Finish();
  ASSERT_TRUE(s.ok()) << s.error_message();
  EXPECT_TRUE(Launch(8, 6, 6).ok());
}

TEST_F(SessionLimitsTest, ASessionPastTheLimitIsRefusedNamingWorkerLimitAndFlag) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(0, 2)));
  ASSERT_TRUE(Apply(Delta(1, 1)).ok());
  ASSERT_TRUE(Apply(Delta(2, 1)).ok());
  grpc::Status s = Apply(Delta(3, 1));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
  for (const char* part : {"tessera-worker@", "already holds 2 sessions", "--max-sessions 2"}) {
    EXPECT_NE(s.error_message().find(part), std::string::npos) << part << ": " << s.error_message();
  }
  // The sessions it holds carry on, and one that ends makes room.
  EXPECT_TRUE(Apply(Delta(2, 2)).ok());
  EXPECT_TRUE(Launch(1).ok());
  ASSERT_TRUE(EndSession(1).ok());
  EXPECT_TRUE(Apply(Delta(3, 1)).ok());
  EXPECT_EQ(Health().sessions(), 2u);
}

TEST_F(SessionLimitsTest, SessionsIdlePastTheTimeoutMakeRoomForANewOne) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(1, 1)));
  ASSERT_TRUE(Apply(Delta(1, 1)).ok());
  grpc::Status s = Apply(Delta(2, 1));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
  EXPECT_NE(s.error_message().find("--session-idle-timeout 1"), std::string::npos)
      << s.error_message();
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  EXPECT_TRUE(Apply(Delta(2, 1)).ok());
  s = Launch(1);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
}

TEST_F(SessionLimitsTest, HealthReportsSessionsTheirMemoryAndTheLimits) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(300, 5)));
  v1::HealthReply empty = Health();
  EXPECT_EQ(empty.sessions(), 0u);
  EXPECT_EQ(empty.max_sessions(), 5u);
  EXPECT_EQ(empty.session_idle_timeout_seconds(), 300.0);
  EXPECT_GT(empty.resident_bytes(), 1u << 20);

  ASSERT_TRUE(Apply(Delta(21, 1, 64, 32)).ok());
  ASSERT_TRUE(Apply(Delta(20, 1, 8, 8)).ok());
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  v1::HealthReply two = Health();
  ASSERT_EQ(two.sessions(), 2u);
  ASSERT_EQ(two.session_list_size(), 2);
  EXPECT_EQ(two.session_list(0).session_id(), 20u);  // in order of id
  EXPECT_EQ(two.session_list(0).buffer_bytes(), 8u * 8u * 16u);
  EXPECT_EQ(two.session_list(1).session_id(), 21u);
  EXPECT_EQ(two.session_list(1).buffer_bytes(), 64u * 32u * 16u);
  EXPECT_FALSE(two.session_list(0).busy());
  EXPECT_GT(two.session_list(0).idle_seconds(), 0.0);
  EXPECT_LT(two.session_list(0).idle_seconds(), 60.0);

  // A resized buffer counts at its new size; an ended session is gone.
  ASSERT_TRUE(Apply(Delta(21, 2, 128, 128)).ok());
  ASSERT_TRUE(EndSession(20).ok());
  v1::HealthReply one = Health();
  ASSERT_EQ(one.session_list_size(), 1);
  EXPECT_EQ(one.session_list(0).buffer_bytes(), 128u * 128u * 16u);
}

TEST(CallCapacityTest, ScalesWithTheSessionLimit) {
  EXPECT_EQ(CallCapacity(1), 35);
  EXPECT_EQ(CallCapacity(64), 224);
  EXPECT_EQ(CallCapacity(0), 4096);        // no limit on sessions: still a bound
  EXPECT_EQ(CallCapacity(1 << 20), 4096);  // and never more
}

// A client that pings far more often than hosts do (every 30 s) is told to calm down and loses
// its connection; the worker keeps serving others.
TEST_F(SessionLimitsTest, APingFloodLosesItsConnection) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(0, 4)));
  grpc::ChannelArguments flood;
  flood.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 50);
  flood.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 1000);
  flood.SetInt(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  flood.SetInt(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  std::shared_ptr<grpc::Channel> channel = Channel(flood);
  ASSERT_TRUE(
      channel->WaitForConnected(std::chrono::system_clock::now() + std::chrono::seconds(5)));
  ASSERT_EQ(channel->GetState(false), GRPC_CHANNEL_READY);
  EXPECT_TRUE(channel->WaitForStateChange(
      GRPC_CHANNEL_READY, std::chrono::system_clock::now() + std::chrono::seconds(5)))
      << "the flooding connection stayed up";
  EXPECT_EQ(Health().sessions(), 0u);  // others are still served
}

int ThreadCount() {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) {
    (void)entry;
    ++count;
  }
  return count;
}

// Every call holds a server thread while it runs: past the worker's capacity no more threads
// start, a call is refused at once, and the worker serves again once the flood is over.
TEST_F(SessionLimitsTest, AFloodOfOpenCallsIsBoundedAndRefused) {
  ASSERT_NO_FATAL_FAILURE(Start(Limits(0, 1)));
  const int capacity = CallCapacity(1);
  ASSERT_EQ(Health().sessions(), 0u);  // the server's threads for one call are up
  const int before = ThreadCount();
  struct Open {
    grpc::ClientContext context;
    v1::ApplyReply reply;
    std::unique_ptr<grpc::ClientWriter<v1::ApplyChunk>> writer;
  };
  // Three connections, each with as many calls as the worker serves: together well past it.
  std::vector<std::unique_ptr<v1::Worker::Stub>> stubs;
  std::vector<std::unique_ptr<Open>> calls;
  const auto deadline = std::chrono::system_clock::now() + std::chrono::seconds(3);
  for (int c = 0; c < 3; ++c) {
    stubs.push_back(v1::Worker::NewStub(Channel()));
    for (int i = 0; i < capacity; ++i) {
      auto open = std::make_unique<Open>();
      open->context.set_deadline(deadline);
      open->writer = stubs.back()->Apply(&open->context, &open->reply);  // and nothing sent
      calls.push_back(std::move(open));
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_LE(ThreadCount(), before + capacity) << "a thread per call";
  {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(2));
    v1::HealthReply reply;
    const grpc::Status s = stub_->Health(&context, v1::HealthRequest(), &reply);
    EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
    EXPECT_EQ(s.error_message(), "Server Threadpool Exhausted");
  }
  for (auto& open : calls) EXPECT_FALSE(open->writer->Finish().ok());
  // Served again once the flood's calls have ended on the worker's side too.
  const auto end = Clock::now() + std::chrono::seconds(5);
  grpc::Status s;
  v1::HealthReply reply;
  while (true) {
    grpc::ClientContext context;
    s = stub_->Health(&context, v1::HealthRequest(), &reply);
    if (s.ok() || Clock::now() >= end) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(s.ok()) << s.error_message();
  EXPECT_EQ(reply.pid(), getpid());
}

}  // namespace
}  // namespace tessera::worker
