// Round trips of the wire conventions: a delta through an Apply stream, a tile result through
// bounded messages, statuses through gRPC.
#include "transport/worker_wire.h"

#include <gtest/gtest.h>

#include <string>

#include "tessera/scheduler/device.h"

namespace tessera::transport {
namespace {

v1::StateDelta SampleDelta() {
  v1::StateDelta delta;
  delta.set_session_id(7);
  delta.set_sequence(3);
  delta.mutable_context()->set_entry_point_count(2);
  delta.mutable_context()->set_num_threads(4);
  delta.add_objects()->mutable_buffer()->set_id(11);
  delta.add_objects()->mutable_program()->set_function("f");
  delta.add_removed(5);
  for (int i = 0; i < 3; ++i) {
    v1::BufferChunk* c = delta.add_chunks();
    c->set_buffer_id(11);
    c->set_offset(static_cast<uint64_t>(i) * 8);
    c->set_data(std::string(8, static_cast<char>('a' + i)));
    c->set_hash(100 + i);
  }
  return delta;
}

TEST(WorkerWireTest, DeltaHeaderCopiesEveryFieldButChunks) {
  // DeltaHeader copies StateDelta field by field: a new field must be added there too.
  EXPECT_EQ(v1::StateDelta::descriptor()->field_count(), 6)
      << "StateDelta changed: update DeltaHeader in worker_wire.cc";
  v1::StateDelta delta = SampleDelta();
  v1::ApplyChunk header = DeltaHeader(delta);
  ASSERT_TRUE(header.has_delta());
  EXPECT_EQ(header.delta().chunks_size(), 0);
  v1::StateDelta without_chunks = delta;
  without_chunks.clear_chunks();
  EXPECT_EQ(header.delta().SerializeAsString(), without_chunks.SerializeAsString());
}

TEST(WorkerWireTest, ApplyStreamRoundTrip) {
  v1::StateDelta delta = SampleDelta();
  DeltaAssembler assembler;
  ASSERT_TRUE(assembler.Add(DeltaHeader(delta)).ok());
  for (const v1::BufferChunk& c : delta.chunks()) {
    v1::ApplyChunk m;
    *m.mutable_chunk() = c;
    ASSERT_TRUE(assembler.Add(std::move(m)).ok());
  }
  absl::StatusOr<v1::StateDelta> out = std::move(assembler).Finish();
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->SerializeAsString(), delta.SerializeAsString());
}

TEST(WorkerWireTest, MalformedApplyStreamsAreRejected) {
  v1::ApplyChunk chunk;
  chunk.mutable_chunk()->set_buffer_id(1);
  {
    DeltaAssembler a;
    absl::Status s = a.Add(v1::ApplyChunk(chunk));
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("starts with a buffer chunk"), std::string::npos) << s;
  }
  {
    DeltaAssembler a;
    ASSERT_TRUE(a.Add(DeltaHeader(SampleDelta())).ok());
    EXPECT_EQ(a.Add(DeltaHeader(SampleDelta())).code(), absl::StatusCode::kInvalidArgument);
  }
  {
    DeltaAssembler a;
    EXPECT_EQ(a.Add(v1::ApplyChunk()).code(), absl::StatusCode::kInvalidArgument);
    EXPECT_EQ(std::move(a).Finish().status().code(), absl::StatusCode::kInvalidArgument);
  }
  {
    DeltaAssembler a;
    v1::ApplyChunk inline_chunks;
    *inline_chunks.mutable_delta() = SampleDelta();
    EXPECT_EQ(a.Add(std::move(inline_chunks)).code(), absl::StatusCode::kInvalidArgument);
  }
}

// Applies regions by offset into a byte image, as the host does.
std::string Paint(const std::vector<v1::TileResult>& pieces, size_t size) {
  std::string image(size, '.');
  for (const v1::TileResult& p : pieces) {
    for (const v1::BufferRegion& r : p.regions())
      image.replace(r.offset(), r.data().size(), r.data());
  }
  return image;
}

