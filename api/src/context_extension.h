// State that travels with a context's deltas and launches without being part of its OptiX 3
// object graph: the OptiX 7 layer (api/optix7/launch7.cc) runs its launches on an internal
// context and adds its pipelines and device memory to what each device receives. api/src knows
// only this interface.
#ifndef TESSERA_API_SRC_CONTEXT_EXTENSION_H_
#define TESSERA_API_SRC_CONTEXT_EXTENSION_H_

#include <cstddef>

#include "absl/status/status.h"
#include "device_sync.h"
#include "lowering.h"
#include "tessera/v1/launch.pb.h"

namespace tessera::api {

class ContextExtension {
 public:
  virtual ~ContextExtension() = default;
  // Adds to `prepared` what device `slot` lacks of the extension's state, and to
  // prepared->commits what its DeviceSync records once the device took it.
  virtual void AddToDelta(const DeviceSlot& slot, PreparedDelta* prepared) = 0;
  // A region with device_memory set that device `slot` sent back.
  virtual absl::Status ApplyWritten(const DeviceSlot& slot, const v1::BufferRegion& region) = 0;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_CONTEXT_EXTENSION_H_
