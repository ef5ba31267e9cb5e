#include "common/rt_util.h"

#include <tessera/rt_ext.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace tessera::bench {

void Check(RTcontext context, RTresult code, const std::string& what) {
  if (code == RT_SUCCESS) return;
  const char* message = nullptr;
  rtContextGetErrorString(context, code, &message);
  throw BenchError(what + " failed: " + (message != nullptr ? message : "(no message)"));
}

void UseDevices(RTcontext context, const std::string& spec) {
  Check(context, tesseraContextSetDeviceSpec(context, spec.c_str()),
        "tesseraContextSetDeviceSpec(\"" + spec + "\")");
}

TransferStats GetTransferStats(RTcontext context) {
  unsigned long long sent = 0, received = 0;
  Check(context, tesseraContextGetTransferStats(context, &sent, &received),
        "tesseraContextGetTransferStats");
  return TransferStats{sent, received};
}

TransferStats operator-(const TransferStats& a, const TransferStats& b) {
  return TransferStats{a.sent - b.sent, a.received - b.received};
}

double NowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double Median(std::vector<double> seconds) {
  if (seconds.empty()) throw BenchError("no timed runs");
  std::sort(seconds.begin(), seconds.end());
  const size_t n = seconds.size();
  return n % 2 == 1 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
}

double LoadAverage() {
  double load = -1;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = -1;
    std::fclose(f);
  }
  return load;
}

}  // namespace tessera::bench
