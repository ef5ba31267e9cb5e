/* Accuracy device functions of OptiX 7 programs (Tessera's, tessera/accuracy.h,
 * docs/optix7_engine.md "Speed and accuracy"). Included by optix_device.h. */
#ifndef TESSERA_OPTIX7_ACCURACY_H_
#define TESSERA_OPTIX7_ACCURACY_H_

/* The origin, in world space, for a ray that leaves the current hit in world direction
 * `direction`: the hit point moved past its floating-point error bound to the side `direction`
 * points to, so that the ray cannot hit the same surface there again and needs no scene epsilon
 * (trace it with tmin 0). Triangles: the point from the vertices and barycentrics, its bound
 * carried through the hit's transforms, moved along the normal (pbrt-v4's error bounds). Other
 * primitives: the point origin + t * direction of the ray that hit, moved along `direction` by
 * its bound. Closest-hit and any-hit programs. */
static __forceinline__ __device__ float3 tesseraOptixGetSpawnPoint(float3 direction) {
  const float d[3] = {direction.x, direction.y, direction.z};
  float o[3];
  tessera_optix7::rt()->spawn_point(d, o);
  return make_float3(o[0], o[1], o[2]);
}

#endif /* TESSERA_OPTIX7_ACCURACY_H_ */
