// Round trips of the wire conventions: a delta through an Apply stream, a tile result through
// bounded messages, statuses through gRPC.
#include "transport/worker_wire.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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
  for (int i = 0; i < 2; ++i) {
    v1::ModuleChunk* m = delta.add_modules();
    m->set_module_hash(std::string(64, 'c'));
    m->set_offset(static_cast<uint64_t>(i) * 5);
    m->set_total_size(10);
    m->set_data(std::string(5, static_cast<char>('m' + i)));
  }
  delta.set_has_allocations(true);
  v1::DeviceAllocation* a = delta.add_allocations();
  a->set_address(0x200000000000);
  a->set_size(4096);
  v1::DeviceMemoryChunk* memory = delta.add_memory();
  memory->set_address(0x200000000010);
  memory->set_data("device bytes");
  memory->set_hash(7);
  delta.set_launch_id(12);
  return delta;
}

TEST(WorkerWireTest, DeltaHeaderCopiesEveryFieldButObjectsChunksAndModules) {
  // DeltaHeader copies StateDelta field by field: a new field must be added there too.
  EXPECT_EQ(v1::StateDelta::descriptor()->field_count(), 11)
      << "StateDelta changed: update DeltaHeader in worker_wire.cc";
  v1::StateDelta delta = SampleDelta();
  v1::ApplyChunk header = DeltaHeader(delta);
  ASSERT_TRUE(header.has_delta());
  EXPECT_EQ(header.delta().objects_size(), 0);
  EXPECT_EQ(header.delta().chunks_size(), 0);
  EXPECT_EQ(header.delta().modules_size(), 0);
  EXPECT_EQ(header.delta().memory_size(), 0);
  // One object batch, the slices, the chunks, the device memory.
  EXPECT_EQ(header.following(), 1u + 2u + 3u + 1u);
  v1::StateDelta without_bulk = delta;
  without_bulk.clear_objects();
  without_bulk.clear_chunks();
  without_bulk.clear_modules();
  without_bulk.clear_memory();
  EXPECT_EQ(header.delta().SerializeAsString(), without_bulk.SerializeAsString());
}

TEST(WorkerWireTest, ApplyStreamRoundTrip) {
  v1::StateDelta delta = SampleDelta();
  std::vector<v1::ApplyChunk> messages;
  ASSERT_TRUE(WriteApplyStream(delta, [&](const v1::ApplyChunk& m) {
    messages.push_back(m);
    return true;
  }));
  // The header, then the objects in one batch, then one message per module slice, then one per
  // buffer chunk, then one per piece of device memory.
  ASSERT_EQ(messages.size(), 8u);
  EXPECT_TRUE(messages[7].has_memory());
  EXPECT_TRUE(messages[0].has_delta());
  ASSERT_TRUE(messages[1].has_objects());
  EXPECT_EQ(messages[1].objects().objects_size(), 2);
  EXPECT_TRUE(messages[2].has_module());
  EXPECT_TRUE(messages[3].has_module());
  EXPECT_TRUE(messages[4].has_chunk());
  DeltaAssembler assembler;
  for (v1::ApplyChunk& m : messages) ASSERT_TRUE(assembler.Add(std::move(m)).ok());
  absl::StatusOr<v1::StateDelta> out = std::move(assembler).Finish();
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(out->SerializeAsString(), delta.SerializeAsString());
}

TEST(WorkerWireTest, ApplyStreamStopsAtTheFirstFailedWrite) {
  int writes = 0;
  EXPECT_FALSE(
      WriteApplyStream(SampleDelta(), [&](const v1::ApplyChunk&) { return ++writes < 2; }));
  EXPECT_EQ(writes, 2);
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
  {
    DeltaAssembler a;
    v1::ApplyChunk inline_modules;
    *inline_modules.mutable_delta() = SampleDelta();
    inline_modules.mutable_delta()->clear_chunks();
    EXPECT_EQ(a.Add(std::move(inline_modules)).code(), absl::StatusCode::kInvalidArgument);
  }
  {
    DeltaAssembler a;
    v1::ApplyChunk module;
    module.mutable_module()->set_module_hash(std::string(64, 'c'));
    absl::Status s = a.Add(std::move(module));
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("starts with a module slice"), std::string::npos) << s;
  }
  {
    DeltaAssembler a;
    v1::ApplyChunk objects;
    objects.mutable_objects()->add_objects()->mutable_buffer()->set_id(3);
    absl::Status s = a.Add(std::move(objects));
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("starts with an object batch"), std::string::npos) << s;
  }
}

