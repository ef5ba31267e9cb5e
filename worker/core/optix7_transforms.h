// Transforms of OptiX 7 traversable graphs, evaluated at a ray's time as OptiX 7.7 defines them
// (guide 5.10): static transforms, matrix motion transforms (element-wise linear interpolation of
// the two nearest keys), SRT motion transforms (components interpolated linearly, the quaternion
// normalized afterwards: nlerp, then C = T * R * S), motion options (keys evenly spaced between
// timeBegin and timeEnd, time clamped to the range unless a vanish flag removes the object).
// Matrices are 3x4 row-major, object to world, as OptixInstance::transform.
#ifndef TESSERA_WORKER_CORE_OPTIX7_TRANSFORMS_H_
#define TESSERA_WORKER_CORE_OPTIX7_TRANSFORMS_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::worker {

// A transform traversable's handle is its device address with its OptixTransformType in the low
// bits (transforms are 64-byte aligned; accelerations, 128-byte aligned, have no tag): what
// optixConvertPointerToTraversableHandle returns and the transform list shows.
inline constexpr uint64_t kTransformTagMask = 63;
inline uint32_t TransformTag(uint64_t handle) {
  return static_cast<uint32_t>(handle & kTransformTagMask);
}
inline uint64_t TransformAddress(uint64_t handle) { return handle & ~kTransformTagMask; }
// Tags 1 to 3 (OPTIX_TRANSFORM_TYPE_STATIC_TRANSFORM to SRT_MOTION_TRANSFORM); other low bits
// are no transform (a descriptor the tests keep in heap memory, 16-byte aligned).
inline bool IsTransformHandle(uint64_t handle) {
  const uint32_t tag = TransformTag(handle);
  return tag >= 1 && tag <= 3;
}

inline constexpr float kIdentity3x4[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

// OptixMotionOptions as the engine keeps them (keys 1: no motion).
struct Optix7Motion {
  uint32_t keys = 1;
  uint32_t flags = 0;  // OptixMotionFlags
  float begin = 0.f, end = 0.f;

  bool moves() const { return keys > 1; }
  // Whether the object is absent at `time` (a vanish flag and a time outside the range).
  bool Vanished(float time) const;
  // `time` as a fraction of the range, clamped to [0, 1] (0 without motion): Embree's time.
  float Normalized(float time) const;
  bool operator==(const Optix7Motion& o) const {
    return keys == o.keys && flags == o.flags && begin == o.begin && end == o.end;
  }
};

// One static or motion transform traversable, copied out of device memory when the scene that
// reaches it was built.
struct Optix7Transform {
  uint64_t handle = 0;  // tagged, as the program sees it
  uint32_t type = 0;    // OptixTransformType: STATIC, MATRIX_MOTION or SRT_MOTION
  Optix7Motion motion;  // keys 1 for a static transform
  // STATIC: transform[12] then invTransform[12]; MATRIX_MOTION: 12 per key; SRT_MOTION: 16 per
  // key (OptixSRTData).
  std::vector<float> data;
  uint64_t child = 0;

  // Object to world and world to object at `time` (clamped into the motion range).
  void At(float time, float to_world[12], float to_object[12]) const;
};

// Reads the transform traversable of tagged `handle`, checking that it lies in readable device
// memory (`readable` says how many bytes there are) and that its motion options are valid
// (guide 5.10.1: at least two keys, timeBegin < timeEnd). INVALID_ARGUMENT otherwise.
absl::StatusOr<Optix7Transform> ReadTransform(uint64_t handle, size_t readable);

// c = a * b for 3x4 affine matrices (b applies first).
void Compose(const float a[12], const float b[12], float c[12]);
// The inverse of an affine 3x4 matrix, in double precision; zeros for a singular one.
void InvertAffine(const float m[12], float out[12]);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_OPTIX7_TRANSFORMS_H_
