// ApplyCall against an in-process server: calls given up on by a device that is then destroyed,
// as a launch does when its workers die.
#include "transport/apply_call.h"

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

namespace tessera::transport {
namespace {

// Reads a stream to its end (or its cancel), slowly, so that the client's side ends after the
// client gave up on it.
class SlowApply final : public v1::Worker::Service {
 public:
  grpc::Status Apply(grpc::ServerContext* context, grpc::ServerReader<v1::ApplyChunk>* reader,
                     v1::ApplyReply*) override {
    v1::ApplyChunk chunk;
    while (reader->Read(&chunk)) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return context->IsCancelled() ? grpc::Status::CANCELLED : grpc::Status::OK;
  }
};

class ApplyCallTest : public testing::Test {
 protected:
  void SetUp() override {
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    address_ = "127.0.0.1:" + std::to_string(port);
  }
  void TearDown() override { server_->Shutdown(); }

  std::unique_ptr<v1::Worker::Stub> NewStub() {
    return v1::Worker::NewStub(grpc::CreateChannel(address_, grpc::InsecureChannelCredentials()));
  }

  static v1::ApplyChunk Chunk() {
    v1::ApplyChunk chunk;
    chunk.mutable_chunk()->set_data(std::string(1024, 'x'));
    return chunk;
  }

  SlowApply service_;
  std::unique_ptr<grpc::Server> server_;
  std::string address_;
};

TEST_F(ApplyCallTest, AFinishedCallReportsTheServersStatus) {
  auto stub = NewStub();
  ApplyCall call(stub.get());
  ASSERT_TRUE(call.Write(Chunk(), absl::Seconds(10)));
  EXPECT_TRUE(call.Finish(absl::Seconds(10)).ok());
  EXPECT_FALSE(call.silent());
}

// The call's context holds the channel; once the device dropped its own reference, the call's
// end drops the last one. Ended on gRPC's callback thread, that shut down gRPC's callback queue
// from its own thread and aborted the process now and then (FaultTest's lost-device launches).
TEST_F(ApplyCallTest, CallsOutlivingTheirChannelsEndWithoutHarm) {
  for (int i = 0; i < 40; ++i) {
    auto stub = NewStub();
    {
      ApplyCall call(stub.get());
      call.Write(Chunk(), absl::Seconds(10));
    }  // given up: cancelled, not waited for
    stub.reset();
    std::this_thread::sleep_for(std::chrono::milliseconds(i % 4 == 0 ? 20 : 1));
  }
  // Calls still work afterwards.
  auto stub = NewStub();
  ApplyCall call(stub.get());
  ASSERT_TRUE(call.Write(Chunk(), absl::Seconds(10)));
  EXPECT_TRUE(call.Finish(absl::Seconds(10)).ok());
}

}  // namespace
}  // namespace tessera::transport