// Hosts before ObjectBatch sent the objects inside the delta: a worker still takes them, before
// any batches.
TEST(WorkerWireTest, ObjectsInsideTheDeltaComeBeforeBatchedOnes) {
  v1::ApplyChunk header;
  header.mutable_delta()->add_objects()->mutable_buffer()->set_id(1);
  header.set_following(1);
  v1::ApplyChunk batch;
  batch.mutable_objects()->add_objects()->mutable_buffer()->set_id(2);
  DeltaAssembler a;
  ASSERT_TRUE(a.Add(std::move(header)).ok());
  ASSERT_TRUE(a.Add(std::move(batch)).ok());
  absl::StatusOr<v1::StateDelta> out = std::move(a).Finish();
  ASSERT_TRUE(out.ok()) << out.status();
  ASSERT_EQ(out->objects_size(), 2);
  EXPECT_EQ(out->objects(0).buffer().id(), 1u);
  EXPECT_EQ(out->objects(1).buffer().id(), 2u);
}

// gRPC ends a server's reads the same way at the end of a stream and at a message it could not
// parse or that was too large: the header says how many messages follow, and a stream that ends
// with fewer (or carries more) is refused instead of applied in part.
TEST(WorkerWireTest, ApplyStreamsCutShortOrPaddedAreRefused) {
  std::vector<v1::ApplyChunk> messages;
  ASSERT_TRUE(WriteApplyStream(SampleDelta(), [&](const v1::ApplyChunk& m) {
    messages.push_back(m);
    return true;
  }));
  ASSERT_EQ(messages.front().following(), messages.size() - 1);
  {
    DeltaAssembler a;
    for (size_t i = 0; i + 1 < messages.size(); ++i) {
      ASSERT_TRUE(a.Add(v1::ApplyChunk(messages[i])).ok());
    }
    absl::StatusOr<v1::StateDelta> out = std::move(a).Finish();
    EXPECT_EQ(out.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(out.status().message().find("cut short"), std::string::npos) << out.status();
  }
  {
    DeltaAssembler a;
    for (const v1::ApplyChunk& m : messages) ASSERT_TRUE(a.Add(v1::ApplyChunk(m)).ok());
    EXPECT_EQ(a.Add(v1::ApplyChunk(messages.back())).code(), absl::StatusCode::kInvalidArgument);
  }
  {
    // An object batch beyond the count is refused as well.
    ASSERT_TRUE(messages[1].has_objects());
    DeltaAssembler a;
    for (const v1::ApplyChunk& m : messages) ASSERT_TRUE(a.Add(v1::ApplyChunk(m)).ok());
    absl::Status s = a.Add(v1::ApplyChunk(messages[1]));
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
    EXPECT_NE(s.message().find("more than the 7 messages"), std::string::npos) << s;
  }
}

// A stream larger than the device could ever hold is refused as it arrives, before it is held.
TEST(WorkerWireTest, ApplyStreamsBeyondTheByteLimitAreRefusedEarly) {
  v1::StateDelta delta = SampleDelta();
  size_t data_bytes = 0;
  for (const v1::BufferChunk& c : delta.chunks()) data_bytes += c.data().size();
  for (const v1::ModuleChunk& m : delta.modules()) data_bytes += m.data().size();
  std::vector<v1::ApplyChunk> messages;
  ASSERT_TRUE(WriteApplyStream(delta, [&](const v1::ApplyChunk& m) {
    messages.push_back(m);
    return true;
  }));
  // The objects count as they travel.
  for (const v1::ApplyChunk& m : messages) {
    if (m.has_objects()) data_bytes += m.objects().ByteSizeLong();
  }
  ASSERT_GT(data_bytes, 1u);
  DeltaAssembler a(data_bytes - 1);
  absl::Status last;
  for (v1::ApplyChunk& m : messages) {
    last = a.Add(std::move(m));
    if (!last.ok()) break;
  }
  EXPECT_EQ(last.code(), absl::StatusCode::kResourceExhausted) << last;
  DeltaAssembler enough(data_bytes);
  for (const v1::ApplyChunk& m : messages) ASSERT_TRUE(enough.Add(v1::ApplyChunk(m)).ok());
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

// Writes `delta` as an Apply stream straight into an assembler, checking that no message exceeds
// `max_message_bytes`, and returns what the assembler rebuilt.
absl::StatusOr<v1::StateDelta> RoundTrip(const v1::StateDelta& delta, size_t object_batch_bytes,
                                         size_t max_message_bytes, int* messages) {
  DeltaAssembler assembler;
  absl::Status added;
  *messages = 0;
  EXPECT_TRUE(WriteApplyStream(
      delta,
      [&](const v1::ApplyChunk& m) {
        ++*messages;
        // One object larger than a batch travels alone.
        if (!m.has_objects() || m.objects().objects_size() != 1) {
          EXPECT_LE(m.ByteSizeLong(), max_message_bytes) << "message " << *messages;
        }
        added = assembler.Add(v1::ApplyChunk(m));
        return added.ok();
      },
      object_batch_bytes));
  if (!added.ok()) return added;
  return std::move(assembler).Finish();
}

v1::Object InstanceWithValue(uint64_t id, size_t value_bytes) {
  v1::Object o;
  v1::GeometryInstance* gi = o.mutable_geometry_instance();
  gi->set_id(id);
  gi->set_version(1);
  gi->set_geometry(1);
  v1::Variable* v = gi->add_variables();
  v->set_name("value");
  v->set_data(std::string(value_bytes, static_cast<char>('a' + id % 26)));
  return o;
}

// Objects travel in batches of a bounded size, in order; the header carries none of them.
TEST(WorkerWireTest, ManyObjectsTravelInBoundedBatches) {
  constexpr size_t kBatch = 1024;
  constexpr size_t kFraming = 16;  // the ApplyChunk's tag and length, and slack
  v1::StateDelta delta = SampleDelta();
  for (uint64_t id = 100; id < 400; ++id) *delta.add_objects() = InstanceWithValue(id, id % 97);
  *delta.add_objects() = InstanceWithValue(400, 3 * kBatch);  // larger than a batch
  for (uint64_t id = 401; id < 450; ++id) *delta.add_objects() = InstanceWithValue(id, 10);

  std::vector<v1::ApplyChunk> messages;
  ASSERT_TRUE(WriteApplyStream(
      delta,
      [&](const v1::ApplyChunk& m) {
        messages.push_back(m);
        return true;
      },
      kBatch));
  ASSERT_TRUE(messages[0].has_delta());
  EXPECT_EQ(messages[0].delta().objects_size(), 0);
  EXPECT_EQ(messages[0].following(), messages.size() - 1);
  int batches = 0;
  for (const v1::ApplyChunk& m : messages) {
    if (!m.has_objects()) continue;
    ++batches;
    if (m.objects().objects_size() == 1 && m.objects().objects(0).ByteSizeLong() > kBatch) {
      EXPECT_EQ(m.objects().objects(0).geometry_instance().id(), 400u);
      continue;
    }
    EXPECT_LE(m.ByteSizeLong(), kBatch + kFraming);
  }
  EXPECT_GT(batches, 10);

  int count = 0;
  absl::StatusOr<v1::StateDelta> out = RoundTrip(delta, kBatch, kBatch + kFraming, &count);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_EQ(count, static_cast<int>(messages.size()));
  EXPECT_EQ(out->SerializeAsString(), delta.SerializeAsString());
}

// A scene whose objects together exceed what one message may carry streams in batches of about
// kMaxRegionBytes (before batching, the objects all travelled in the first message).
TEST(WorkerWireTest, ObjectsTogetherLargerThanOneMessageStillTravel) {
  v1::StateDelta delta = SampleDelta();
  size_t total = 0;
  for (uint64_t id = 100; total <= static_cast<size_t>(kMaxMessageBytes); ++id) {
    *delta.add_objects() = InstanceWithValue(id, 64 << 10);
    total += delta.objects(delta.objects_size() - 1).ByteSizeLong();
  }
  EXPECT_TRUE(CheckDeltaMessageSizes(delta).ok());
  int messages = 0;
  absl::StatusOr<v1::StateDelta> out =
      RoundTrip(delta, kMaxRegionBytes, kMaxRegionBytes + 16, &messages);
  ASSERT_TRUE(out.ok()) << out.status();
  EXPECT_GT(messages, 16);
  EXPECT_EQ(out->SerializeAsString(), delta.SerializeAsString());
}

// Removing a million objects at once: the ids beyond what the first message holds follow in
// bounded batches, in their order.
TEST(WorkerWireTest, ManyRemovedIdsTravelInBoundedMessages) {
  v1::StateDelta delta = SampleDelta();
  for (uint64_t id = 1000; id < 1001000; ++id) delta.add_removed(id * 7919);
  EXPECT_TRUE(CheckDeltaMessageSizes(delta).ok());
  int messages = 0;
  absl::StatusOr<v1::StateDelta> out =
      RoundTrip(delta, kMaxRegionBytes, kMaxRegionBytes + (64 << 10), &messages);
  ASSERT_TRUE(out.ok()) << out.status();
  // Header, objects, removed ids, modules, chunks, device memory.
  EXPECT_EQ(messages, 1 + 1 + 2 + 2 + 3 + 1);
  EXPECT_EQ(out->SerializeAsString(), delta.SerializeAsString());
}

// The context state travels in one message and each object in one: one too large for it is
// refused before sending, naming the largest value (gRPC said only "Sent message larger than
// max").
TEST(WorkerWireTest, ASceneDescriptionTooLargeForOneMessageNamesItsLargestValue) {
  v1::StateDelta delta;
  v1::Variable* small = delta.mutable_context()->add_variables();
  small->set_name("small");
  small->set_data(std::string(16, 'a'));
  EXPECT_TRUE(CheckDeltaMessageSizes(delta).ok());
  v1::Variable* big = delta.mutable_context()->add_variables();
  big->set_name("big");
  big->set_data(std::string(static_cast<size_t>(kMaxMessageBytes), 'b'));
  absl::Status s = CheckDeltaMessageSizes(delta);
  EXPECT_EQ(s.code(), absl::StatusCode::kResourceExhausted) << s;
  EXPECT_NE(s.message().find("variable 'big' of the context"), std::string::npos) << s;
  EXPECT_NE(s.message().find("put large data in a buffer"), std::string::npos) << s;

  // The same value on one object.
  delta.mutable_context()->mutable_variables()->RemoveLast();
  *delta.add_objects() = InstanceWithValue(9, kMaxMessageBytes);
  s = CheckDeltaMessageSizes(delta);
  EXPECT_EQ(s.code(), absl::StatusCode::kResourceExhausted) << s;
  EXPECT_NE(s.message().find("variable 'value' of geometry instance #9"), std::string::npos) << s;
  EXPECT_NE(s.message().find("put large data in a buffer"), std::string::npos) << s;
}

TEST(WorkerWireTest, LargeTileResultsAreSplitIntoBoundedMessages) {
  v1::TileResult result;
  result.set_launch_id(9);
  result.set_tile_index(4);
  result.set_error("boom");
  result.set_error_code(42);
  result.set_traces(1234);  // a call's counts (auto_batching.h): once, in the first piece
  result.set_packet_answers(567);
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
  uint64_t traces = 0, packet_answers = 0;
  for (const v1::TileResult& p : pieces) {
    traces += p.traces();
    packet_answers += p.packet_answers();
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
  EXPECT_EQ(traces, 1234u);
  EXPECT_EQ(packet_answers, 567u);
}

TEST(WorkerWireTest, PackedRunsAreSplitByRunAndKeepTheirOffsets) {
  v1::TileResult result;
  result.set_tile_index(kFinalTileIndex);
  result.set_call_sequence(3);
  v1::BufferRegion* region = result.add_regions();
  region->set_buffer_id(7);
  // Runs of 4, 9 and 2 bytes at scattered offsets, packed.
  const std::vector<std::pair<uint64_t, std::string>> runs = {
      {100, "abcd"}, {300, "efghijklm"}, {40, "no"}};
  for (const auto& [offset, bytes] : runs) {
    region->add_run_offsets(offset);
    region->add_run_sizes(bytes.size());
    region->mutable_data()->append(bytes);
  }
  std::vector<v1::TileResult> pieces = SplitTileResult(std::move(result), /*max_bytes=*/5);
  std::string rebuilt(400, '.'), expected(400, '.');
  for (const auto& [offset, bytes] : runs) expected.replace(offset, bytes.size(), bytes);
  for (const v1::TileResult& piece : pieces) {
    EXPECT_EQ(piece.tile_index(), kFinalTileIndex);
    EXPECT_EQ(piece.call_sequence(), 3u);  // every piece: the host orders calls by it
    size_t bytes_in_piece = 0;
    for (const v1::BufferRegion& r : piece.regions()) {
      EXPECT_EQ(r.buffer_id(), 7u);
      bytes_in_piece += r.data().size();
      size_t at = 0;
      ASSERT_EQ(r.run_offsets_size(), r.run_sizes_size());
      for (int i = 0; i < r.run_offsets_size(); ++i) {
        rebuilt.replace(r.run_offsets(i), r.run_sizes(i), r.data().substr(at, r.run_sizes(i)));
        at += r.run_sizes(i);
      }
      EXPECT_EQ(at, r.data().size());
    }
    EXPECT_LE(bytes_in_piece, 5u);
  }
  EXPECT_GE(pieces.size(), 3u);
  EXPECT_EQ(rebuilt, expected);
}

TEST(WorkerWireTest, SmallResultsTravelWhole) {
  v1::TileResult result;
  result.set_tile_index(2);
  result.add_regions()->set_data("abc");
  std::vector<v1::TileResult> pieces = SplitTileResult(v1::TileResult(result));
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].SerializeAsString(), result.SerializeAsString());
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
