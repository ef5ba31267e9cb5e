// Programs of callable_test.cc (OptiX 3.0 "Callable Programs"): rtCallableProgram variables
// called from ray generation, closest hit, intersection and exception paths; callable programs
// with variables of their own, semantic values shared with their caller, nested traces,
// recursion, rtThrow, and the guide's pickled pointer. callable_other_programs.cu holds callable
// programs of another module; callable_plain_programs.cu a caller that declares no semantic
// variables.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

struct Payload {
  float value;
  unsigned depth;
};

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(float, hit_t, rtIntersectionDistance, );
rtDeclareVariable(Payload, prd, rtPayload, );
rtDeclareVariable(float, a_value, attribute a_value, );
rtBuffer<float, 2> result;

// ---- Called from ray generation: the guide's example, its target set by the host ----------
rtCallableProgram(float, shade, (float, float));
rtDeclareVariable(float, scale, , );

RT_CALLABLE_PROGRAM float add(float a, float b) { return a + b; }
// `scale` as the callable program's scopes give it (its own, then the context).
RT_CALLABLE_PROGRAM float times(float a, float b) { return a * b * scale; }
RT_CALLABLE_PROGRAM float throws(float a, float) {
  rtThrow(RT_EXCEPTION_USER + 7);
  return a;
}

// The caller reads `scale` after the call, as its own scopes give it.
RT_PROGRAM void call_from_raygen() {
  const float v = shade(static_cast<float>(launch_index.x), static_cast<float>(launch_index.y));
  result[launch_index] = v + 1000.f * scale;
}

RT_PROGRAM void on_exception() { result[launch_index] = -static_cast<float>(rtGetExceptionCode()); }

// ---- Recursion --------------------------------------------------------------------------------
rtCallableProgram(unsigned, fact, (unsigned));
RT_CALLABLE_PROGRAM unsigned factorial(unsigned n) { return n <= 1 ? 1 : n * fact(n - 1); }
RT_CALLABLE_PROGRAM unsigned endless(unsigned n) { return fact(n + 1) + 1; }
RT_PROGRAM void call_factorial() {
  result[launch_index] = static_cast<float>(fact(launch_index.x + 1));
}

// ---- The guide's pickled pointer ------------------------------------------------------------
rtCallableProgram(void, pbr, (rtPickledLocalPointer));
RT_CALLABLE_PROGRAM void plus_one(rtPickledLocalPointer pointer) {
  int* p = rtUnpickleLocalPointer(pointer);
  *p += 1;
}
RT_PROGRAM void pickled() {
  int x = 42;
  rtPickledLocalPointer p = rtPickleLocalPointer(&x);
  pbr(p);
  result[launch_index] = static_cast<float>(x);
}

// ---- A scene: one primitive hit at t = 1, its attribute the ray's origin x -----------------
RT_PROGRAM void intersect(int) {
  if (rtPotentialIntersection(1.f)) {
    a_value = ray.origin.x;
    rtReportIntersection(0);
  }
}
// The same, the attribute written by a callable program.
rtCallableProgram(void, make_attributes, ());
RT_PROGRAM void intersect_via_callable(int) {
  if (rtPotentialIntersection(1.f)) {
    make_attributes();
    rtReportIntersection(0);
  }
}
RT_CALLABLE_PROGRAM void attributes_here() { a_value = ray.origin.x + 0.25f; }

RT_PROGRAM void bounds(int, float result[6]) {
  result[0] = result[1] = result[2] = -1e6f;
  result[3] = result[4] = result[5] = 1e6f;
}

// Rays start at x = launch index x (the attribute), pointing down +z.
RT_PROGRAM void trace_raygen() {
  Payload p = {0.f, 0u};
  const float3 origin = make_float3(static_cast<float>(launch_index.x), 0.f, -1.f);
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 0, 0.f, RT_DEFAULT_MAX), p);
  result[launch_index] = p.value;
}

// ---- Called from closest hit ------------------------------------------------------------------
// `tint` and `level` are looked up through the closest hit's scopes: geometry instance, then
// material, then context.
rtCallableProgram(float, tint, (float));
rtDeclareVariable(float, level, , );
RT_CALLABLE_PROGRAM float tint_up(float x) { return x + level; }
RT_CALLABLE_PROGRAM float tint_down(float x) { return x - level; }
RT_PROGRAM void ch_tint() { prd.value = tint(hit_t); }

// The callable program reads the closest hit's distance, attribute and payload, writes the
// payload, and traces once more from the first hit (depth 0).
rtCallableProgram(void, shade_hit, ());
RT_CALLABLE_PROGRAM void shade_here() {
  prd.value = hit_t * 100.f + a_value;
  if (prd.depth == 0) {
    Payload q = {0.f, 1u};
    rtTrace(top_object, make_Ray(ray.origin, ray.direction, 0, 0.f, RT_DEFAULT_MAX), q);
    prd.value += 1000.f * q.value;
  }
}
RT_PROGRAM void ch_shade() { shade_hit(); }
RT_PROGRAM void ch_attribute() { prd.value = a_value; }

// Its own values after a callee of another module traced from x + 0.5: its attribute is still x.
RT_PROGRAM void ch_values_after() {
  if (prd.depth != 0) {
    prd.value = a_value;
    return;
  }
  shade_hit();
  if (a_value == static_cast<float>(launch_index.x) && hit_t == 1.f) prd.value += 1000.f;
}

// ---- Any hit ----------------------------------------------------------------------------------
// Primitive i is hit at t = i + 1.
RT_PROGRAM void intersect_indexed(int primitive) {
  if (rtPotentialIntersection(1.f + static_cast<float>(primitive))) {
    a_value = ray.origin.x;
    rtReportIntersection(0);
  }
}
rtCallableProgram(void, on_candidate, ());
RT_PROGRAM void ah_calls() { on_candidate(); }
RT_PROGRAM void ch_add() { prd.value += 1000.f * hit_t; }

// ---- Where recursion runs out ----------------------------------------------------------------
// About a kilobyte of native stack per level; launch index x recurses 200 x levels.
rtCallableProgram(unsigned, fat, (unsigned));
RT_CALLABLE_PROGRAM unsigned fat_levels(unsigned n) {
  volatile unsigned char pad[1024];
  pad[n % 1024] = 1;
  return n == 0 ? 0u : fat(n - 1) + pad[n % 1024];
}
RT_PROGRAM void call_fat() {
  result[launch_index] = static_cast<float>(fat(200u * launch_index.x));
}

// ---- A chain of callable programs, each set on the next link's own scope ---------------------
rtCallableProgram(float, next_link, (float));
RT_CALLABLE_PROGRAM float chain_link(float x) { return next_link(x) + 1.f; }
RT_CALLABLE_PROGRAM float chain_end(float x) { return x; }
RT_PROGRAM void call_chain() { result[launch_index] = next_link(0.f); }
