#include "transport/result_arena.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "absl/strings/str_cat.h"

namespace tessera::transport {
namespace {

// The state words, one per cache line, then the slots.
constexpr uint64_t kHeaderBytes = 4096;
constexpr uint64_t kStateStride = 64;
constexpr uint64_t kWriting = 1;  // the state's low bit; the token is the rest

static_assert(ResultArena::kSlots * kStateStride <= kHeaderBytes, "state words fit the header");
static_assert(std::atomic<uint64_t>::is_always_lock_free, "shared between processes");

std::string Errno(const char* what) { return absl::StrCat(what, ": ", std::strerror(errno)); }

}  // namespace

ResultArena::ResultArena(int fd, unsigned char* base, uint64_t bytes)
    : fd_(fd), base_(base), bytes_(bytes), slot_bytes_((bytes - kHeaderBytes) / kSlots) {}

ResultArena::~ResultArena() {
  munmap(base_, bytes_);
  CloseFd();
}

void ResultArena::CloseFd() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

absl::StatusOr<std::unique_ptr<ResultArena>> ResultArena::Create(uint64_t slot_bytes) {
  slot_bytes = (slot_bytes + 4095) / 4096 * 4096;
  const uint64_t bytes = kHeaderBytes + kSlots * slot_bytes;
  int fd = memfd_create("tessera-results", MFD_CLOEXEC);
  if (fd < 0) return absl::UnavailableError(Errno("memfd_create"));
  if (fd <= STDERR_FILENO) {
    // An application that closed stdio: a child's stdio set-up would clobber the arena.
    const int moved = fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    close(fd);
    if (moved < 0) return absl::UnavailableError(Errno("moving the result arena's descriptor"));
    fd = moved;
  }
  if (ftruncate(fd, static_cast<off_t>(bytes)) != 0) {
    std::string message = Errno("ftruncate of the result arena");
    close(fd);
    return absl::UnavailableError(message);
  }
  void* base = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (base == MAP_FAILED) {
    std::string message = Errno("mmap of the result arena");
    close(fd);
    return absl::UnavailableError(message);
  }
  // ftruncate zeroed the file: every state word starts as token 0, not writing.
  return std::unique_ptr<ResultArena>(
      new ResultArena(fd, static_cast<unsigned char*>(base), bytes));
}

absl::StatusOr<std::unique_ptr<ResultArena>> ResultArena::Map(int fd) {
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    return absl::InvalidArgumentError(Errno(absl::StrCat("result arena descriptor ", fd).c_str()));
  }
  const uint64_t bytes = static_cast<uint64_t>(st.st_size);
  if (bytes <= kHeaderBytes || (bytes - kHeaderBytes) % (kSlots * uint64_t{4096}) != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("result arena descriptor ", fd, " has ", bytes, " bytes, not an arena"));
  }
  void* base = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (base == MAP_FAILED) return absl::UnavailableError(Errno("mmap of the result arena"));
  return std::unique_ptr<ResultArena>(
      new ResultArena(fd, static_cast<unsigned char*>(base), bytes));
}

std::atomic<uint64_t>& ResultArena::State(int slot) const {
  return *reinterpret_cast<std::atomic<uint64_t>*>(base_ + slot * kStateStride);
}

unsigned char* ResultArena::SlotData(int slot) const {
  return base_ + kHeaderBytes + slot * slot_bytes_;
}

ResultArena::Lease ResultArena::Acquire() {
  std::lock_guard<std::mutex> lock(mu_);
  // The lowest free slot: a device with two calls in flight keeps touching the same two.
  for (int s = 0; s < kSlots; ++s) {
    if (leased_[s]) continue;
    uint64_t state = State(s).load(std::memory_order_acquire);
    if (state & kWriting) continue;  // a late writer of an earlier call is still in it
    const uint64_t token = ++next_token_;
    if (!State(s).compare_exchange_strong(state, token << 1, std::memory_order_acq_rel)) {
      continue;  // that writer got in first
    }
    leased_[s] = true;
    return Lease{s, token};
  }
  return Lease{};
}

void ResultArena::Release(const Lease& lease) {
  if (lease.slot < 0) return;
  std::lock_guard<std::mutex> lock(mu_);
  leased_[lease.slot] = false;
}

absl::Status ResultArena::Restore(ResultArena* arena, const Lease& lease, v1::TileResult* result) {
  for (v1::BufferRegion& r : *result->mutable_regions()) {
    if (r.arena_size() == 0) continue;
    if (arena == nullptr) {
      return absl::DataLossError(absl::StrCat("a result names ", r.arena_size(),
                                              " bytes in shared memory this host never gave it"));
    }
    if (absl::Status s = arena->RestoreRegion(lease, r); !s.ok()) return s;
  }
  return absl::OkStatus();
}

absl::Status ResultArena::RestoreRegion(const Lease& lease, v1::BufferRegion& r) {
  if (lease.slot < 0 || r.arena_offset() > slot_bytes_ ||
      r.arena_size() > slot_bytes_ - r.arena_offset()) {
    return absl::DataLossError(absl::StrCat("a result names arena bytes [", r.arena_offset(), ", +",
                                            r.arena_size(), ") outside its slot of ", slot_bytes_,
                                            " bytes"));
  }
  r.mutable_data()->assign(reinterpret_cast<const char*>(SlotData(lease.slot)) + r.arena_offset(),
                           r.arena_size());
  restored_bytes_.fetch_add(r.arena_size(), std::memory_order_relaxed);
  r.clear_arena_offset();
  r.clear_arena_size();
  return absl::OkStatus();
}

ResultArena::Writer::Writer(ResultArena* arena, const v1::LaunchRequest& request) {
  if (arena == nullptr || request.arena_token() == 0 || request.arena_slot() >= kSlots) return;
  arena_ = arena;
  slot_ = static_cast<int>(request.arena_slot());
  token_ = request.arena_token();
}

void ResultArena::Writer::Move(v1::TileResult* result) {
  if (arena_ == nullptr) return;
  bool any = false;
  for (const v1::BufferRegion& r : result->regions()) {
    any = any || r.data().size() >= kMinRegionBytes;
  }
  if (!any) return;
  std::atomic<uint64_t>& state = arena_->State(slot_);
  uint64_t expected = token_ << 1;
  if (!state.compare_exchange_strong(expected, expected | kWriting, std::memory_order_acquire)) {
    arena_ = nullptr;  // the host leased the slot to another call: this one was given up
    return;
  }
  unsigned char* slot = arena_->SlotData(slot_);
  for (v1::BufferRegion& r : *result->mutable_regions()) {
    const uint64_t size = r.data().size();
    if (size < kMinRegionBytes || size > arena_->slot_bytes_ - used_) continue;
    std::memcpy(slot + used_, r.data().data(), size);
    r.set_arena_offset(used_);
    r.set_arena_size(size);
    r.mutable_data()->clear();  // keeps its capacity for the message's next use
    used_ += (size + 63) / 64 * 64;
    if (used_ > arena_->slot_bytes_) used_ = arena_->slot_bytes_;
  }
  state.store(token_ << 1, std::memory_order_release);
}

}  // namespace tessera::transport
