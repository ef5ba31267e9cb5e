// 4x4 row-major float matrices for Transform nodes.
#ifndef TESSERA_API_SRC_MATRIX4_H_
#define TESSERA_API_SRC_MATRIX4_H_

#include <array>

namespace tessera::api {

using Matrix4 = std::array<float, 16>;

Matrix4 IdentityMatrix4();
Matrix4 Transpose(const Matrix4& m);
// False when `m` is singular (or not finite); `out` is then untouched.
bool Invert(const Matrix4& m, Matrix4* out);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_MATRIX4_H_
