// Embree scenes of OptiX 7 accelerations: built by each worker from the descriptor optixAccelBuild
// left in device memory (worker/memory/accel_format.h), lazily and cached by the descriptor's
// content hash, so that the same geometry is built once whatever handle or launch names it
// (docs/device_memory.md, "Accelerations").
#ifndef TESSERA_WORKER_CORE_OPTIX7_SCENE_H_
#define TESSERA_WORKER_CORE_OPTIX7_SCENE_H_

#include <embree3/rtcore.h>

#include <bitset>
#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <vector>

#include "absl/status/statusor.h"
#include "accel_format.h"

namespace tessera::worker {

struct Optix7Scene {
  ~Optix7Scene();
  RTCScene scene = nullptr;
  memory::AccelKind kind = memory::AccelKind::kTriangles;
  // GAS: the build input of each Embree geometry (geomID), whose primitive IDs count from 0 in
  // the input; IAS: the child scene of each instance.
  std::vector<uint32_t> input_of_geometry;
  std::vector<const Optix7Scene*> children;
  // Per custom-primitive geometry, where its boxes are: what its bounds function reads (reserved
  // up front, so that the addresses Embree holds stay put).
  std::vector<const float*> custom_boxes;
  // The descriptor the scene was built from, in device memory (valid while the memory is).
  const memory::AccelHeader* header = nullptr;

  // What the engine needs at a hit, copied out of the descriptor so that tracing reads no
  // descriptor fields. GAS: per Embree geometry, its build input and the SBT geometry-AS index of
  // the input's first record (the prefix sum of num_sbt_records over the inputs before it, empty
  // inputs included: OptiX 7.7 guide 7.3.2).
  struct Geometry {
    memory::AccelInput input;
    uint32_t sbt_base = 0;
  };
  std::vector<Geometry> geometries;
  // GAS: the SBT geometry-AS index where each input's records begin, per input (empty inputs
  // included), and one past the last: optixGetTriangleVertexData finds an input by it.
  std::vector<uint32_t> sbt_bases;
  // IAS: per instance (its Embree geometry ID is its index), the OptixInstance fields and the
  // inverse of its transform (3x4 row-major, object to world).
  struct Instance {
    // Aligned: programs read them as float4[3] (optixGetInstanceTransformFromHandle).
    alignas(16) float to_world[12];
    alignas(16) float to_object[12];
    uint32_t id = 0, sbt_offset = 0, mask = 0, flags = 0;
    uint64_t child = 0;
  };
  std::vector<Instance> instances;
  // IAS: bit r is set when every instance shares a bit with visibility mask r: rays with such a
  // mask need no per-hit mask test.
  std::bitset<256> all_visible;
};

class Optix7SceneCache {
 public:
  // How many bytes of device memory can be read from an address (0: none, not device memory):
  // what keeps a handle an instance names from sending a read anywhere.
  using Readable = std::function<size_t(uint64_t address)>;
  // `intersect`: the intersection function of custom primitives (the engine's, which runs the
  // hit group's intersection program); their bounds come from the descriptor.
  Optix7SceneCache(RTCDevice device, RTCIntersectFunctionN intersect, Readable readable)
      : device_(device), intersect_(intersect), readable_(std::move(readable)) {}
  Optix7SceneCache(const Optix7SceneCache&) = delete;
  Optix7SceneCache& operator=(const Optix7SceneCache&) = delete;

  // The scene of the descriptor at `handle`. INVALID_ARGUMENT for a handle that is no descriptor;
  // UNIMPLEMENTED for an instance whose child is itself an instance build (Embree here has one
  // instance level; deeper instancing goes through the engine's own traversal, not yet built).
  absl::StatusOr<const Optix7Scene*> Get(uint64_t handle);

  size_t built() const { return built_; }

 private:
  RTCDevice device_;
  RTCIntersectFunctionN intersect_;
  Readable readable_;
  std::unordered_map<uint64_t, std::unique_ptr<Optix7Scene>> by_hash_;
  size_t built_ = 0;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_SCENE_H_
