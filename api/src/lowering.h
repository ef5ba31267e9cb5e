// Lowering: the host object graph becomes a v1::StateDelta for one device, carrying only what
// changed since that device's last successful Apply (docs/devices.md).
#ifndef TESSERA_API_SRC_LOWERING_H_
#define TESSERA_API_SRC_LOWERING_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "device_sync.h"
#include "tessera/v1/state.pb.h"

namespace tessera::api {

class Context;

// A delta plus the sync records it establishes once the device accepts it.
struct PreparedDelta {
  v1::StateDelta delta;
  std::vector<std::pair<uint64_t, uint64_t>> versions;        // id → version shipped
  std::vector<std::pair<uint64_t, BufferSyncState>> buffers;  // id → what it will hold
  std::vector<std::string> modules;                           // module hashes shipped
  // What else the device's sync record learns (a ContextExtension's state).
  std::vector<std::function<void(DeviceSync*)>> commits;
};

// Everything that changed for the device `sync` describes: the full ContextState; every object
// whose version differs (reachable from the context, plus every buffer, since programs can reach
// buffers by id); ids of destroyed objects the device holds; buffer chunks whose content hash
// the device lacks; and, once per device, the bytes of each program module it has not received.
// OUTPUT-only buffers never ship contents. The context must be valid.
PreparedDelta BuildDelta(Context& context, const DeviceSync& sync);
// The same for device `slot`, with what the context's extension (context_extension.h) adds.
PreparedDelta BuildDelta(Context& context, const DeviceSlot& slot);

// Ships module `hash` (`bytes`) in slices, unless the device has it or `out` carries it already.
void LowerModuleBytes(const std::string& hash, const std::string& bytes, const DeviceSync& sync,
                      PreparedDelta* out);

// The device applied the delta.
void CommitDelta(PreparedDelta&& prepared, DeviceSync* sync);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_LOWERING_H_
