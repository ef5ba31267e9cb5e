// The Worker service through a real gRPC server on 127.0.0.1, driven by the raw stub so that
// malformed streams can be sent: errors come back as statuses and leave the session as it was.
#include "worker_service.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "tessera/rt.h"
#include "tessera/scheduler/device.h"
#include "tessera/worker/module_cache.h"
#include "transport/worker_wire.h"
#include "write_index_delta.h"

namespace tessera::worker {
namespace {

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";

class WorkerServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // Modules this test's worker receives go to a private cache directory.
    std::string pattern =
        (std::filesystem::temp_directory_path() / "tessera-worker-test-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    module_cache_ = pattern;
    SetModuleCacheDirectory(module_cache_);
    ASSERT_EQ(ModuleCacheDirectory(), module_cache_);

    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
    builder.RegisterService(&service_);
    builder.SetMaxReceiveMessageSize(transport::kMaxMessageBytes);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    ASSERT_NE(port_, 0);
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(transport::kMaxMessageBytes);
    stub_ = v1::Worker::NewStub(grpc::CreateCustomChannel(
        "127.0.0.1:" + std::to_string(port_), grpc::InsecureChannelCredentials(), args));
  }
  void TearDown() override {
    if (server_ != nullptr) server_->Shutdown();
    std::error_code ec;
    std::filesystem::remove_all(module_cache_, ec);
  }

  static v1::StateDelta WriteIndexDelta(uint64_t session, uint64_t sequence, uint64_t w, uint64_t h,
                                        bool ship_module = true) {
    return ::tessera::testing::WriteIndexDelta(kModule, session, sequence, w, h, ship_module);
  }

  grpc::Status Apply(const std::vector<v1::ApplyChunk>& messages) {
    grpc::ClientContext context;
    v1::ApplyReply reply;
    auto writer = stub_->Apply(&context, &reply);
    for (const v1::ApplyChunk& m : messages) {
      if (!writer->Write(m)) break;
    }
    writer->WritesDone();
    return writer->Finish();
  }
  // As GrpcDevice sends it; `module_bytes` counts the module bytes that travel.
  grpc::Status Apply(const v1::StateDelta& delta, size_t* module_bytes = nullptr) {
    std::vector<v1::ApplyChunk> messages;
    transport::WriteApplyStream(delta, [&](const v1::ApplyChunk& m) {
      messages.push_back(m);
      if (module_bytes != nullptr && m.has_module()) *module_bytes += m.module().data().size();
      return true;
    });
    return Apply(messages);
  }

  grpc::Status Launch(uint64_t session, uint64_t w, uint64_t h,
                      std::vector<v1::TileResult>* results, uint64_t launch_id = 1) {
    v1::LaunchRequest request;
    request.set_session_id(session);
    request.set_launch_id(launch_id);
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
    while (reader->Read(&result)) results->push_back(result);
    return reader->Finish();
  }

  // The final contents of buffer 2, joined from the final results.
  static std::string FinalOutput(const std::vector<v1::TileResult>& results) {
    std::string out;
    for (const v1::TileResult& r : results) {
      if (r.tile_index() != kFinalTileIndex) continue;
      for (const v1::BufferRegion& region : r.regions()) {
        ::tessera::testing::ApplyRegion(region, 2, &out);
      }
    }
    return out;
  }

  static void ExpectIndices(const std::string& bytes, uint64_t w, uint64_t h) {
    ASSERT_EQ(bytes.size(), w * h * 16);
    std::vector<float> f(w * h * 4);
    std::memcpy(f.data(), bytes.data(), bytes.size());
    for (uint64_t y = 0; y < h; y += h / 4 + 1) {
      for (uint64_t x = 0; x < w; x += w / 4 + 1) {
        EXPECT_EQ(f[4 * (y * w + x)], static_cast<float>(x));
        EXPECT_EQ(f[4 * (y * w + x) + 1], static_cast<float>(y));
      }
    }
  }