TEST(WorkerWireTest, LargeTileResultsAreSplitIntoBoundedMessages) {
  v1::TileResult result;
  result.set_launch_id(9);
  result.set_tile_index(4);
  result.set_error("boom");
  result.set_error_code(42);
  std::string big(1000, 'x');
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>('a' + i % 26);
  v1::BufferRegion* r = result.add_regions();
  r->set_buffer_id(1);
  r->set_offset(100);
  r->set_data(big);
  v1::BufferRegion* small = result.add_regions();
  small->set_buffer_id(1);
  small->set_offset(0);
  small->set_data("0123456789");
  for (int i = 0; i < 20; ++i) result.add_prints()->set_text(std::string(30, 'p'));
  result.add_exceptions()->set_code(0x3FC);

  std::string expected = Paint({result}, 1100);
  std::vector<v1::TileResult> pieces = SplitTileResult(v1::TileResult(result), 256);
  ASSERT_GE(pieces.size(), 4u);
  int prints = 0, exceptions = 0, errors = 0;
  for (const v1::TileResult& p : pieces) {
    EXPECT_EQ(p.launch_id(), 9u);
    EXPECT_EQ(p.tile_index(), 4u);
    size_t bytes = 0;
    for (const v1::BufferRegion& reg : p.regions()) bytes += reg.data().size();
    EXPECT_LE(bytes, 256u);
    prints += p.prints_size();
    exceptions += p.exceptions_size();
    errors += p.error().empty() ? 0 : 1;
  }
  EXPECT_EQ(Paint(pieces, 1100), expected);
  EXPECT_EQ(prints, 20);
  EXPECT_EQ(exceptions, 1);
  EXPECT_EQ(errors, 1);
  EXPECT_EQ(pieces[0].error(), "boom");
  EXPECT_EQ(pieces[0].error_code(), 42u);
}

TEST(WorkerWireTest, SmallResultsTravelWhole) {
  v1::TileResult result;
  result.set_tile_index(2);
  result.add_regions()->set_data("abc");
  std::vector<v1::TileResult> pieces = SplitTileResult(v1::TileResult(result));
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].SerializeAsString(), result.SerializeAsString());
}

TEST(WorkerWireTest, FinalResultIsJoinedBackIntoWholeBuffers) {
  v1::TileResult final_result;
  final_result.set_launch_id(3);
  final_result.set_tile_index(kFinalTileIndex);
  std::string a(1000, 'a'), b(300, 'b');
  for (size_t i = 0; i < a.size(); ++i) a[i] = static_cast<char>(i * 7);
  v1::BufferRegion* ra = final_result.add_regions();
  ra->set_buffer_id(1);
  ra->set_data(a);
  v1::BufferRegion* rb = final_result.add_regions();
  rb->set_buffer_id(2);
  rb->set_data(b);

  FinalResultJoiner joiner;
  EXPECT_TRUE(joiner.empty());
  for (v1::TileResult& piece : SplitTileResult(v1::TileResult(final_result), 128)) {
    joiner.Add(std::move(piece));
  }
  ASSERT_FALSE(joiner.empty());
  v1::TileResult joined = std::move(joiner).Take();
  EXPECT_EQ(joined.SerializeAsString(), final_result.SerializeAsString());
}

TEST(WorkerWireTest, StatusesKeepTheirCodeAndNameTheWorker) {
  absl::Status device = absl::FailedPreconditionError("state delta 3 out of order (expected 2)");
  grpc::Status wire = ToGrpcStatus(device);
  EXPECT_EQ(wire.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  absl::Status back = FromGrpcStatus(wire, "unix:/tmp/w0.sock");
  EXPECT_EQ(back.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(back.message(), "worker unix:/tmp/w0.sock: state delta 3 out of order (expected 2)");
  EXPECT_TRUE(ToGrpcStatus(absl::OkStatus()).ok());
  EXPECT_TRUE(FromGrpcStatus(grpc::Status::OK, "x").ok());
  EXPECT_EQ(FromGrpcStatus(grpc::Status(grpc::StatusCode::UNAVAILABLE, "down"), "h:1").code(),
            absl::StatusCode::kUnavailable);
}

}  // namespace
}  // namespace tessera::transport
