// Affine transforms of scene nodes, in double precision: a deep node hierarchy multiplies many
// matrices per frame, and the renderer only receives the floats of the product.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_TRANSFORM_H_
#define TESSERA_TOOLS_TESSERA_SCENE_TRANSFORM_H_

#include <array>

#include "scene.h"

namespace tessera::render {

// 3x4 row-major, the layout of Affine.
using AffineD = std::array<double, 12>;

// A node's translation, rotation (unit quaternion x, y, z, w, as glTF stores it) and scale.
struct Trs {
  std::array<double, 3> translation{0.0, 0.0, 0.0};
  std::array<double, 4> rotation{0.0, 0.0, 0.0, 1.0};
  std::array<double, 3> scale{1.0, 1.0, 1.0};
};

AffineD IdentityAffine();
// a * b: b applied first.
AffineD Compose(const AffineD& a, const AffineD& b);
// T * R * S, as glTF composes a node's local transform. The rotation is normalized first (a
// zero quaternion gives no rotation), so that a file's rounding never skews the mesh.
AffineD TrsToAffine(const Trs& trs);
// A glTF node matrix: 16 numbers, column-major; its last row is assumed to be 0 0 0 1.
AffineD ColumnMajorToAffine(const double* m16);
Affine ToFloat(const AffineD& m);
std::array<double, 3> TransformPoint(const AffineD& m, const std::array<double, 3>& p);

// Unit quaternion, or identity for a zero one.
std::array<double, 4> NormalizeQuaternion(const std::array<double, 4>& q);
// Spherical interpolation along the shorter arc, normalized.
std::array<double, 4> Slerp(const std::array<double, 4>& a, const std::array<double, 4>& b,
                            double t);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_TRANSFORM_H_
