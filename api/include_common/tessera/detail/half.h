/* IEEE binary16 to float, exactly (every half is a float): half texels (RT_FORMAT_HALF*) and
 * OptiX 7's half vertex formats. Depends on nothing else of Tessera, so that both the program-side
 * headers and the host's OptiX 7 layer include it. */
#ifndef TESSERA_DETAIL_HALF_H_
#define TESSERA_DETAIL_HALF_H_

#include <cstdint>
#include <cstring>

namespace tessera::detail {

inline float HalfBitsToFloat(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  std::uint32_t bits;
  if (exponent == 0x1f) {
    bits = sign | 0x7f800000u | (mantissa << 13);  // inf, NaN
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else {
    // Zero and subnormals: mantissa * 2^-24, exact in float.
    const float magnitude = static_cast<float>(mantissa) * 5.9604644775390625e-8f;
    return sign != 0 ? -magnitude : magnitude;
  }
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

}  // namespace tessera::detail

#endif  // TESSERA_DETAIL_HALF_H_