  WorkerService service_{2};
  std::string module_cache_;
  int port_ = 0;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Worker::Stub> stub_;
};

TEST_F(WorkerServiceTest, HealthReportsThreadsPidAndVersion) {
  grpc::ClientContext context;
  v1::HealthReply reply;
  ASSERT_TRUE(stub_->Health(&context, v1::HealthRequest(), &reply).ok());
  EXPECT_EQ(reply.thread_count(), 2u);
  EXPECT_EQ(reply.pid(), getpid());
  EXPECT_FALSE(reply.version().empty());
  EXPECT_EQ(reply.device_name().rfind("tessera-worker", 0), 0u) << reply.device_name();
}

// What the status endpoint reports: launches (not calls) and tiles.
TEST_F(WorkerServiceTest, StatsCountSessionsLaunchesAndTiles) {
  ASSERT_TRUE(Apply(WriteIndexDelta(5, 1, 16, 16)).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(5, 16, 16, &results, 1).ok());
  ASSERT_TRUE(Launch(5, 16, 16, &results, 1).ok());  // a second call of launch 1
  ASSERT_TRUE(Launch(5, 16, 16, &results, 2).ok());
  const WorkerService::Stats stats = service_.GetStats();
  EXPECT_EQ(stats.sessions, 1u);
  EXPECT_EQ(stats.launches, 2u);
  EXPECT_EQ(stats.tiles, 3u);
  EXPECT_GT(stats.tiles_per_s, 0.0);
  EXPECT_LE(stats.tiles_per_s, 3.0);
}

// A stopping worker (SIGTERM) finishes the launches under way and takes nothing new: no session,
// no state update, no other launch, no host looking for devices.
TEST_F(WorkerServiceTest, AStoppingWorkerFinishesLaunchesUnderWayAndRefusesNewWork) {
  ASSERT_TRUE(Apply(WriteIndexDelta(6, 1, 16, 16)).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(6, 16, 16, &results, 7).ok());
  service_.BeginShutdown("SIGTERM");
  EXPECT_TRUE(service_.shutting_down());
  EXPECT_TRUE(Launch(6, 16, 16, &results, 7).ok()) << "a call of the launch under way";
  grpc::Status s = Launch(6, 16, 16, &results, 8);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  for (const char* part : {"tessera-worker@", "is shutting down (SIGTERM)", "refused launch 8"}) {
    EXPECT_NE(s.error_message().find(part), std::string::npos) << part << ": " << s.error_message();
  }
  s = Apply(WriteIndexDelta(9, 1, 8, 8));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  EXPECT_NE(s.error_message().find("refused a new session"), std::string::npos);
  s = Apply(WriteIndexDelta(6, 2, 16, 16, /*ship_module=*/false));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  grpc::ClientContext context;
  v1::HealthReply reply;
  s = stub_->Health(&context, v1::HealthRequest(), &reply);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::UNAVAILABLE) << s.error_message();
  EXPECT_EQ(service_.calls_in_progress(), 0);
}

TEST_F(WorkerServiceTest, MalformedStreamsAreRejectedAndTheWorkerStaysUsable) {
  v1::ApplyChunk chunk;
  chunk.mutable_chunk()->set_buffer_id(2);
  grpc::Status s = Apply(std::vector<v1::ApplyChunk>{chunk});
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("starts with a buffer chunk"), std::string::npos)
      << s.error_message();
  s = Apply(std::vector<v1::ApplyChunk>{});
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);

  // A first delta the device rejects (a chunk outside its buffer) creates no session.
  v1::StateDelta bad = WriteIndexDelta(5, 1, 4, 4);
  v1::BufferChunk* c = bad.add_chunks();
  c->set_buffer_id(2);
  c->set_offset(4 * 4 * 16);
  c->set_data("x");
  s = Apply(bad);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::OUT_OF_RANGE) << s.error_message();
  std::vector<v1::TileResult> results;
  s = Launch(5, 4, 4, &results);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(s.error_message().find("no state for session 5"), std::string::npos);

  ASSERT_TRUE(Apply(WriteIndexDelta(5, 1, 4, 4)).ok());
  results.clear();
  ASSERT_TRUE(Launch(5, 4, 4, &results).ok());
  ExpectIndices(FinalOutput(results), 4, 4);
}

