// What the machine offers this process.
#include "tessera/scheduler/system_info.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <thread>

namespace tessera::scheduler {
namespace {

// The default worker and thread counts follow the CPUs the process may use (taskset, cpusets,
// Slurm allocations), not every CPU of the machine.
TEST(SystemInfoTest, HardwareThreadsFollowTheAffinityMask) {
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof(all), &all), 0);
  EXPECT_EQ(HardwareThreads(), CPU_COUNT(&all));
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  // On a thread of its own: affinity is per thread, and the test runner's must stay as it was.
  int seen = 0;
  std::thread([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    if (sched_setaffinity(0, sizeof(one), &one) == 0) seen = HardwareThreads();
  }).join();
  EXPECT_EQ(seen, 1);
}

}  // namespace
}  // namespace tessera::scheduler
