// The next float above or below a value, by its bits (pbrt-v4's NextFloatUp/NextFloatDown): what
// std::nextafter towards an infinity gives, without libm's out-of-line call, on paths every ray
// takes (ray offsets, exclusive tmin).
#ifndef TESSERA_WORKER_CORE_FLOAT_STEPS_H_
#define TESSERA_WORKER_CORE_FLOAT_STEPS_H_

#include <cstdint>
#include <cstring>

namespace tessera::worker {

inline float NextFloatUp(float v) {
  if (!(v == v) || v == __builtin_inff()) return v;  // NaN and +inf stay
  if (v == 0.f) v = 0.f;                             // -0 steps up like +0
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  bits = v >= 0.f ? bits + 1 : bits - 1;
  std::memcpy(&v, &bits, sizeof(bits));
  return v;
}

inline float NextFloatDown(float v) {
  if (!(v == v) || v == -__builtin_inff()) return v;  // NaN and -inf stay
  if (v == 0.f) v = -0.f;                             // +0 steps down like -0
  uint32_t bits;
  std::memcpy(&bits, &v, sizeof(bits));
  bits = v > 0.f ? bits - 1 : bits + 1;
  std::memcpy(&v, &bits, sizeof(bits));
  return v;
}

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_FLOAT_STEPS_H_
