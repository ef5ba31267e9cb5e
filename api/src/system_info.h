// The machine facts of tessera/scheduler/system_info.h, under the names the API layer uses.
#ifndef TESSERA_API_SRC_SYSTEM_INFO_H_
#define TESSERA_API_SRC_SYSTEM_INFO_H_

#include "tessera/scheduler/system_info.h"

namespace tessera::api {

using scheduler::AvailableSystemMemory;
using scheduler::CpuClockKHz;
using scheduler::HardwareThreads;
using scheduler::TotalSystemMemory;

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_SYSTEM_INFO_H_
