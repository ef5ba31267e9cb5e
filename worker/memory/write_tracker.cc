#include "write_tracker.h"

#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <tuple>

#include "absl/strings/str_cat.h"

namespace tessera::memory {
namespace {

enum : uint8_t { kFree = 0, kProtected = 1, kCopying = 2, kWritten = 3 };
constexpr size_t kBlockPages = 16;  // 64 KiB with 4 KiB pages

std::atomic<WriteTracker*> g_armed{nullptr};
struct sigaction g_previous;  // the handler before ours (the crash reporter's)

}  // namespace

WriteTracker::WriteTracker(uintptr_t base, size_t size, size_t page)
    : base_(base), size_(size), page_(page) {}

absl::StatusOr<std::unique_ptr<WriteTracker>> WriteTracker::Create(uintptr_t base, size_t size) {
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  if (size == 0 || base % page != 0 || size % page != 0) {
    return absl::InvalidArgumentError("write tracking needs a page-aligned, nonempty range");
  }
  std::unique_ptr<WriteTracker> t(new WriteTracker(base, size, page));
  // Both cost nothing until touched: a copy of a page when it is first written, a byte of state
  // per page.
  void* shadow = mmap(nullptr, size, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  void* state = mmap(nullptr, size / page, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (shadow == MAP_FAILED || state == MAP_FAILED) {
    if (shadow != MAP_FAILED) munmap(shadow, size);
    if (state != MAP_FAILED) munmap(state, size / page);
    return absl::ResourceExhaustedError("cannot reserve memory for write tracking");
  }
  t->shadow_ = static_cast<unsigned char*>(shadow);
  t->state_ = static_cast<std::atomic<uint8_t>*>(state);
  WriteTracker* none = nullptr;
  if (!g_armed.compare_exchange_strong(none, t.get())) {
    return absl::FailedPreconditionError("another write tracker is armed in this process");
  }
  struct sigaction action;
  std::memset(&action, 0, sizeof(action));
  action.sa_sigaction = reinterpret_cast<void (*)(int, siginfo_t*, void*)>(&OnFault);
  action.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
  sigemptyset(&action.sa_mask);
  sigaction(SIGSEGV, &action, &g_previous);
  return t;
}

WriteTracker::~WriteTracker() {
  if (g_armed.load() == this) {
    (void)Collect();
    sigaction(SIGSEGV, &g_previous, nullptr);
    g_armed.store(nullptr);
  }
  if (shadow_ != nullptr) munmap(shadow_, size_);
  if (state_ != nullptr) munmap(state_, size_ / page_);
}

absl::Status WriteTracker::Protect(uintptr_t address, size_t length) {
  const uintptr_t first = address / page_ * page_;
  const uintptr_t end = (address + length + page_ - 1) / page_ * page_;
  if (first < base_ || end > base_ + size_ || end < first) {
    return absl::OutOfRangeError("write tracking outside its range");
  }
  if (end == first) return absl::OkStatus();
  const size_t p0 = (first - base_) / page_, p1 = (end - base_) / page_;
  for (size_t p = p0; p < p1; ++p) state_[p].store(kProtected, std::memory_order_relaxed);
  if (mprotect(reinterpret_cast<void*>(first), end - first, PROT_READ) != 0) {
    for (size_t p = p0; p < p1; ++p) state_[p].store(kFree, std::memory_order_relaxed);
    return absl::InternalError(
        absl::StrCat("cannot write-protect device memory: ", std::strerror(errno)));
  }
  protected_.push_back(Protected{p0, p1, address});
  return absl::OkStatus();
}

absl::Status WriteTracker::Snapshot(uintptr_t address, size_t length) {
  const uintptr_t first = address / page_ * page_;
  const uintptr_t end = (address + length + page_ - 1) / page_ * page_;
  if (first < base_ || end > base_ + size_ || end < first) {
    return absl::OutOfRangeError("write tracking outside its range");
  }
  if (end == first) return absl::OkStatus();
  const size_t p0 = (first - base_) / page_, p1 = (end - base_) / page_;
  std::memcpy(shadow_ + p0 * page_, reinterpret_cast<const void*>(first), end - first);
  for (size_t p = p0; p < p1; ++p) state_[p].store(kWritten, std::memory_order_relaxed);
  snapshots_.emplace_back(p0, p1);
  return absl::OkStatus();
}

// Async-signal-safe: atomics, memcpy, mprotect and write only. A fault claims every protected
// page of the faulting page's block of kBlockPages (aligned to the range's base), not the page
// alone: a program that writes one page usually writes its neighbours, a fault costs tens of
// microseconds with several threads (each change of protection flushes their TLBs), and fewer,
// larger writable stretches keep the process's count of memory mappings down.
bool WriteTracker::Take(uintptr_t address) {
  if (address < base_ || address >= base_ + size_) return false;
  const size_t p = (address - base_) / page_;
  const uint8_t was = state_[p].load(std::memory_order_acquire);
  if (was == kFree) return false;  // not tracked: the program's own bad write
  const size_t b0 = p / kBlockPages * kBlockPages;
  const size_t b1 = std::min(b0 + kBlockPages, size_ / page_);
  size_t run_begin = 0, run_end = 0;  // pages this thread claimed, made writable together
  auto unprotect = [&] {
    if (run_end == run_begin) return;
    void* at = reinterpret_cast<void*>(base_ + run_begin * page_);
    if (mprotect(at, (run_end - run_begin) * page_, PROT_READ | PROT_WRITE) != 0) {
      // Retrying the write would fault forever: say why and end the process, as a crash does.
      static const char kMessage[] =
          "tessera-worker: crashed: cannot make tracked device memory writable again (too many "
          "memory mappings? raise vm.max_map_count)\n";
      (void)!write(2, kMessage, sizeof(kMessage) - 1);
      _exit(70);
    }
    for (size_t q = run_begin; q < run_end; ++q) {
      state_[q].store(kWritten, std::memory_order_release);
    }
    run_begin = run_end = 0;
  };
  for (size_t q = b0; q < b1; ++q) {
    uint8_t expected = kProtected;
    if (state_[q].compare_exchange_strong(expected, kCopying, std::memory_order_acq_rel)) {
      std::memcpy(shadow_ + q * page_, reinterpret_cast<const void*>(base_ + q * page_), page_);
      written_.fetch_add(1, std::memory_order_relaxed);
      if (run_end != q) {
        unprotect();
        run_begin = q;
      }
      run_end = q + 1;
    } else {
      unprotect();
    }
  }
  unprotect();
  // Another thread claimed the faulting page first: wait until it is writable.
  while (state_[p].load(std::memory_order_acquire) == kCopying) {
  }
  return state_[p].load(std::memory_order_acquire) == kWritten;
}

void WriteTracker::OnFault(int signal, void* info, void* context) {
  WriteTracker* t = g_armed.load(std::memory_order_acquire);
  const auto* si = static_cast<const siginfo_t*>(info);
  if (t != nullptr && si->si_code == SEGV_ACCERR &&
      t->Take(reinterpret_cast<uintptr_t>(si->si_addr))) {
    return;  // the write is retried and succeeds
  }
  // Not a tracked write: a program's own bug. Put the previous handler back and let the fault
  // happen again, so that it reports the crash as it would have.
  sigaction(SIGSEGV, &g_previous, nullptr);
  (void)signal;
  (void)context;
}

namespace {

// Appends the bytes of `now` that differ from `before` (`length` bytes at `address`) to `runs`,
// merging adjacent ones. Equal stretches are skipped 64 bytes at a time.
void AppendDifferences(const unsigned char* now, const unsigned char* before, size_t length,
                       uintptr_t address, std::vector<WriteTracker::Run>& runs) {
  size_t i = 0;
  while (i < length) {
    if (i + 64 <= length && std::memcmp(now + i, before + i, 64) == 0) {
      i += 64;
      continue;
    }
    if (now[i] == before[i]) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < length && now[j] != before[j]) ++j;
    const uintptr_t at = address + i;
    if (!runs.empty() && runs.back().first + runs.back().second == at) {
      runs.back().second += j - i;
    } else {
      runs.emplace_back(at, j - i);
    }
    i = j;
  }
}

}  // namespace

std::vector<WriteTracker::Run> WriteTracker::Collect(
    std::vector<std::pair<uintptr_t, size_t>>* faulted) {
  std::vector<Run> runs;
  if (faulted != nullptr) faulted->clear();
  for (const Protected& r : protected_) {
    mprotect(reinterpret_cast<void*>(base_ + r.p0 * page_), (r.p1 - r.p0) * page_,
             PROT_READ | PROT_WRITE);
  }
  // Every range, protected (with its address) or copied (0), in page order: runs come out sorted.
  std::vector<std::tuple<size_t, size_t, uintptr_t>> ranges;
  for (const Protected& r : protected_) ranges.emplace_back(r.p0, r.p1, r.address);
  for (const auto& [p0, p1] : snapshots_) ranges.emplace_back(p0, p1, 0);
  std::sort(ranges.begin(), ranges.end());
  for (const auto& [p0, p1, address] : ranges) {
    size_t written = 0;
    for (size_t p = p0; p < p1; ++p) {
      const uint8_t s = state_[p].exchange(kFree, std::memory_order_acq_rel);
      if (s != kWritten) continue;
      ++written;
      const auto* now = reinterpret_cast<const unsigned char*>(base_ + p * page_);
      AppendDifferences(now, shadow_ + p * page_, page_, base_ + p * page_, runs);
    }
    if (faulted != nullptr && address != 0) faulted->emplace_back(address, written);
  }
  protected_.clear();
  snapshots_.clear();
  written_.store(0, std::memory_order_relaxed);
  return runs;
}

}  // namespace tessera::memory