TEST_F(WorkerServiceTest, OutOfOrderDeltaKeepsTheSessionAndSequenceOneRestartsIt) {
  ASSERT_TRUE(Apply(WriteIndexDelta(9, 1, 8, 8)).ok());
  grpc::Status s = Apply(WriteIndexDelta(9, 3, 16, 16));
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(s.error_message().find("out of order"), std::string::npos) << s.error_message();
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(9, 8, 8, &results).ok());
  ExpectIndices(FinalOutput(results), 8, 8);  // still the 8×8 state

  ASSERT_TRUE(Apply(WriteIndexDelta(9, 2, 6, 6)).ok());
  // The host re-creating its devices starts over at sequence 1 with the same session id.
  ASSERT_TRUE(Apply(WriteIndexDelta(9, 1, 5, 3)).ok());
  results.clear();
  ASSERT_TRUE(Launch(9, 5, 3, &results).ok());
  ExpectIndices(FinalOutput(results), 5, 3);
}

// A failed launch's call can still wait in the worker for the device when the host ships the
// next launch's state: once a delta for launch 3 is applied, a call of launch 2 is refused (it
// would write into launch 3's buffers), and calls of launch 3 and later run.
TEST_F(WorkerServiceTest, ACallOfALaunchOlderThanTheStateIsRefused) {
  v1::StateDelta delta = WriteIndexDelta(13, 1, 8, 8);
  delta.set_launch_id(3);
  ASSERT_TRUE(Apply(delta).ok());
  std::vector<v1::TileResult> results;
  grpc::Status s = Launch(13, 8, 8, &results, /*launch_id=*/2);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(s.error_message().find("launch 2 came after the state update for launch 3"),
            std::string::npos)
      << s.error_message();
  EXPECT_TRUE(FinalOutput(results).empty());
  results.clear();
  ASSERT_TRUE(Launch(13, 8, 8, &results, /*launch_id=*/3).ok());
  ExpectIndices(FinalOutput(results), 8, 8);
  results.clear();
  ASSERT_TRUE(Launch(13, 8, 8, &results, /*launch_id=*/4).ok());  // no state change: no delta
  ExpectIndices(FinalOutput(results), 8, 8);
}

// A stream that ends before every announced message arrived (a message gRPC could not parse or
// refused as too large ends it the same way) changes nothing: the same sequence number is still
// the next one.
TEST_F(WorkerServiceTest, AnApplyStreamCutShortChangesNothing) {
  ASSERT_TRUE(Apply(WriteIndexDelta(11, 1, 4, 4)).ok());
  std::vector<v1::ApplyChunk> messages;
  transport::WriteApplyStream(WriteIndexDelta(11, 2, 6, 6), [&](const v1::ApplyChunk& m) {
    messages.push_back(m);
    return true;
  });
  ASSERT_GT(messages.size(), 1u);
  messages.pop_back();
  grpc::Status s = Apply(messages);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << s.error_message();
  ASSERT_TRUE(Apply(WriteIndexDelta(11, 2, 6, 6)).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(11, 6, 6, &results).ok());
  ExpectIndices(FinalOutput(results), 6, 6);
}

