#include "transport/worker_wire.h"

#include <algorithm>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"

namespace tessera::transport {

v1::ApplyChunk DeltaHeader(const v1::StateDelta& delta) {
  // Field by field, so the chunks (the bulk of a delta) are not copied only to be cleared.
  // worker_wire_test fails when StateDelta gains a field, as a reminder to copy it here.
  v1::ApplyChunk header;
  v1::StateDelta* out = header.mutable_delta();
  out->set_session_id(delta.session_id());
  out->set_sequence(delta.sequence());
  *out->mutable_context() = delta.context();
  *out->mutable_objects() = delta.objects();
  *out->mutable_removed() = delta.removed();
  header.set_following(static_cast<uint64_t>(delta.modules_size()) + delta.chunks_size());
  return header;
}

absl::Status CheckDeltaHeaderSize(const v1::StateDelta& delta) {
  // Framing of the header message itself (tags, lengths, `following`) stays far below this.
  constexpr size_t kSlack = 64 << 10;
  size_t bytes = delta.context().ByteSizeLong();
  for (const v1::Object& o : delta.objects()) bytes += o.ByteSizeLong();
  bytes += delta.removed_size() * sizeof(uint64_t);
  if (bytes + kSlack <= static_cast<size_t>(kMaxMessageBytes)) return absl::OkStatus();
  std::string largest;
  size_t largest_bytes = 0;
  auto scan = [&](const auto& variables, const std::string& owner) {
    for (const v1::Variable& v : variables) {
      if (v.data().size() > largest_bytes) {
        largest_bytes = v.data().size();
        largest = absl::StrCat("variable '", v.name(), "' of ", owner);
      }
    }
  };
  scan(delta.context().variables(), "the context");
  for (const v1::Object& o : delta.objects()) {
    if (o.has_program()) scan(o.program().variables(), absl::StrCat("program #", o.program().id()));
    if (o.has_geometry()) {
      scan(o.geometry().variables(), absl::StrCat("geometry #", o.geometry().id()));
    }
    if (o.has_material())
      scan(o.material().variables(), absl::StrCat("material #", o.material().id()));
    if (o.has_geometry_instance()) {
      scan(o.geometry_instance().variables(),
           absl::StrCat("geometry instance #", o.geometry_instance().id()));
    }
    if (o.has_selector())
      scan(o.selector().variables(), absl::StrCat("selector #", o.selector().id()));
  }
  return absl::ResourceExhaustedError(absl::StrCat(
      "the scene description (objects and variable values, buffer contents aside) takes ", bytes,
      " bytes, more than the ", kMaxMessageBytes - kSlack, " a worker accepts in one update",
      largest.empty() ? std::string()
                      : absl::StrCat("; the largest value is ", largest, " (", largest_bytes,
                                     " bytes): put large data in a buffer")));
}

bool WriteApplyStream(const v1::StateDelta& delta,
                      absl::FunctionRef<bool(const v1::ApplyChunk&)> write) {
  if (!write(DeltaHeader(delta))) return false;
  v1::ApplyChunk message;
  for (const v1::ModuleChunk& module : delta.modules()) {
    *message.mutable_module() = module;
    if (!write(message)) return false;
  }
  for (const v1::BufferChunk& chunk : delta.chunks()) {
    *message.mutable_chunk() = chunk;
    if (!write(message)) return false;
  }
  return true;
}

absl::Status DeltaAssembler::Add(v1::ApplyChunk&& part) {
  bytes_ += part.has_chunk()    ? part.chunk().data().size()
            : part.has_module() ? part.module().data().size()
                                : 0;
  if (bytes_ > max_bytes_) {
    return absl::ResourceExhaustedError(absl::StrCat("Apply stream carries more than ", max_bytes_,
                                                     " bytes, more than this device can hold"));
  }
  switch (part.part_case()) {
    case v1::ApplyChunk::kDelta:
      if (has_delta_) return absl::InvalidArgumentError("Apply stream carries two state deltas");
      if (part.delta().chunks_size() != 0 || part.delta().modules_size() != 0) {
        return absl::InvalidArgumentError(
            "Apply stream's delta carries buffer chunks or module slices inline; they travel as "
            "separate messages");
      }
      delta_ = std::move(*part.mutable_delta());
      following_ = part.following();
      has_delta_ = true;
      return absl::OkStatus();
    case v1::ApplyChunk::kChunk:
      if (!has_delta_) {
        return absl::InvalidArgumentError("Apply stream starts with a buffer chunk, not a delta");
      }
      if (++received_ > following_) {
        return absl::InvalidArgumentError(absl::StrCat(
            "Apply stream carries more than the ", following_, " messages its delta announced"));
      }
      *delta_.add_chunks() = std::move(*part.mutable_chunk());
      return absl::OkStatus();
    case v1::ApplyChunk::kModule:
      if (!has_delta_) {
        return absl::InvalidArgumentError("Apply stream starts with a module slice, not a delta");
      }
      if (++received_ > following_) {
        return absl::InvalidArgumentError(absl::StrCat(
            "Apply stream carries more than the ", following_, " messages its delta announced"));
      }
      *delta_.add_modules() = std::move(*part.mutable_module());
      return absl::OkStatus();
    case v1::ApplyChunk::PART_NOT_SET:
      break;
  }
  return absl::InvalidArgumentError(
      "Apply stream message carries no delta, buffer chunk or module slice");
}

absl::StatusOr<v1::StateDelta> DeltaAssembler::Finish() && {
  if (!has_delta_) return absl::InvalidArgumentError("Apply stream ended without a state delta");
  if (received_ != following_) {
    return absl::InvalidArgumentError(absl::StrCat(
        "Apply stream ended after ", received_, " of the ", following_,
        " chunk messages its delta announced (cut short, or a message was malformed or too "
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
