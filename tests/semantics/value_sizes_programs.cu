// Programs of value_sizes_test.cc: payloads and attributes of sizes that are not the usual 4, 8,
// 12 or 16 bytes (1, 3, 6, 20, 128, 130, 132 and 260), a round trip each; a nested trace whose
// callee shares the caller's module, so the caller's values are saved and restored; a program
// that traces its own payload variable; and 512 bytes of attributes in all.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

template <int N>
struct Bytes {
  unsigned char b[N];
};

struct Twenty {
  int v[5];
};

// With the attributes around it, 512 bytes only without alignment padding before a_twenty.
struct Big476 {
  unsigned char b[476];
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
// 0 where every check of the launch index passed, else one bit per failed check.
rtBuffer<unsigned int, 2> failures;

rtDeclareVariable(unsigned char, a_byte, attribute a_byte, );
rtDeclareVariable(Big476, a_big, attribute a_big, );
rtDeclareVariable(uchar3, a_uchar3, attribute a_uchar3, );
rtDeclareVariable(float3, a_float3, attribute a_float3, );
rtDeclareVariable(Twenty, a_twenty, attribute a_twenty, );

rtDeclareVariable(Bytes<1>, payload_1, rtPayload, );
rtDeclareVariable(Bytes<3>, payload_3, rtPayload, );
rtDeclareVariable(Bytes<6>, payload_6, rtPayload, );
rtDeclareVariable(Bytes<20>, payload_20, rtPayload, );
rtDeclareVariable(Bytes<128>, payload_128, rtPayload, );
rtDeclareVariable(Bytes<130>, payload_130, rtPayload, );
rtDeclareVariable(Bytes<132>, payload_132, rtPayload, );
rtDeclareVariable(Bytes<260>, payload_260, rtPayload, );

// The seed a ray carries in its origin's x: every value below is a function of it.
static __device__ unsigned Seed() { return static_cast<unsigned>(ray.origin.x); }

static __device__ bool AttributesMatch(unsigned k) {
  bool ok = a_byte == static_cast<unsigned char>(k * 7 + 1);
  ok &= a_uchar3.x == static_cast<unsigned char>(k) &&
        a_uchar3.y == static_cast<unsigned char>(k + 1) &&
        a_uchar3.z == static_cast<unsigned char>(k + 2);
  ok &= a_float3.x == static_cast<float>(k) && a_float3.y == 0.5f * k && a_float3.z == -1.f * k;
  for (int i = 0; i < 5; ++i) ok &= a_twenty.v[i] == static_cast<int>(k * 10 + i);
  for (int i = 0; i < 476; ++i) ok &= a_big.b[i] == static_cast<unsigned char>(k + i);
  return ok;
}

// Primitive 0 is hit at t = 1 by every ray; attributes come from the ray's seed.
RT_PROGRAM void intersect(int) {
  if (rtPotentialIntersection(1.f)) {
    const unsigned k = Seed();
    a_byte = static_cast<unsigned char>(k * 7 + 1);
    a_uchar3 = make_uchar3(k, k + 1, k + 2);
    a_float3 = make_float3(k, 0.5f * k, -1.f * k);
    for (int i = 0; i < 5; ++i) a_twenty.v[i] = static_cast<int>(k * 10 + i);
    for (int i = 0; i < 476; ++i) a_big.b[i] = static_cast<unsigned char>(k + i);
    rtReportIntersection(0);
  }
}

RT_PROGRAM void bounds(int, float result[6]) {
  result[0] = result[1] = result[2] = -1e6f;
  result[3] = result[4] = result[5] = 1e6f;
}

// What a closest-hit program makes of byte i of a payload: the caller checks it. A failed check
// of the attributes or the distance shows as an extra 1.
static __device__ unsigned char Transformed(unsigned char b, int i, bool ok) {
  return static_cast<unsigned char>(b * 3 + i + (ok ? 0 : 1));
}

template <int N>
static __device__ void Shade(Bytes<N>& p) {
  const bool ok = AttributesMatch(Seed()) && hit_t == 1.f;
  for (int i = 0; i < N; ++i) p.b[i] = Transformed(p.b[i], i, ok);
}

template <int N>
static __device__ Bytes<N> Filled(unsigned k) {
  Bytes<N> p;
  for (int i = 0; i < N; ++i) p.b[i] = static_cast<unsigned char>(k + 5 * i);
  return p;
}

template <int N>
static __device__ bool CameBack(const Bytes<N>& p, unsigned k) {
  bool ok = true;
  for (int i = 0; i < N; ++i) {
    ok &= p.b[i] == Transformed(static_cast<unsigned char>(k + 5 * i), i, true);
  }
  return ok;
}

// Ray type t carries the t-th payload size.
template <int N>
static __device__ bool TraceSize(unsigned ray_type, unsigned k) {
  Bytes<N> p = Filled<N>(k);
  // The primitive is hit at t = 1 whatever the ray.
  Ray r = make_Ray(make_float3(static_cast<float>(k), 0.f, 0.f), make_float3(0.f, 0.f, 1.f),
                   ray_type, 0.f, RT_DEFAULT_MAX);
  rtTrace(top_object, r, p);
  return CameBack(p, k);
}

RT_PROGRAM void ch_1() { Shade(payload_1); }
RT_PROGRAM void ch_3() { Shade(payload_3); }
RT_PROGRAM void ch_6() { Shade(payload_6); }
RT_PROGRAM void ch_128() { Shade(payload_128); }
RT_PROGRAM void ch_130() { Shade(payload_130); }
RT_PROGRAM void ch_132() { Shade(payload_132); }
RT_PROGRAM void ch_260() { Shade(payload_260); }

// Traces a 3-byte payload (ch_3, same module) before shading its own: its payload, attributes,
// ray and distance must be back as they were. A failed nested check shows as Shade's extra 1.
RT_PROGRAM void ch_20_nested() {
  const unsigned k = Seed();
  const bool nested_ok = TraceSize<3>(1, k + 1);
  const bool ray_kept = ray.ray_type == 3 && Seed() == k;
  const bool ok = nested_ok && ray_kept && AttributesMatch(k) && hit_t == 1.f;
  for (int i = 0; i < 20; ++i) payload_20.b[i] = Transformed(payload_20.b[i], i, ok);
}

// Traces its own payload variable (ray type 9, which misses): the nested miss program, of this
// module, changes it, and the change must survive restoring this program's values afterwards.
RT_PROGRAM void ch_self() {
  payload_20.b[0] = 100;
  const Ray r = make_Ray(ray.origin, ray.direction, 9, 0.f, 0.5f);  // the primitive is at t = 1
  rtTrace(top_object, r, payload_20);
  payload_20.b[2] = payload_20.b[1];
}
RT_PROGRAM void miss_self() {
  payload_20.b[1] = 42;
  payload_20.b[3] = 7;
}

// Ray type 10 traces 8 bytes, a size no payload variable has: the variable the program changed
// (20 bytes) brings them back.
RT_PROGRAM void ch_other_size() { Shade(payload_20); }

static __device__ bool SelfPayloadKept(unsigned k) {
  Bytes<20> p = Filled<20>(k);
  rtTrace(top_object,
          make_Ray(make_float3(static_cast<float>(k), 0.f, 0.f), make_float3(0.f, 0.f, 1.f), 8, 0.f,
                   RT_DEFAULT_MAX),
          p);
  bool ok = p.b[0] == 100 && p.b[1] == 42 && p.b[2] == 42 && p.b[3] == 7;
  for (int i = 4; i < 20; ++i) ok &= p.b[i] == static_cast<unsigned char>(k + 5 * i);
  return ok;
}

// Traces 24 bytes inside its own payload variable, from its ninth byte (ray type 12, which
// misses): the nested miss program, of this module, receives them at the start of payload_128
// and changes their first and last bytes; they must come back to where they lie in this
// program's variable (copies between overlapping bytes, in both directions).
RT_PROGRAM void ch_member() {
  Bytes<24>& part = *reinterpret_cast<Bytes<24>*>(&payload_128.b[8]);
  const Ray r = make_Ray(ray.origin, ray.direction, 12, 0.f, 0.5f);  // the primitive is at t = 1
  rtTrace(top_object, r, part);
}
RT_PROGRAM void miss_member() {
  payload_128.b[0] = static_cast<unsigned char>(payload_128.b[0] + 1);
  payload_128.b[23] = 99;
}

static __device__ bool MemberPayloadKept(unsigned k) {
  const Bytes<128> sent = Filled<128>(k);
  Bytes<128> p = sent;
  rtTrace(top_object,
          make_Ray(make_float3(static_cast<float>(k), 0.f, 0.f), make_float3(0.f, 0.f, 1.f), 11,
                   0.f, RT_DEFAULT_MAX),
          p);
  bool ok = p.b[8] == static_cast<unsigned char>(sent.b[8] + 1) && p.b[31] == 99;
  for (int i = 0; i < 128; ++i) ok &= i == 8 || i == 31 || p.b[i] == sent.b[i];
  return ok;
}

RT_PROGRAM void check_sizes() {
  const unsigned k = launch_index.x + 17 * launch_index.y;
  unsigned failed = 0;
  failed |= TraceSize<1>(0, k) ? 0u : 1u;
  failed |= TraceSize<3>(1, k) ? 0u : 2u;
  failed |= TraceSize<6>(2, k) ? 0u : 4u;
  failed |= TraceSize<20>(3, k) ? 0u : 8u;
  failed |= TraceSize<128>(4, k) ? 0u : 16u;
  failed |= TraceSize<130>(5, k) ? 0u : 32u;
  failed |= TraceSize<132>(6, k) ? 0u : 64u;
  failed |= TraceSize<260>(7, k) ? 0u : 128u;
  failed |= SelfPayloadKept(k) ? 0u : 256u;
  failed |= TraceSize<8>(10, k) ? 0u : 512u;
  failed |= MemberPayloadKept(k) ? 0u : 1024u;
  failures[launch_index] = failed;
}
