// Programs for the multi-device semantics tests (docs/devices.md "Buffers across devices"):
// each reads and writes buffers by launch index, so that a test can tell which writes reached the
// host and which values every device saw, whichever device ran which tile.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(unsigned int, index1, rtLaunchIndex, );
rtDeclareVariable(uint2, index2, rtLaunchIndex, );
rtDeclareVariable(uint2, dim2, rtLaunchDim, );
rtDeclareVariable(uint3, index3, rtLaunchIndex, );

// A value that changes from launch to launch, so that stale data cannot pass for new data.
rtDeclareVariable(unsigned int, salt, , );

// ---- INPUT: a buffer of more than one 4 MiB chunk -----------------------------------------------
rtBuffer<float4, 1> big_input;
rtBuffer<float4, 1> seen;  // OUTPUT
rtDeclareVariable(unsigned int, probe_a, , );
rtDeclareVariable(unsigned int, probe_b, , );

RT_PROGRAM void read_input() {
  const size_t n = big_input.size();
  seen[index1] = make_float4(big_input[probe_a].x, big_input[probe_b].x, big_input[index1].y,
                             big_input[n - 1 - index1].z);
}

// ---- OUTPUT: every index, scatter, and half of the elements ------------------------------------
rtBuffer<float4, 2> image;  // OUTPUT
RT_PROGRAM void write_every_index() {
  image[index2] = make_float4(float(index2.x), float(index2.y), float(salt), 1.f);
}

rtBuffer<unsigned int, 1> scattered;  // OUTPUT
// Launch index i writes element (i * 7919) % n: a permutation when n is not a multiple of 7919,
// and the element lies in another tile for almost every i.
RT_PROGRAM void scatter_writes() {
  const unsigned long long n = scattered.size();
  scattered[(index1 * 7919ull) % n] = index1 * 3u + salt;
}
rtBuffer<unsigned int, 1> bins;  // OUTPUT
// Every launch index adds one to one of four shared elements.
RT_PROGRAM void count_into_bins() { atomicAdd(&bins[index1 % 4], 1u); }
RT_PROGRAM void write_even_elements() {
  if ((index1 & 1u) == 0) scattered[index1] = index1 + salt;
}

// ---- INPUT_OUTPUT ------------------------------------------------------------------------------
rtBuffer<unsigned int, 1> shared_io;  // INPUT_OUTPUT
rtBuffer<unsigned int, 1> neighbor;   // OUTPUT
rtDeclareVariable(unsigned int, stride, , );

RT_PROGRAM void io_write() { shared_io[index1] = index1 * 3u + salt; }
RT_PROGRAM void io_read_neighbor() {
  neighbor[index1] = shared_io[(index1 + stride) % shared_io.size()];
}
// Increments its own element and only reads another one (which its owner increments in the same
// launch; the value read is racy, as in OptiX, but the owner's write is not).
RT_PROGRAM void io_increment_and_peek() {
  shared_io[index1] += 1u;
  const unsigned int peeked = shared_io[(index1 + stride) % shared_io.size()];
  neighbor[index1] = peeked == 0xFFFFFFFFu ? 1u : 0u;
}

// Increments its element; launch index `fail_at` then fails the launch (a code below
// RT_EXCEPTION_USER is an error, not an exception).
rtDeclareVariable(unsigned int, fail_at, , );
RT_PROGRAM void io_increment_or_fail() {
  shared_io[index1] += 1u;
  if (index1 == fail_at) rtThrow(0x10);
}

// Adds one to its element of an OUTPUT buffer: what a device's copy held before shows.
rtBuffer<unsigned int, 1> out_counts;  // OUTPUT
RT_PROGRAM void output_increment() { out_counts[index1] += 1u; }

// ---- GPU_LOCAL ---------------------------------------------------------------------------------
rtBuffer<int, 2> local_acc;   // INPUT_OUTPUT | GPU_LOCAL
rtBuffer<int, 2> local_copy;  // OUTPUT
RT_PROGRAM void accumulate_local() {
  local_acc[index2] += 1;
  local_copy[index2] = local_acc[index2];
}

// ---- Variables, programs and the node graph as deltas ------------------------------------------
struct Payload {
  float3 color;
  float t;
};

rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(float, t_hit, rtIntersectionDistance, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(float, scale, , );
rtDeclareVariable(float3, color, , );       // material
rtDeclareVariable(float3, miss_color, , );  // context
rtDeclareVariable(float, slab_z, , );       // geometry
rtDeclareVariable(float, slab_max_x, , );   // geometry: rays at x >= slab_max_x miss

rtBuffer<float4, 2> frame;  // OUTPUT

RT_PROGRAM void ray_gen_scaled() {
  frame[index2] = make_float4(scale * float(index2.x), scale * float(index2.y), 0.f, 0.f);
}
RT_PROGRAM void ray_gen_trace() {
  Payload p;
  p.color = make_float3(0.f);
  p.t = 0.f;
  const float3 origin = make_float3(float(index2.x), float(index2.y), -10.f);
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 0, 1e-3f, RT_DEFAULT_MAX), p);
  frame[index2] = make_float4(p.color, p.t);
}

RT_PROGRAM void slab_bounds(int, float box[6]) {
  box[0] = box[1] = box[2] = -1000.f;
  box[3] = box[4] = box[5] = 1000.f;
}
RT_PROGRAM void slab_intersect(int) {
  if (ray.direction.z == 0.f) return;
  const float t = (slab_z - ray.origin.z) / ray.direction.z;
  if ((ray.origin + t * ray.direction).x >= slab_max_x) return;
  if (rtPotentialIntersection(t)) rtReportIntersection(0);
}
RT_PROGRAM void shade_color() {
  payload.color = color;
  payload.t = t_hit;
}
RT_PROGRAM void shade_inverted() {
  payload.color = make_float3(1.f) - color;
  payload.t = t_hit;
}
RT_PROGRAM void miss_with_color() {
  payload.color = miss_color;
  payload.t = -1.f;
}

// ---- rtPrintf and exceptions -------------------------------------------------------------------
rtBuffer<uint4, 2> exception_log;  // OUTPUT

RT_PROGRAM void print_indices() {
  rtPrintf("[%u,%u] first\n", index2.x, index2.y);
  rtPrintf("[%u,%u] second\n", index2.x, index2.y);
}

// One print of 70 MB (a width formats it from a short string): more than a message may carry.
RT_PROGRAM void print_huge() {
  if (index2.x == 0 && index2.y == 0) rtPrintf("%70000000d\n", 7);
  rtPrintf("[%u,%u]\n", index2.x, index2.y);
}

// Bytes that are not UTF-8 (Latin-1 text, binary): printed as they are.
RT_PROGRAM void print_latin1() { rtPrintf("caf\xe9 \xff %u\n", index2.x); }

// Prints, then every third launch index throws (as throw_some): reports and prints interleave.
RT_PROGRAM void print_then_throw_some() {
  rtPrintf("[%u,%u]\n", index2.x, index2.y);
  const unsigned int linear = index2.y * dim2.x + index2.x;
  if (linear % 3u == 0) rtThrow(RT_EXCEPTION_USER + linear % 16u);
}

// Every third launch index (row-major) throws a user code that depends on it.
RT_PROGRAM void throw_some() {
  const unsigned int linear = index2.y * dim2.x + index2.x;
  if (linear % 3u == 0) rtThrow(RT_EXCEPTION_USER + linear % 16u);
  exception_log[index2] = make_uint4(0u, index2.x, index2.y, 2u);
}
RT_PROGRAM void log_and_print_exception() {
  const unsigned int code = rtGetExceptionCode();
  exception_log[index2] = make_uint4(code, index2.x, index2.y, 1u);
  rtPrintf("exception 0x%X at [%u,%u]\n", code, index2.x, index2.y);
  rtPrintExceptionDetails();
}

// ---- Determinism: floating-point work that depends only on inputs and the launch index ---------
rtBuffer<float4, 1> spheres;  // INPUT: center, radius
rtBuffer<float4, 1> det1;     // OUTPUT
rtBuffer<float4, 2> det2;     // OUTPUT
rtBuffer<float4, 3> det3;     // OUTPUT
rtBuffer<float4, 2> det_acc;  // INPUT_OUTPUT: sums det2 over launches

rtDeclareVariable(float3, normal, attribute normal, );

