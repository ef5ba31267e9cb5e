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
#include "optix7_transforms.h"
#include "optix7_watertight.h"

namespace tessera::worker {

struct Optix7Scene;

// An instance of an IAS that Embree's one instance level cannot trace: its child is a transform
// traversable (static, matrix motion, SRT motion; chains of them), another IAS, or a GAS whose
// motion does not fit the IAS's time (Optix7Scene::time). The IAS holds it as a user geometry
// whose intersection function (the engine's) evaluates the transforms at the ray's time, moves
// the ray into the child's space and traces the child's scene there: docs/optix7_engine.md,
// "Traversable graphs".
struct Optix7Node {
  uint32_t instance = 0;                    // its index in the IAS
  std::vector<Optix7Transform> transforms;  // between the instance and the child, outermost first
  const Optix7Scene* child = nullptr;       // a GAS or an IAS
  uint64_t child_handle = 0;
  float bounds[6] = {};  // in the IAS's space, over every time: what Embree's bounds function says
};

struct Optix7Scene {
  ~Optix7Scene();
  RTCScene scene = nullptr;
  memory::AccelKind kind = memory::AccelKind::kTriangles;
  // The build's motion options (keys 1: built without motion).
  Optix7Motion motion;
  // The motion range Embree's time spans in this scene: a GAS's own; for an IAS, the range of the
  // moving GASes it instances directly (one range: those of another range become nodes).
  // Rays enter with Embree time time.Normalized(ray time).
  Optix7Motion time;
  // GAS: the build input of each Embree geometry (geomID), whose primitive IDs count from 0 in
  // the input; IAS: the child scene of each instance (the node's final child for a node).
  std::vector<uint32_t> input_of_geometry;
  std::vector<const Optix7Scene*> children;
  // Per custom-primitive geometry, where its boxes are (key after key): what its bounds function
  // reads (reserved up front, so that the addresses Embree holds stay put).
  struct Boxes {
    const float* boxes;
    uint64_t per_key;  // primitives
  };
  std::vector<Boxes> custom_boxes;
  // The descriptor the scene was built from, in device memory (valid while the memory is).
  const memory::AccelHeader* header = nullptr;
  // TESSERA_ACCURACY_ROBUST, _WATERTIGHT and _COMPACT bits it was built with: the launch's
  // context flags and the acceleration's TESSERA_OPTIX_BUILD_FLAG_* bits (AccuracyOf).
  uint32_t accuracy = 0;
  // Watertight mode: the triangles each such user geometry holds (by geomID; null for others).
  std::vector<std::unique_ptr<Optix7WatertightMesh>> watertight;
  // A GAS built with OPTIX_BUILD_FLAG_ALLOW_UPDATE: the buffer it was built for (0 otherwise),
  // whose OPTIX_BUILD_OPERATION_UPDATE refits this scene in place, and how often it was.
  uint64_t updatable = 0;
  unsigned refits = 0;

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
    const Optix7Node* node = nullptr;  // null: an Embree instance of a GAS
  };
  std::vector<Instance> instances;
  std::vector<std::unique_ptr<Optix7Node>> nodes;
  // Whether any instance is a node, or any nested IAS has one: traces then need the transform
  // list kept per level.
  bool deep = false;
  // What the graph from here down uses, checked against the pipeline's compile options when a
  // trace first meets the scene (SceneOf): OptixPrimitiveTypeFlags of its GASes; whether it or
  // anything below moves (motion options of an acceleration or a transform); whether it is an IAS
  // whose instances are GASes without transforms (OptiX's single-level instancing).
  uint32_t primitive_types = 0;
  bool any_motion = false;
  bool single_level = false;
  // Whether rays can be traced in it as Embree packets (optix7_batch.h): Embree's own primitives
  // (triangles, spheres) directly or under one level of Embree instances; custom primitives,
  // watertight triangles and nodes are called back per ray.
  bool packets = false;
  // IAS: bit r is set when every instance (of nested IASes too) shares a bit with visibility mask
  // r: rays with such a mask need no per-hit mask test.
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

  // `node_intersect`: the intersection function of nodes (Optix7Node), the engine's.
  void set_node_intersect(RTCIntersectFunctionN f) { node_intersect_ = f; }

  // The scene of the descriptor at `handle`. An IAS's scene is keyed by its content and its
  // children's (transforms' contents, nested scenes' keys), so that a child rebuilt in place
  // gives a new scene. Within one launch (`serial` > 0: the same device memory throughout)
  // answers are remembered by handle. INVALID_ARGUMENT for a handle that is no descriptor, a
  // transform that is not in device memory or has invalid motion options, a graph deeper than
  // kMaxGraphDepth or with a cycle.
  // `accuracy`: the launch's TESSERA_ACCURACY_* bits; scenes are keyed by what they were built
  // with, so launches of other settings get scenes of their own.
  absl::StatusOr<const Optix7Scene*> Get(uint64_t handle, uint64_t serial = 0,
                                         uint32_t accuracy = 0);

  size_t built() const { return built_; }
  size_t refitted() const { return refitted_; }

  // Instances and transforms on one path from a trace's root to a GAS, at most (a transform list
  // longer than OptiX's limit of traversable graph depth 31 is refused when a scene is built).
  static constexpr unsigned kMaxGraphDepth = 16;

 private:
  absl::StatusOr<const Optix7Scene*> GetAt(uint64_t handle, unsigned depth);
  absl::StatusOr<uint64_t> KeyOf(uint64_t handle, unsigned depth);
  absl::Status BuildInstances(uint64_t handle, unsigned depth, Optix7Scene& s);
  absl::Status BuildPrimitives(const unsigned char* bytes, Optix7Scene& s);
  // The ROBUST/WATERTIGHT/COMPACT bits a scene of `h` gets under the current launch.
  uint32_t AccuracyOf(const memory::AccelHeader& h) const;
  // A GAS's key: its content, build flags and accuracy, and for ALLOW_UPDATE its buffer.
  uint64_t GasKey(uint64_t handle, const memory::AccelHeader& h) const;
  // An OPTIX_BUILD_OPERATION_UPDATE of `handle` whose previous scene this cache holds with the
  // same counts and indices: refits that scene in place (Embree REFIT quality), files it under
  // `key` and forgets every IAS scene built over it. Null when it cannot (then a build follows).
  Optix7Scene* Refit(uint64_t handle, const memory::AccelHeader& h, uint64_t key);

  RTCDevice device_;
  RTCIntersectFunctionN intersect_;
  RTCIntersectFunctionN node_intersect_ = nullptr;
  Readable readable_;
  std::unordered_map<uint64_t, std::unique_ptr<Optix7Scene>> by_hash_;
  uint64_t serial_ = 0;
  std::unordered_map<uint64_t, const Optix7Scene*> this_launch_;  // by handle, for serial_
  std::unordered_map<uint64_t, uint64_t> keys_this_launch_;       // by handle, for serial_
  uint32_t accuracy_ = 0;                                         // of the launch of serial_
  // ALLOW_UPDATE GASes: the key of the scene last built or refit for each buffer.
  std::unordered_map<uint64_t, uint64_t> updatable_;
  size_t built_ = 0;
  size_t refitted_ = 0;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_SCENE_H_
