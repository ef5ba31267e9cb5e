// What the path tracer's programs and `tessera render`'s host code share: ray types, the light
// records of the `lights` and `emissive_triangles` buffers (RT_FORMAT_USER), and the payloads.
//
// The programs (one module per .cu, as OptiX compiles one PTX file per .cu):
//   camera.cu    ray generation: `path_trace` (entry 0) adds samples to `accum_buffer`;
//                `aovs` (entry 1) writes the first-hit albedo, normal and depth
//   material.cu  closest hit of radiance rays: emission, next-event estimation, BSDF sampling
//   mesh.cu      attribute program of built-in triangles: normals, texture coordinates, tangents
//   miss.cu      miss programs: environment or background for radiance rays, "visible" for
//                shadow rays
#ifndef TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PATH_TRACER_H_
#define TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PATH_TRACER_H_

#include <optixu/optixu_vector_types.h>

namespace path_tracer {

enum RayType : unsigned int { kRadianceRay = 0, kShadowRay = 1, kRayTypeCount = 2 };
enum EntryPoint : unsigned int { kPathTraceEntry = 0, kAovEntry = 1, kEntryPointCount = 2 };

// A texture sampler id that names no texture: RT_TEXTURE_ID_NULL, which programs spell so.
enum : int { kNoTexture = 0 };

// Light types of PunctualLight::type (KHR_lights_punctual).
enum LightType : int { kPointLight = 0, kSpotLight = 1, kDirectionalLight = 2 };

// One element of the `lights` buffer: a light with no area, reached only by next-event
// estimation. `intensity` is colour times intensity: candela (W/sr here) for point and spot
// lights, lux (W/m^2) for directional ones.
struct PunctualLight {
  float3 position;   // world space; point and spot
  int type;          // LightType
  float3 direction;  // world space, unit, where the light shines; spot and directional
  float range;       // 0: unlimited
  float3 intensity;
  float spot_scale;  // the spot's cone: attenuation = saturate(cos * scale + offset)^2 (glTF)
  float spot_offset;
  float padding[3];
};

// One element of the `emissive_triangles` buffer: a world-space triangle of an emissive material,
// sampled for next-event estimation with probability proportional to area * luminance(emission)
// (the `emissive_cdf` buffer holds the running sums, normalized to end at 1).
struct EmissiveTriangle {
  float3 p0, e1, e2;     // vertex 0 and the edges to vertices 1 and 2
  float3 normal;         // unit, the side the triangle winds counter-clockwise on
  float3 emission;       // the material's emissive factor (linear RGB)
  int emissive_texture;  // a texture sampler id, or 0
  float2 uv0, uv1, uv2;  // texture coordinates of the vertices, for the emissive texture
  int double_sided;      // emits on both sides; else only on the normal's side
  float padding;
};

}  // namespace path_tracer

#endif  // TESSERA_TOOLS_TESSERA_RENDER_PROGRAMS_PATH_TRACER_H_
