/* Tessera's speed/accuracy settings, shared by the OptiX 3 (tesseraContextSetAccuracy) and
 * OptiX 7 (tesseraOptixDeviceContextSetAccuracy) layers. Each is off by default, so that default
 * results stay bit-identical across machines and device sets; docs/accuracy.md gives each one's
 * measured cost and effect. The environment variable TESSERA_ACCURACY ("robust,watertight,offset,
 * fast_math,compact", or "all") sets a context's initial flags, so an unmodified application can
 * ask for them. C99-clean. */
#ifndef TESSERA_ACCURACY_H_
#define TESSERA_ACCURACY_H_

/* Embree's robust traversal (RTC_SCENE_FLAG_ROBUST) for every acceleration: conservative box
 * tests, so that rays through shared vertices and edges find one of the triangles far more
 * often. About 3-14% more traversal time. */
#define TESSERA_ACCURACY_ROBUST 0x1u
/* A watertight ray/triangle test (Woop, Benthin and Wald 2013, edge functions recomputed in
 * double precision where they are 0) on robust traversal: no ray passes between the triangles of
 * a closed mesh, through a vertex, an edge or a face, at any offset or scale. Implies ROBUST. */
#define TESSERA_ACCURACY_WATERTIGHT 0x2u
/* Rays a closest-hit program traces from its hit point start past the hit's floating-point error
 * bound, on the side they leave towards (pbrt-v4's error bounds, carried through transforms), with
 * tmin 0: no self-intersection and no scene_epsilon to tune. Applies to triangle hits. */
#define TESSERA_ACCURACY_OFFSET_RAYS 0x4u
/* Program modules the context compiles from source get fast math (NaN and infinity checks kept)
 * and tracing threads flush denormals to zero (FTZ/DAZ). */
#define TESSERA_ACCURACY_FAST_MATH 0x8u
/* Compact acceleration structures (RTC_SCENE_FLAG_COMPACT): less memory, slower traversal. */
#define TESSERA_ACCURACY_COMPACT 0x10u
/* Every flag above. */
#define TESSERA_ACCURACY_ALL 0x1Fu

#endif /* TESSERA_ACCURACY_H_ */
