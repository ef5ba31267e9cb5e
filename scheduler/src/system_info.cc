#include "tessera/scheduler/system_info.h"

#include <sched.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <thread>

namespace tessera::scheduler {

int HardwareThreads() {
  // The CPUs this process may run on (taskset, a cgroup cpuset, a Slurm allocation), not every
  // CPU of the machine: defaults such as local:<cores> must not oversubscribe a share of it.
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof(set), &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
  unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

namespace {

// Bytes in `pages` (a sysconf count) of the system's page size; 0 when either is unknown.
uint64_t PageBytes(long pages) {
  const long page_size = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page_size <= 0) return 0;
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size);
}

}  // namespace

uint64_t TotalSystemMemory() { return PageBytes(sysconf(_SC_PHYS_PAGES)); }

uint64_t AvailableSystemMemory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit) {
    if (key == "MemAvailable:") return kib * 1024;
  }
  return PageBytes(sysconf(_SC_AVPHYS_PAGES));
}

int CpuClockKHz() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("cpu MHz", 0) != 0) continue;
    size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    try {
      return static_cast<int>(std::stod(line.substr(colon + 1)) * 1000.0);
    } catch (...) {
      return 0;
    }
  }
  return 0;
}

}  // namespace tessera::scheduler