RT_PROGRAM void sphere_bounds(int prim, float box[6]) {
  const float4 s = spheres[prim];
  box[0] = s.x - s.w;
  box[1] = s.y - s.w;
  box[2] = s.z - s.w;
  box[3] = s.x + s.w;
  box[4] = s.y + s.w;
  box[5] = s.z + s.w;
}
RT_PROGRAM void sphere_intersect(int prim) {
  const float4 s = spheres[prim];
  const float3 o = ray.origin - make_float3(s);
  const float a = dot(ray.direction, ray.direction);
  const float b = dot(o, ray.direction);
  const float disc = b * b - a * (dot(o, o) - s.w * s.w);
  if (disc <= 0.f) return;
  const float root = sqrtf(disc);
  const float t0 = (-b - root) / a;
  if (rtPotentialIntersection(t0)) {
    normal = (o + t0 * ray.direction) / s.w;
    if (rtReportIntersection(0)) return;
  }
  const float t1 = (-b + root) / a;
  if (rtPotentialIntersection(t1)) {
    normal = (o + t1 * ray.direction) / s.w;
    rtReportIntersection(0);
  }
}
// Closest hit: shading from the normal, plus a reflected ray (two levels at most).
RT_PROGRAM void shade_reflect() {
  const float3 n = normalize(normal);
  const float3 hit = ray.origin + t_hit * ray.direction;
  float3 c = (n * 0.5f + 0.5f) * expf(-0.07f * t_hit);
  if (payload.t == 0.f) {
    Payload bounce;
    bounce.color = make_float3(0.f);
    bounce.t = 1.f;
    const float3 d = ray.direction - 2.f * dot(ray.direction, n) * n;
    rtTrace(top_object, make_Ray(hit, normalize(d), 0, 1e-3f, RT_DEFAULT_MAX), bounce);
    c += 0.3f * bounce.color;
  }
  payload.color = c;
  payload.t = t_hit;
}
RT_PROGRAM void miss_sky() {
  payload.color = make_float3(0.2f, 0.3f, 0.5f) * (1.f + sinf(3.f * ray.direction.y));
}

static float4 Render(float u, float v, float w) {
  const float3 dir = normalize(make_float3(u * 2.f - 1.f, v * 2.f - 1.f, 1.4f + 0.2f * w));
  Payload p;
  p.color = make_float3(0.f);
  p.t = 0.f;
  rtTrace(top_object, make_Ray(make_float3(0.f, 0.f, -1.f), dir, 0, 1e-3f, RT_DEFAULT_MAX), p);
  const float wobble = sinf(17.f * u + 3.f * w) * cosf(11.f * v) + logf(1.f + u * v);
  return make_float4(p.color, p.t + 0.01f * wobble);
}

RT_PROGRAM void det_1d() {
  const float n = float(det1.size());
  det1[index1] = Render((float(index1) + 0.5f) / n, fmodf(float(index1) * 0.618034f, 1.f), 0.f);
}
RT_PROGRAM void det_2d() {
  const float2 d = make_float2(det2.size());
  const float4 c = Render((float(index2.x) + 0.5f) / d.x, (float(index2.y) + 0.5f) / d.y, 0.f);
  det2[index2] = c;
  det_acc[index2] = det_acc[index2] * 0.5f + c;
}
RT_PROGRAM void det_3d() {
  const float3 d = make_float3(det3.size());
  det3[index3] =
      Render((float(index3.x) + 0.5f) / d.x, (float(index3.y) + 0.5f) / d.y, float(index3.z) / d.z);
}

// ---- Device pointers (rtBufferGetDevicePointer / rtBufferSetDevicePointer) and race checking --
rtBuffer<unsigned int, 1> from_pointer;  // INPUT, or INPUT_OUTPUT | GPU_LOCAL
rtBuffer<unsigned int, 1> copied;        // OUTPUT
RT_PROGRAM void copy_from_pointer() { copied[index1] = from_pointer[index1]; }

rtBuffer<unsigned int, 1> contested;  // OUTPUT
// Every launch index writes element 0 (a race between devices) and its own element (none). The
// salt makes every launch's values new: the race check takes an element that still holds its value
// from before the launch for one the device only read.
RT_PROGRAM void race_on_first() {
  contested[0] = index1 + 1u + 1000u * salt;
  if (index1 != 0) contested[index1] = index1;
}

// ---- Probes: races on a 2D buffer, writes of one value by every device -----------------------
rtBuffer<unsigned int, 2> contested2;  // OUTPUT
// Every launch index writes element (3, 2) with a value of its own (a race between devices) and
// its own element (none).
RT_PROGRAM void race_on_element_3_2() {
  const unsigned int linear = index2.y * dim2.x + index2.x;
  if (index2.x != 3 || index2.y != 2) contested2[index2] = linear;
  contested2[make_uint2(3, 2)] = linear + 1u + 1000u * salt;
}
// Every launch index writes the same value to element 0: no race.
RT_PROGRAM void same_on_first() {
  contested[0] = salt;
  if (index1 != 0) contested[index1] = index1;
}

// Adds one to its element of from_pointer (GPU_LOCAL: each device's copy diverges from the
// host's) and copies the result.
RT_PROGRAM void bump_and_copy() {
  from_pointer[index1] += 1u;
  copied[index1] = from_pointer[index1];
}
