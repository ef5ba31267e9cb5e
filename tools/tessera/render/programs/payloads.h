// The payloads of the path tracer's rays (program side only).
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PAYLOADS_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PAYLOADS_H_

#include <optix.h>

#include "random.h"

// A path's state. The ray generation program traces one segment at a time; the closest-hit
// program adds what reaches the camera through this hit and sets the next segment, the miss
// program adds the background and ends the path. Iterating in ray generation (rather than
// recursing from closest hit) keeps the nesting two rtTrace calls deep whatever the path length.
struct RadiancePayload {
  float3 radiance;    // light reaching the camera along the path so far
  float3 throughput;  // the product of the path's BSDF weights: what light at the next hit counts
  float3 origin;      // the next segment, set by the closest-hit program
  float3 direction;
  Rng rng;
  float bsdf_pdf;     // solid-angle density of the direction that reached this hit (for MIS)
  int depth;          // bounces so far: 0 at the camera ray's hit
  int specular;       // that direction came from a delta lobe, which lights cannot sample
  int done;           // no next segment
  unsigned int rays;  // rays the closest-hit program traced (shadow rays), for the ray count
  int aov_only;       // entry `aovs`: fill the first-hit fields below and stop
  float3 albedo;      // first hit: base colour, world-space shading normal, distance
  float3 normal;
  float hit_distance;
};

// Shadow rays toward a light: the miss program says the light is visible. They are traced with
// RT_RAY_FLAG_TERMINATE_ON_FIRST_HIT and DISABLE_CLOSESTHIT, so any hit ends them at once.
struct ShadowPayload {
  int visible;
};

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PAYLOADS_H_
