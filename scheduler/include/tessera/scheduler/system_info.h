// Facts about the machine a process runs on, which OptiX reports as device and context
// attributes: the host for in-process and local devices, a worker for itself (its Health reply).
#ifndef TESSERA_SCHEDULER_SYSTEM_INFO_H_
#define TESSERA_SCHEDULER_SYSTEM_INFO_H_

#include <cstdint>

namespace tessera::scheduler {

int HardwareThreads();             // at least 1
uint64_t TotalSystemMemory();      // bytes
uint64_t AvailableSystemMemory();  // bytes the kernel reports as available
int CpuClockKHz();                 // 0 when unknown

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_SYSTEM_INFO_H_
