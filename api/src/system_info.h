// Facts about the host machine that OptiX reports as device and context attributes.
#ifndef TESSERA_API_SRC_SYSTEM_INFO_H_
#define TESSERA_API_SRC_SYSTEM_INFO_H_

#include <cstdint>

namespace tessera::api {

int HardwareThreads();             // at least 1
uint64_t TotalSystemMemory();      // bytes
uint64_t AvailableSystemMemory();  // bytes the kernel reports as available
int CpuClockKHz();                 // 0 when unknown

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_SYSTEM_INFO_H_
