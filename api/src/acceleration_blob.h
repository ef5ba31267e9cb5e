// The bytes rtAccelerationGetData hands out and rtAccelerationSetData takes back: a versioned,
// self-describing, checksummed record of one acceleration's build (docs/acceleration_data.md).
#ifndef TESSERA_API_SRC_ACCELERATION_BLOB_H_
#define TESSERA_API_SRC_ACCELERATION_BLOB_H_

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::api {

// Raised when a format change makes older blobs unreadable; a blob of another version is refused.
inline constexpr uint32_t kAccelerationDataVersion = 1;

// What the structure was built over, without geometry data: enough to tell a blob made for
// another scene. For a GeometryGroup, one entry per GeometryInstance; for a Group, one per child.
inline constexpr uint32_t kGeometryInput = 1;   // a Geometry (bounding-box program)
inline constexpr uint32_t kTrianglesInput = 2;  // GeometryTriangles
struct BuildInput {
  // GeometryGroup children: kGeometryInput or kTrianglesInput; Group children: their RTobjecttype.
  uint32_t kind = 0;
  uint64_t primitive_count = 0;  // GeometryGroup children only
  std::string bounds_program;    // "'function' in module <sha-256>", GeometryGroup children
};

struct AccelerationBlob {
  std::string builder, traverser;
  std::map<std::string, std::string> properties;
  uint32_t node_kind = 0;  // RT_OBJECTTYPE_GEOMETRY_GROUP or RT_OBJECTTYPE_GROUP
  std::vector<BuildInput> inputs;
  // Per GeometryGroup child: 6 floats per primitive as the device fed them to Embree, or empty
  // where no bounding-box program ran (triangles) or they were too many to carry.
  std::vector<std::vector<float>> bounds;
};

// "tessera-embree3 x86_64-linux little-endian": the engine and machine kind whose floats and
// programs made the bounds. A blob from another is refused.
const std::string& AccelerationDataPlatform();

std::string EncodeAccelerationBlob(const AccelerationBlob& blob);

// RT_ERROR_INVALID_VALUE with a message saying what is wrong (truncated, corrupted, another
// format version or platform, malformed) for bytes that are not a blob this Tessera wrote.
absl::StatusOr<AccelerationBlob> DecodeAccelerationBlob(const void* data, size_t size);

// Empty when `saved` (a blob's) and `now` (the current graph's) agree, else what differs first.
std::string DescribeInputMismatch(const std::vector<BuildInput>& saved,
                                  const std::vector<BuildInput>& now);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_ACCELERATION_BLOB_H_
