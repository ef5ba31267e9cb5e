// What the host knows one device holds: object versions, buffer chunk hashes and program modules
// as of the last successful Apply, so the next delta carries only differences.
#ifndef TESSERA_API_SRC_DEVICE_SYNC_H_
#define TESSERA_API_SRC_DEVICE_SYNC_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "device_table.h"
#include "tessera/scheduler/device.h"

namespace tessera::api {

class DeviceJoiner;  // device_joiner.h

struct BufferSyncState {
  uint64_t byte_size = 0;
  uint64_t host_write_epoch = 0;  // GPU_LOCAL: the host writes the device has received
  std::vector<uint64_t> hashes;   // per chunk; 0 = unknown
};

struct DeviceSync {
  int ordinal = -1;  // the device's number in the context's device list (device pointers)
  uint64_t session_id = 0;
  uint64_t next_sequence = 1;
  uint64_t context_version = 0;
  std::string last_context;  // the ContextState last applied, serialized (skips unchanged ones)
  absl::flat_hash_map<uint64_t, uint64_t> versions;  // object id → version the device has
  absl::flat_hash_map<uint64_t, BufferSyncState> buffers;
  // Hashes of the program modules the device has received (state.proto ModuleChunk).
  absl::flat_hash_set<std::string> modules;
  // OptiX 7 (api/optix7/launch7.cc): program group and pipeline versions, the device memory
  // allocations and write epoch the device has, and the hash of each piece of device memory it
  // received, by address.
  absl::flat_hash_map<uint64_t, uint64_t> optix7_versions;
  uint64_t allocation_generation = 0;
  bool memory_synced = false;      // has taken the whole device memory once
  uint64_t memory_epoch = 0;       // host writes up to this epoch it has
  uint64_t memory_run_cursor = 0;  // runs other devices wrote, up to this one, it has
  absl::flat_hash_map<uint64_t, uint64_t> memory_hashes;
};

// A device a context uses, created at its first launch.
struct DeviceSlot {
  DeviceDesc desc;
  std::unique_ptr<Device> device;  // null until created, and after it was lost
  DeviceSync sync;
  bool lost = false;  // lost (or never started): created again, or left out, at the next launch
  bool start_failure_said = false;  // a failure to start was said in the log; reset once it starts
  // A running worker (HOST:PORT, unix:PATH) that did not answer or was lost: tried again in the
  // background until it answers, and taken by the launch after that (Context::EnsureDevices).
  // (shared_ptr: destroyed where DeviceJoiner is incomplete, which unique_ptr cannot do.)
  std::shared_ptr<DeviceJoiner> joiner;
  std::string down_reason;  // why it was lost or did not answer, for the line that says so
  // The device's threads when it last existed: a device gone at a launch with stable tile
  // ownership still counts toward the tile size, so that the other devices keep their tiles.
  int threads = 0;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_DEVICE_SYNC_H_
