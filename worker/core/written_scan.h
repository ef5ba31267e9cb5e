// Finding what a call wrote: runs of a buffer's elements whose written marks a collection takes
// (Replica::TakeWrittenRegions), and of those the elements whose bytes changed.
//
// A collection at the end of a call looks at every element of every written block: one byte of
// marks and one compare of the element's bytes each. Element by element (an atomic load, a range
// test, a memcmp call, a run appended) that took 3.9% of a 16-thread eyelight launch's samples
// on the 16-core machine, where the scan runs while every other thread waits. Here marks are read
// eight at a time and tested with SSE2, and bytes are compared a chunk at a time, element by
// element only inside a chunk that differs, with the element size a constant where it is a usual
// one.
#ifndef TESSERA_WORKER_CORE_WRITTEN_SCAN_H_
#define TESSERA_WORKER_CORE_WRITTEN_SCAN_H_

#include <emmintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace tessera::worker {

struct ElementRun {
  size_t begin, end;
};

// Appends [begin, end) to `runs`, extending the last run when the two touch.
inline void AppendRun(std::vector<ElementRun>& runs, size_t begin, size_t end) {
  if (!runs.empty() && runs.back().end == begin) {
    runs.back().end = end;
  } else {
    runs.push_back({begin, end});
  }
}

// The marks a collection takes: epochs in (after, upto], or every one above `after` when `last`.
struct MarkRange {
  unsigned char after;
  unsigned char upto;
  bool last;
  bool Taken(unsigned char m) const { return m > after && (last || m <= upto); }
};

// Bit i set where byte i of `word` (memory order) is a mark `range` takes.
inline unsigned TakenBits(uint64_t word, const MarkRange& range) {
  if (range.after == 0xFF) return 0;
  const __m128i m = _mm_cvtsi64_si128(static_cast<long long>(word));
  // m > after  <=>  max(m, after + 1) == m;  m <= upto  <=>  min(m, upto) == m.
  const __m128i above = _mm_set1_epi8(static_cast<char>(range.after + 1));
  __m128i taken = _mm_cmpeq_epi8(_mm_max_epu8(m, above), m);
  if (!range.last) {
    const __m128i upto = _mm_set1_epi8(static_cast<char>(range.upto));
    taken = _mm_and_si128(taken, _mm_cmpeq_epi8(_mm_min_epu8(m, upto), m));
  }
  return static_cast<unsigned>(_mm_movemask_epi8(taken)) & 0xFFu;
}

// Calls fn(begin, end) for each maximal run of taken marks among marks[begin, end), in order.
// Marks may be raised while this reads them (collections during a call): each is read once,
// atomically, eight at a time where they are aligned.
template <typename Fn>
void ForEachTakenRun(const unsigned char* marks, size_t begin, size_t end, const MarkRange& range,
                     Fn&& fn) {
  using Word = uint64_t __attribute__((may_alias));
  constexpr size_t kNone = ~size_t{0};
  size_t open = kNone;  // where the run being extended began
  auto step = [&](size_t e, bool taken) {
    if (taken && open == kNone) open = e;
    if (!taken && open != kNone) {
      fn(open, e);
      open = kNone;
    }
  };
  size_t e = begin;
  while (e < end) {
    if ((reinterpret_cast<uintptr_t>(marks + e) & 7) == 0 && end - e >= 8) {
      const uint64_t word =
          __atomic_load_n(reinterpret_cast<const Word*>(marks + e), __ATOMIC_RELAXED);
      const unsigned bits = TakenBits(word, range);
      if (bits == 0xFFu) {
        if (open == kNone) open = e;
      } else if (bits == 0) {
        step(e, false);
      } else {
        for (size_t i = 0; i < 8; ++i) step(e + i, (bits >> i) & 1u);
      }
      e += 8;
    } else {
      step(e, range.Taken(__atomic_load_n(marks + e, __ATOMIC_RELAXED)));
      ++e;
    }
  }
  if (open != kNone) fn(open, end);
}

namespace written_scan_detail {

// Elements compared as one block before they are compared one by one.
inline constexpr size_t kChunkElements = 64;

// kSize: the element size where it is a constant (memcmp then compiles to loads), 0 for `size`.
template <size_t kSize>
void AppendChangedSized(const unsigned char* data, const unsigned char* before, size_t size,
                        size_t begin, size_t end, std::vector<ElementRun>& runs) {
  const size_t n = kSize != 0 ? kSize : size;
  for (size_t e = begin; e < end;) {
    const size_t chunk_end = std::min(end, e + kChunkElements);
    if (std::memcmp(data + e * n, before + e * n, (chunk_end - e) * n) == 0) {
      e = chunk_end;
      continue;
    }
    for (; e < chunk_end; ++e) {
      if (std::memcmp(data + e * n, before + e * n, kSize != 0 ? kSize : size) != 0) {
        AppendRun(runs, e, e + 1);
      }
    }
  }
}

}  // namespace written_scan_detail

// Appends the elements of [begin, end) (each `size` bytes) whose bytes in `data` differ from
// those in `before`, as runs joined where they touch.
inline void AppendChanged(const unsigned char* data, const unsigned char* before, size_t size,
                          size_t begin, size_t end, std::vector<ElementRun>& runs) {
  using written_scan_detail::AppendChangedSized;
  switch (size) {
    case 1:
      return AppendChangedSized<1>(data, before, size, begin, end, runs);
    case 2:
      return AppendChangedSized<2>(data, before, size, begin, end, runs);
    case 4:
      return AppendChangedSized<4>(data, before, size, begin, end, runs);
    case 8:
      return AppendChangedSized<8>(data, before, size, begin, end, runs);
    case 12:
      return AppendChangedSized<12>(data, before, size, begin, end, runs);
    case 16:
      return AppendChangedSized<16>(data, before, size, begin, end, runs);
    default:
      return AppendChangedSized<0>(data, before, size, begin, end, runs);
  }
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_WRITTEN_SCAN_H_
