// A callable program of another module than the visit program calling it (selector_test.cc): it
// sees the visit program's ray, payload and distance, and picks the child itself.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

struct Payload {
  float value, t, visits, seen;
};

rtDeclareVariable(optix::Ray, r, rtCurrentRay, );
rtDeclareVariable(Payload, p, rtPayload, );
rtDeclareVariable(float, d, rtIntersectionDistance, );

RT_CALLABLE_PROGRAM void pick_by_direction() {
  p.visits += 10.f;
  rtIntersectChild(static_cast<unsigned>(r.direction.y < 0));
  p.seen = d;
}