// A scene of many small objects, together more than a few MiB, travels in bounded batches and is
// applied whole (before batching, every object travelled in the stream's first message).
TEST_F(WorkerServiceTest, ManySmallObjectsTravelInBoundedMessagesAndAreApplied) {
  v1::StateDelta delta = WriteIndexDelta(14, 1, 4, 4);
  for (uint64_t id = 1000; id < 201000; ++id) {
    v1::Material* m = delta.add_objects()->mutable_material();
    m->set_id(id);
    m->set_version(1);
    v1::Variable* v = m->add_variables();
    v->set_name("transform");
    v->set_type(RT_OBJECTTYPE_MATRIX_FLOAT4x4);
    v->set_data(std::string(64, static_cast<char>(id)));
  }
  size_t object_bytes = 0;
  for (const v1::Object& o : delta.objects()) object_bytes += o.ByteSizeLong();
  ASSERT_GT(object_bytes, size_t{16} << 20);
  std::vector<v1::ApplyChunk> messages;
  transport::WriteApplyStream(delta, [&](const v1::ApplyChunk& m) {
    EXPECT_LE(m.ByteSizeLong(), transport::kMaxRegionBytes + 1024);
    messages.push_back(m);
    return true;
  });
  ASSERT_TRUE(Apply(messages).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(14, 4, 4, &results).ok());
  ExpectIndices(FinalOutput(results), 4, 4);
}

// A host done with a session ends it, and the worker lets go of its replica.
TEST_F(WorkerServiceTest, EndSessionDropsTheReplica) {
  ASSERT_TRUE(Apply(WriteIndexDelta(12, 1, 4, 4)).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(12, 4, 4, &results).ok());
  for (int i = 0; i < 2; ++i) {  // ending it again, or one never begun, is fine
    grpc::ClientContext context;
    v1::EndSessionRequest request;
    request.set_session_id(12);
    v1::EndSessionReply reply;
    ASSERT_TRUE(stub_->EndSession(&context, request, &reply).ok());
  }
  results.clear();
  grpc::Status s = Launch(12, 4, 4, &results);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(s.error_message().find("no state for session 12"), std::string::npos);
  ASSERT_TRUE(Apply(WriteIndexDelta(12, 1, 4, 4)).ok());  // sequence 1 begins it again
  results.clear();
  ASSERT_TRUE(Launch(12, 4, 4, &results).ok());
  ExpectIndices(FinalOutput(results), 4, 4);
}

TEST_F(WorkerServiceTest, LargeResultsArriveInBoundedMessages) {
  constexpr uint64_t kW = 1024, kH = 600;  // 9.4 MiB of float4
  ASSERT_TRUE(Apply(WriteIndexDelta(3, 1, kW, kH)).ok());
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(3, kW, kH, &results).ok());
  int final_messages = 0;
  for (const v1::TileResult& r : results) {
    size_t bytes = 0;
    for (const v1::BufferRegion& region : r.regions()) bytes += region.data().size();
    EXPECT_LE(bytes, transport::kMaxRegionBytes);
    final_messages += r.tile_index() == kFinalTileIndex ? 1 : 0;
  }
  EXPECT_GE(final_messages, 3);
  ExpectIndices(FinalOutput(results), kW, kH);
}

TEST_F(WorkerServiceTest, ModuleShippedByBytesLoadsWithoutTheHostsPath) {
  v1::StateDelta delta = WriteIndexDelta(21, 1, 6, 4);
  // A path that exists only on the host: the worker must never need it.
  v1::Program* program = delta.mutable_objects(0)->mutable_program();
  program->set_module_path("/nonexistent/host-only/worker_core_test_programs.so");
  const std::string module = ::tessera::testing::ReadModuleFile(kModule);
  size_t sent = 0;
  // Slices smaller than the module: reassembled in order on the worker.
  delta.clear_modules();
  ::tessera::testing::AddModuleBytes(&delta, module, module.size() / 3 + 1);
  ASSERT_EQ(delta.modules_size(), 3);
  grpc::Status s = Apply(delta, &sent);
  ASSERT_TRUE(s.ok()) << s.error_message();
  EXPECT_EQ(sent, module.size());
  std::vector<v1::TileResult> results;
  s = Launch(21, 6, 4, &results);
  ASSERT_TRUE(s.ok()) << s.error_message();
  ExpectIndices(FinalOutput(results), 6, 4);
  // Stored in the cache directory under its hash.
  EXPECT_EQ(
      ::tessera::testing::ReadModuleFile(module_cache_ + "/" + program->module_hash() + ".so"),
      module);
}

