// Hooks for tests of the launch path (linked from tessera::api_core, never part of rt.h).
#ifndef TESSERA_API_SRC_TESTING_HOOKS_H_
#define TESSERA_API_SRC_TESTING_HOOKS_H_

#include <memory>
#include <vector>

#include "tessera/rt.h"
#include "tessera/scheduler/device.h"

namespace tessera::api::testing {

// Makes `context` launch on `devices` (e.g. fakes) instead of the devices of its spec.
RTresult UseDevices(RTcontext context, std::vector<std::unique_ptr<Device>> devices);

}  // namespace tessera::api::testing

#endif  // TESSERA_API_SRC_TESTING_HOOKS_H_
