// Programs that each make one device call, for the "which calls where" table test. Every call
// comes in four forms: plain (ray generation, exception, closest hit, any hit, miss),
// intersection (int), bounding box (int, float[6]) and visit (the call, then the selector's only
// child).
#include <optix_world.h>

using namespace optix;

struct Payload {
  float value;
};

rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(Payload, payload, rtPayload, );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );

static void DoTransform() {
  float3 p = rtTransformPoint(RT_OBJECT_TO_WORLD, make_float3(1.f, 2.f, 3.f));
  (void)p;
}
static void DoTrace() {
  Payload p;
  p.value = 0.f;
  rtTrace(
      top_object,
      make_Ray(make_float3(0.f, 0.f, -10.f), make_float3(0.f, 0.f, 1.f), 0, 0.f, RT_DEFAULT_MAX),
      p);
}
static void DoThrow() { rtThrow(RT_EXCEPTION_USER); }
static void DoPrint() { rtPrintf("print\n"); }
static void DoTerminate() { rtTerminateRay(); }
static void DoIgnore() { rtIgnoreIntersection(); }
static void DoPotential() { rtPotentialIntersection(1.f); }
static void DoReport() { rtReportIntersection(0); }
static void DoIntersectChild() { rtIntersectChild(0); }

// The unit box every intersection program below reports at t = 1.
static void UnitBounds(float b[6]) {
  b[0] = b[1] = b[2] = -1.f;
  b[3] = b[4] = b[5] = 1.f;
}
static void ReportUnit() {
  if (rtPotentialIntersection(1.f)) rtReportIntersection(0);
}

#define CALL_PROGRAMS(name, call)                  \
  RT_PROGRAM void name##_plain() { call(); }       \
  RT_PROGRAM void name##_intersect(int) {          \
    call();                                        \
    ReportUnit();                                  \
  }                                                \
  RT_PROGRAM void name##_bounds(int, float b[6]) { \
    UnitBounds(b);                                 \
    call();                                        \
  }                                                \
  RT_PROGRAM void name##_visit() {                 \
    call();                                        \
    rtIntersectChild(0);                           \
  }

CALL_PROGRAMS(transform, DoTransform)
CALL_PROGRAMS(trace, DoTrace)
CALL_PROGRAMS(throw, DoThrow)
CALL_PROGRAMS(print, DoPrint)
CALL_PROGRAMS(terminate, DoTerminate)
CALL_PROGRAMS(ignore, DoIgnore)
CALL_PROGRAMS(potential, DoPotential)
CALL_PROGRAMS(report, DoReport)
CALL_PROGRAMS(intersect_child, DoIntersectChild)

// Fillers for the positions a test does not probe.
RT_PROGRAM void nothing() {}
RT_PROGRAM void visit_plain() { rtIntersectChild(0); }
RT_PROGRAM void plain_intersect(int) { ReportUnit(); }
RT_PROGRAM void plain_bounds(int, float b[6]) { UnitBounds(b); }
RT_PROGRAM void camera() { DoTrace(); }
RT_PROGRAM void throw_camera() { rtThrow(RT_EXCEPTION_USER); }