TEST_F(WorkerServiceTest, ModuleAlreadyReceivedNeedsNoBytes) {
  size_t sent = 0;
  ASSERT_TRUE(Apply(WriteIndexDelta(31, 1, 4, 4), &sent).ok());
  EXPECT_GT(sent, 0u);
  // The program travels again (say its variables changed), its module does not.
  sent = 0;
  grpc::Status s = Apply(WriteIndexDelta(31, 2, 5, 3, /*ship_module=*/false), &sent);
  ASSERT_TRUE(s.ok()) << s.error_message();
  EXPECT_EQ(sent, 0u);
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(31, 5, 3, &results).ok());
  ExpectIndices(FinalOutput(results), 5, 3);
  // Another session of the same worker process finds the module too.
  ASSERT_TRUE(Apply(WriteIndexDelta(32, 1, 3, 3, /*ship_module=*/false)).ok());
  results.clear();
  ASSERT_TRUE(Launch(32, 3, 3, &results).ok());
  ExpectIndices(FinalOutput(results), 3, 3);
}

TEST_F(WorkerServiceTest, CorruptModuleIsRejectedAndTheWorkerStillWorks) {
  ASSERT_TRUE(Apply(WriteIndexDelta(41, 1, 4, 4)).ok());
  v1::StateDelta bad = WriteIndexDelta(41, 2, 8, 8);
  ASSERT_GT(bad.modules_size(), 0);
  std::string* data = bad.mutable_modules(0)->mutable_data();
  (*data)[data->size() / 2] ^= 0x10;
  const std::string hash = bad.objects(0).program().module_hash();
  grpc::Status s = Apply(bad);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find(hash), std::string::npos) << s.error_message();
  EXPECT_NE(s.error_message().find("'write_index'"), std::string::npos) << s.error_message();
  // The session keeps its state and its sequence.
  std::vector<v1::TileResult> results;
  ASSERT_TRUE(Launch(41, 4, 4, &results).ok());
  ExpectIndices(FinalOutput(results), 4, 4);
  ASSERT_TRUE(Apply(WriteIndexDelta(41, 2, 8, 8)).ok());
  results.clear();
  ASSERT_TRUE(Launch(41, 8, 8, &results).ok());
  ExpectIndices(FinalOutput(results), 8, 8);

  // A first delta with a corrupt module creates no session.
  bad.set_session_id(42);
  bad.set_sequence(1);
  EXPECT_EQ(Apply(bad).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  results.clear();
  EXPECT_EQ(Launch(42, 4, 4, &results).error_code(), grpc::StatusCode::FAILED_PRECONDITION);
}

TEST_F(WorkerServiceTest, ProgramWhoseModuleNeverArrivedIsRefused) {
  v1::StateDelta delta = WriteIndexDelta(51, 1, 4, 4, /*ship_module=*/false);
  const std::string never_sent = ::tessera::testing::Sha256Hex("a module no host sent");
  delta.mutable_objects(0)->mutable_program()->set_module_hash(never_sent);
  grpc::Status s = Apply(delta);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(s.error_message().find("program #1 'write_index'"), std::string::npos)
      << s.error_message();
  EXPECT_NE(s.error_message().find(never_sent), std::string::npos) << s.error_message();
  EXPECT_NE(s.error_message().find("has not received"), std::string::npos) << s.error_message();
  std::vector<v1::TileResult> results;
  EXPECT_EQ(Launch(51, 4, 4, &results).error_code(), grpc::StatusCode::FAILED_PRECONDITION);

  // No hash at all is malformed.
  delta.mutable_objects(0)->mutable_program()->clear_module_hash();
  s = Apply(delta);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("names no module hash"), std::string::npos) << s.error_message();

  ASSERT_TRUE(Apply(WriteIndexDelta(51, 1, 4, 4)).ok());
  results.clear();
  ASSERT_TRUE(Launch(51, 4, 4, &results).ok());
  ExpectIndices(FinalOutput(results), 4, 4);
}

}  // namespace
}  // namespace tessera::worker
