// What Optix7Engine::Prepare resolves of an optixLaunch before any tile runs: the pipeline's
// program groups as entry functions, and every SBT record as the program group its header names
// plus the address of its data. Read-only while tiles run, so tracing threads share it without
// locks. Internal to worker/core (optix7_*.cc).
#ifndef TESSERA_WORKER_CORE_OPTIX7_LAUNCH_H_
#define TESSERA_WORKER_CORE_OPTIX7_LAUNCH_H_

#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "tessera/v1/state.pb.h"

namespace tessera::worker {

class Optix7Engine;

// Every OptiX 7 entry point is `extern "C" void __<kind>__<name>()`; callables are called with
// their own signature by the module itself (optixDirectCall), so the engine only hands them out.
using Optix7Function = void (*)();

// One entry function of a program group, with its name for messages.
struct Optix7Entry {
  Optix7Function function = nullptr;
  std::string name;  // "__closesthit__ch in /path/module.so"
};

struct Optix7Group {
  uint64_t id = 0;
  uint32_t kind = 0;  // OptixProgramGroupKind
  Optix7Entry entry;  // raygen, miss, exception, direct callable
  Optix7Entry continuation;
  Optix7Entry closest_hit, any_hit, intersection;
  uint32_t builtin_primitive = 0;  // OptixPrimitiveType of a built-in intersection
};

// One SBT record: the program group its header names and where its data block starts (the
// record's address plus the 32-byte header), which optixGetSbtDataPointer returns.
struct Optix7Record {
  const Optix7Group* group = nullptr;
  uint64_t data = 0;
  uint32_t index = 0;  // within its section, for messages
};

struct Optix7Launch {
  // Distinguishes launches (and engines) in per-thread caches: unique in the process.
  uint64_t serial = 0;
  Optix7Engine* engine = nullptr;
  uint32_t max_trace_depth = 0;  // OptixPipelineLinkOptions::maxTraceDepth, at most 31
  uint32_t exception_flags = 0;  // OptixExceptionFlags
  // What the pipeline's compile options say its traces may meet (OptiX specializes its programs
  // for them): OptixTraversableGraphFlags, OptixPrimitiveTypeFlags as OptiX reads them (0 means
  // custom and triangles), usesMotionBlur. A scene beyond them is an error (SceneOf).
  uint32_t graph_flags = 0;
  uint32_t primitive_flags = 0;
  bool motion_blur = false;
  // TESSERA_ACCURACY_* bits of the launch's context (Optix7Launch.accuracy_flags): how scenes are
  // built (robust, watertight, compact) and whether closest-hit programs' rays are offset.
  uint32_t accuracy = 0;
  // Live device memory, address -> size (a copy: the device's state may change after the call).
  std::map<uint64_t, uint64_t> allocations;
  std::unordered_map<uint64_t, Optix7Group> groups;  // the pipeline's, by id
  Optix7Record raygen;
  Optix7Record exception;  // group null: none
  std::vector<Optix7Record> miss, hit, callables;
  // Whether some hit group record has an any-hit program: traces on triangles then need the
  // per-hit filter; without one (and without culling, masks or early termination) they need none.
  bool any_hit = false;
  // Whether the tiles run with denormals flushed to zero (float_mode.h): a module of the pipeline
  // was compiled with fast math, or the context asked for it (TESSERA_ACCURACY_FAST_MATH).
  bool flush_denormals = false;
  // Whether tiles run in blocks of lanes whose rays are traced as packets (optix7_batch.h), or
  // one launch index and one ray at a time (Optix7Launch.batched).
  bool batched = false;

  // How many bytes can be read from `address` to the end of its allocation (0: none).
  uint64_t Readable(uint64_t address) const {
    auto it = allocations.upper_bound(address);
    if (it == allocations.begin()) return 0;
    --it;
    const uint64_t end = it->first + it->second;
    return address < end ? end - address : 0;
  }
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_LAUNCH_H_
