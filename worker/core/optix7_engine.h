// TEMPORARY stand-in for helper's header (same interface as the brief); replaced at merge.
#ifndef TESSERA_WORKER_CORE_OPTIX7_ENGINE_H_
#define TESSERA_WORKER_CORE_OPTIX7_ENGINE_H_
#include <embree3/rtcore.h>
#include <atomic>
#include <map>
#include <mutex>
#include <unordered_map>
#include "absl/status/status.h"
#include "runtime.h"
#include "tessera/v1/launch.pb.h"
#include "tessera/v1/state.pb.h"
namespace tessera::worker {
struct Optix7State {
  std::unordered_map<uint64_t, v1::Optix7ProgramGroup> program_groups;
  std::unordered_map<uint64_t, v1::Optix7Pipeline> pipelines;
  std::map<uint64_t, uint64_t> allocations;
};
std::mutex& Optix7CallMutex();
class Optix7Engine {
 public:
  explicit Optix7Engine(RTCDevice device);
  ~Optix7Engine();
  absl::Status Prepare(const Optix7State& state, const v1::Optix7Launch& launch,
                       const std::atomic<bool>* cancel);
  bool RunTile(const Index3& origin, const Index3& size, const Index3& dims,
               const std::atomic<bool>& cancel, const std::atomic<bool>& stop, v1::TileResult& out);
};
}  // namespace tessera::worker
#endif
