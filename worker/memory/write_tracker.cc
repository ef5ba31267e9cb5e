#include "write_tracker.h"

#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace tessera::memory {
namespace {

enum : uint8_t { kFree = 0, kProtected = 1, kCopying = 2, kWritten = 3 };

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
  protected_.emplace_back(p0, p1);
  return absl::OkStatus();
}

// Async-signal-safe: atomics, memcpy and mprotect only.
bool WriteTracker::Take(uintptr_t address) {
  if (address < base_ || address >= base_ + size_) return false;
  const size_t p = (address - base_) / page_;
  uint8_t expected = kProtected;
  if (state_[p].compare_exchange_strong(expected, kCopying, std::memory_order_acq_rel)) {
    void* page = reinterpret_cast<void*>(base_ + p * page_);
    std::memcpy(shadow_ + p * page_, page, page_);  // the page is readable while protected
    mprotect(page, page_, PROT_READ | PROT_WRITE);
    written_.fetch_add(1, std::memory_order_relaxed);
    state_[p].store(kWritten, std::memory_order_release);
    return true;
  }
  if (expected == kCopying) {  // another thread's first write: wait until the page is writable
    while (state_[p].load(std::memory_order_acquire) == kCopying) {
    }
    return true;
  }
  // kWritten: the page became writable after this thread faulted; the write goes through now.
  return expected == kWritten;
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

std::vector<WriteTracker::Run> WriteTracker::Collect() {
  std::vector<Run> runs;
  std::sort(protected_.begin(), protected_.end());  // runs in address order
  for (const auto& [p0, p1] : protected_) {
    mprotect(reinterpret_cast<void*>(base_ + p0 * page_), (p1 - p0) * page_,
             PROT_READ | PROT_WRITE);
    for (size_t p = p0; p < p1; ++p) {
      const uint8_t s = state_[p].exchange(kFree, std::memory_order_acq_rel);
      if (s != kWritten) continue;
      const auto* now = reinterpret_cast<const unsigned char*>(base_ + p * page_);
      const unsigned char* before = shadow_ + p * page_;
      for (size_t i = 0; i < page_;) {
        if (now[i] == before[i]) {
          ++i;
          continue;
        }
        size_t j = i;
        while (j < page_ && now[j] != before[j]) ++j;
        const uintptr_t at = base_ + p * page_ + i;
        if (!runs.empty() && runs.back().first + runs.back().second == at) {
          runs.back().second += j - i;
        } else {
          runs.emplace_back(at, j - i);
        }
        i = j;
      }
    }
  }
  protected_.clear();
  written_.store(0, std::memory_order_relaxed);
  return runs;
}

}  // namespace tessera::memory
