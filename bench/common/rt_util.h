// What every benchmark needs around the C API: failures as exceptions carrying the context's
// error string, device selection, transfer counters and medians of timed runs.
#ifndef TESSERA_BENCH_COMMON_RT_UTIL_H_
#define TESSERA_BENCH_COMMON_RT_UTIL_H_

#include <tessera/rt.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera::bench {

// A failed rt* call or a wrong figure; main() prints it and exits non-zero.
class BenchError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws BenchError naming `what` with rtContextGetErrorString's message unless `code` is
// RT_SUCCESS. `context` may be null.
void Check(RTcontext context, RTresult code, const std::string& what);

// The devices `spec` names (tesseraContextSetDeviceSpec): benchmarks name their devices rather
// than inherit TESSERA_DEVICES, which ctest sets to "inproc" for every test.
void UseDevices(RTcontext context, const std::string& spec);

// tesseraContextGetTransferStats: buffer bytes host → devices and devices → host so far.
struct TransferStats {
  uint64_t sent = 0;
  uint64_t received = 0;
};
TransferStats GetTransferStats(RTcontext context);
TransferStats operator-(const TransferStats& a, const TransferStats& b);

// Seconds on the steady clock since an arbitrary epoch.
double NowSeconds();

// The median of `seconds` (the mean of the middle two for an even count); throws when empty.
double Median(std::vector<double> seconds);

// The 1-minute load average (-1 if unknown): other work on the machine skews timings.
double LoadAverage();

}  // namespace tessera::bench

#endif  // TESSERA_BENCH_COMMON_RT_UTIL_H_
