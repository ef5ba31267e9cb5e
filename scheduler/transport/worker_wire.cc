#include "transport/worker_wire.h"

#include <google/protobuf/io/coded_stream.h>

#include <algorithm>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "tessera/v1/object_fields.h"

namespace tessera::transport {

namespace {

// Bytes `object` adds to an ObjectBatch: its tag, its length and itself.
size_t BatchedSize(const v1::Object& object) {
  const size_t bytes = object.ByteSizeLong();
  return 1 + google::protobuf::io::CodedOutputStream::VarintSize64(bytes) + bytes;
}

// Where the objects of `delta` are cut into batches of at most `max_bytes`: batch i ends before
// object ends[i]. An object larger than `max_bytes` is a batch of its own.
std::vector<int> ObjectBatchEnds(const v1::StateDelta& delta, size_t max_bytes) {
  std::vector<int> ends;
  size_t used = 0;  // bytes in the batch being filled
  for (int i = 0; i < delta.objects_size(); ++i) {
    const size_t bytes = BatchedSize(delta.objects(i));
    if (used > 0 && used + bytes > max_bytes) {
      ends.push_back(i);
      used = 0;
    }
    used += bytes;
  }
  if (used > 0) ends.push_back(delta.objects_size());
  return ends;
}

// Removed ids per message: at most 10 bytes each as varints, so a message of them stays within
// kMaxRegionBytes. The header carries the first this many, ObjectBatches the rest.
constexpr int kRemovedPerMessage = static_cast<int>(kMaxRegionBytes / 10);

// The messages after the header that carry removed ids.
size_t RemovedBatches(const v1::StateDelta& delta) {
  const int rest = std::max(0, delta.removed_size() - kRemovedPerMessage);
  return static_cast<size_t>((rest + kRemovedPerMessage - 1) / kRemovedPerMessage);
}

v1::ApplyChunk Header(const v1::StateDelta& delta, size_t object_batches) {
  // Field by field, so the objects and chunks (the bulk of a delta) are not copied only to be
  // cleared. worker_wire_test fails when StateDelta gains a field, as a reminder to copy it here.
  v1::ApplyChunk header;
  v1::StateDelta* out = header.mutable_delta();
  out->set_session_id(delta.session_id());
  out->set_sequence(delta.sequence());
  *out->mutable_context() = delta.context();
  const int removed = std::min(delta.removed_size(), kRemovedPerMessage);
  out->mutable_removed()->Add(delta.removed().begin(), delta.removed().begin() + removed);
  out->set_has_allocations(delta.has_allocations());
  *out->mutable_allocations() = delta.allocations();
  out->set_launch_id(delta.launch_id());
  header.set_following(object_batches + RemovedBatches(delta) + delta.modules_size() +
                       delta.chunks_size() + delta.memory_size());
  return header;
}

// The largest variable value `scope` (a ContextState, or the message inside an Object) carries;
// null when it carries none. Only on the way to an error, so reflection will do.
const v1::Variable* LargestVariable(const google::protobuf::Message& scope) {
  const auto* field = scope.GetDescriptor()->FindFieldByName("variables");
  if (field == nullptr || field->message_type() != v1::Variable::descriptor()) return nullptr;
  const google::protobuf::Reflection* reflection = scope.GetReflection();
  const v1::Variable* largest = nullptr;
  for (int i = 0; i < reflection->FieldSize(scope, field); ++i) {
    const auto& v =
        static_cast<const v1::Variable&>(reflection->GetRepeatedMessage(scope, field, i));
    if (largest == nullptr || v.data().size() > largest->data().size()) largest = &v;
  }
  return largest;
}

// RESOURCE_EXHAUSTED: `owner`'s description (`scope`) takes `bytes`, more than `limit`.
absl::Status TooLargeForOneMessage(const std::string& owner, const google::protobuf::Message& scope,
                                   size_t bytes, size_t limit) {
  const v1::Variable* largest = LargestVariable(scope);
  return absl::ResourceExhaustedError(absl::StrCat(
      "the description of ", owner, " (variable values included, buffer contents aside) takes ",
      bytes, " bytes, more than the ", limit, " a worker accepts in one message",
      largest == nullptr || largest->data().empty()
          ? std::string()
          : absl::StrCat("; the largest value is variable '", largest->name(), "' of ", owner, " (",
                         largest->data().size(), " bytes): put large data in a buffer")));
}

}  // namespace

v1::ApplyChunk DeltaHeader(const v1::StateDelta& delta) {
  return Header(delta, ObjectBatchEnds(delta, kMaxRegionBytes).size());
}

absl::Status CheckDeltaMessageSizes(const v1::StateDelta& delta) {
  // Framing of a message (tags, lengths, `following`) stays far below this.
  constexpr size_t kSlack = 64 << 10;
  constexpr size_t kLimit = kMaxMessageBytes - kSlack;
  // The header: removed ids (as many as it carries) take at most 10 bytes each.
  const size_t header = delta.context().ByteSizeLong() +
                        std::min(delta.removed_size(), kRemovedPerMessage) * size_t{10};
  if (header > kLimit) {
    return TooLargeForOneMessage("the context", delta.context(), header, kLimit);
  }
  // Objects are batched, but one object is never split.
  for (const v1::Object& o : delta.objects()) {
    const size_t bytes = o.ByteSizeLong();
    if (bytes <= kLimit) continue;
    // The message inside the object's kind (a GeometryInstance, say) holds its variables.
    const auto* kind = v1::Object::descriptor()->FindFieldByNumber(o.kind_case());
    const std::string owner =
        absl::StrCat(absl::StrReplaceAll(v1::ObjectKindName(o.kind_case()), {{"_", " "}}), " #",
                     v1::ObjectId(o));
    return TooLargeForOneMessage(owner, kind ? o.GetReflection()->GetMessage(o, kind) : o, bytes,
                                 kLimit);
  }
  return absl::OkStatus();
}

bool WriteApplyStream(const v1::StateDelta& delta,
                      absl::FunctionRef<bool(const v1::ApplyChunk&)> write,
                      size_t object_batch_bytes) {
  const std::vector<int> ends = ObjectBatchEnds(delta, object_batch_bytes);
  if (!write(Header(delta, ends.size()))) return false;
  v1::ApplyChunk message;
  int begin = 0;
  for (int end : ends) {
    v1::ObjectBatch* batch = message.mutable_objects();
    batch->clear_objects();
    for (; begin < end; ++begin) *batch->add_objects() = delta.objects(begin);
    if (!write(message)) return false;
  }
  for (int at = kRemovedPerMessage; at < delta.removed_size(); at += kRemovedPerMessage) {
    v1::ObjectBatch* batch = message.mutable_objects();
    batch->clear_objects();
    batch->clear_removed();
    const int end = std::min(delta.removed_size(), at + kRemovedPerMessage);
    batch->mutable_removed()->Add(delta.removed().begin() + at, delta.removed().begin() + end);
    if (!write(message)) return false;
  }
  for (const v1::ModuleChunk& module : delta.modules()) {
    *message.mutable_module() = module;
    if (!write(message)) return false;
  }
  for (const v1::BufferChunk& chunk : delta.chunks()) {
    *message.mutable_chunk() = chunk;
    if (!write(message)) return false;
  }
  for (const v1::DeviceMemoryChunk& memory : delta.memory()) {
    *message.mutable_memory() = memory;
    if (!write(message)) return false;
  }
  return true;
}

absl::Status DeltaAssembler::Add(v1::ApplyChunk&& part) {
  bytes_ += part.has_chunk()     ? part.chunk().data().size()
            : part.has_memory()  ? part.memory().data().size()
            : part.has_module()  ? part.module().data().size()
            : part.has_objects() ? part.objects().ByteSizeLong()
                                 : 0;
  if (bytes_ > max_bytes_) {
    return absl::ResourceExhaustedError(absl::StrCat("Apply stream carries more than ", max_bytes_,
                                                     " bytes, more than this device can hold"));
  }
  switch (part.part_case()) {
    case v1::ApplyChunk::kDelta:
      if (has_delta_) return absl::InvalidArgumentError("Apply stream carries two state deltas");
      if (part.delta().chunks_size() != 0 || part.delta().modules_size() != 0 ||
          part.delta().memory_size() != 0) {
        return absl::InvalidArgumentError(
            "Apply stream's delta carries buffer chunks or module slices inline; they travel as "
            "separate messages");
      }
      // Objects inline (as hosts before ObjectBatch sent them) come first; batches append.
      delta_ = std::move(*part.mutable_delta());
      following_ = part.following();
      has_delta_ = true;
      return absl::OkStatus();
    case v1::ApplyChunk::kObjects:
      if (absl::Status s = Follow("an object batch"); !s.ok()) return s;
      delta_.mutable_objects()->Reserve(delta_.objects_size() + part.objects().objects_size());
      for (v1::Object& o : *part.mutable_objects()->mutable_objects()) {
        *delta_.add_objects() = std::move(o);
      }
      delta_.mutable_removed()->Add(part.objects().removed().begin(),
                                    part.objects().removed().end());
      return absl::OkStatus();
    case v1::ApplyChunk::kChunk:
      if (absl::Status s = Follow("a buffer chunk"); !s.ok()) return s;
      *delta_.add_chunks() = std::move(*part.mutable_chunk());
      return absl::OkStatus();
    case v1::ApplyChunk::kModule:
      if (absl::Status s = Follow("a module slice"); !s.ok()) return s;
      *delta_.add_modules() = std::move(*part.mutable_module());
      return absl::OkStatus();
    case v1::ApplyChunk::kMemory:
      if (absl::Status s = Follow("a device memory chunk"); !s.ok()) return s;
      *delta_.add_memory() = std::move(*part.mutable_memory());
      return absl::OkStatus();
    case v1::ApplyChunk::PART_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError(
      "Apply stream message carries no delta, object batch, buffer chunk or module slice");
}

absl::Status DeltaAssembler::Follow(absl::string_view what) {
  if (!has_delta_) {
    return absl::InvalidArgumentError(
        absl::StrCat("Apply stream starts with ", what, ", not a delta"));
  }
  if (++received_ > following_) {
    return absl::InvalidArgumentError(absl::StrCat("Apply stream carries more than the ",
                                                   following_, " messages its delta announced"));
  }
  return absl::OkStatus();
}

absl::StatusOr<v1::StateDelta> DeltaAssembler::Finish() && {
  if (!has_delta_) return absl::InvalidArgumentError("Apply stream ended without a state delta");
  if (received_ != following_) {
    return absl::InvalidArgumentError(
        absl::StrCat("Apply stream ended after ", received_, " of the ", following_,
                     " messages its delta announced (cut short, or a message was malformed or too "
                     "large); nothing was applied"));
  }
  return std::move(delta_);
}

std::vector<v1::TileResult> SplitTileResult(v1::TileResult&& result, size_t max_bytes) {
  max_bytes = std::max<size_t>(max_bytes, 1);
  std::vector<v1::TileResult> pieces;
  size_t used = 0;  // bytes in pieces.back()
  // A new piece when the next item would not fit; an empty piece takes anything.
  auto piece_for = [&](size_t bytes) -> v1::TileResult& {
    if (pieces.empty() || (used > 0 && used + bytes > max_bytes)) {
      pieces.emplace_back();
      pieces.back().set_launch_id(result.launch_id());
      pieces.back().set_tile_index(result.tile_index());
      pieces.back().set_call_sequence(result.call_sequence());
      used = 0;
    }
    used += bytes;
    return pieces.back();
  };

  v1::TileResult& first = piece_for(0);
  first.set_error(std::move(*result.mutable_error()));
  first.set_error_code(result.error_code());
  first.set_tiles_done(result.tiles_done());
  first.set_traces(result.traces());
  first.set_packet_answers(result.packet_answers());
  for (v1::BufferRegion& region : *result.mutable_regions()) {
    const std::string& data = region.data();
    if (data.size() <= max_bytes) {
      *piece_for(data.size()).add_regions() = std::move(region);
      continue;
    }
    if (region.run_offsets_size() > 0) {
      // Packed runs: each piece takes whole runs, or slices of one larger than a piece.
      v1::BufferRegion* slice = nullptr;
      size_t slice_piece = 0;  // index: `pieces` may reallocate
      size_t at = 0;
      for (int r = 0; r < region.run_offsets_size() && r < region.run_sizes_size(); ++r) {
        for (uint64_t done = 0; done < region.run_sizes(r);) {
          const size_t n = std::min<uint64_t>(max_bytes, region.run_sizes(r) - done);
          v1::TileResult& piece = piece_for(n);
          if (slice == nullptr || slice_piece != pieces.size() - 1) {
            slice = piece.add_regions();
            slice->set_buffer_id(region.buffer_id());
            slice_piece = pieces.size() - 1;
          }
          slice->add_run_offsets(region.run_offsets(r) + done);
          slice->add_run_sizes(n);
          slice->mutable_data()->append(data, at, n);
          at += n;
          done += n;
        }
      }
      continue;
    }
    for (size_t begin = 0; begin < data.size(); begin += max_bytes) {
      size_t n = std::min(max_bytes, data.size() - begin);
      v1::BufferRegion* slice = piece_for(n).add_regions();
      slice->set_buffer_id(region.buffer_id());
      slice->set_offset(region.offset() + begin);
      slice->set_data(data.data() + begin, n);
    }
  }
  for (v1::PrintRecord& print : *result.mutable_prints()) {
    *piece_for(print.ByteSizeLong()).add_prints() = std::move(print);
  }
  for (v1::ExceptionReport& report : *result.mutable_exceptions()) {
    *piece_for(report.ByteSizeLong()).add_exceptions() = std::move(report);
  }
  return pieces;
}

grpc::Status ToGrpcStatus(const absl::Status& status) {
  if (status.ok()) return grpc::Status::OK;
  return grpc::Status(static_cast<grpc::StatusCode>(status.code()), std::string(status.message()));
}

absl::Status FromGrpcStatus(const grpc::Status& status, absl::string_view address) {
  if (status.ok()) return absl::OkStatus();
  return absl::Status(static_cast<absl::StatusCode>(status.error_code()),
                      absl::StrCat("worker ", address, ": ", status.error_message()));
}

}  // namespace tessera::transport
