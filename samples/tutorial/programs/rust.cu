// Tutorial step 8: the box as rusty metal, a port of Larry Gritz's BMRT "rusty metal" shader as
// the SDK tutorial does it, with its 3D noise texture (noise.h).
#include "noise.h"
#include "shading.h"

rtDeclareVariable(float3, reflectivity_n, , );

rtDeclareVariable(float, metalKa, , ) = 1;
rtDeclareVariable(float, metalKs, , ) = 1;
rtDeclareVariable(float, metalroughness, , ) = .1f;
rtDeclareVariable(float, rustKa, , ) = 1;
rtDeclareVariable(float, rustKd, , ) = 1;
rtDeclareVariable(float3, rustcolor, , ) = {.437f, .084f, 0};
rtDeclareVariable(float3, metalcolor, , ) = {.7f, .7f, .7f};
rtDeclareVariable(float, txtscale, , ) = .02f;
rtDeclareVariable(float, rusty, , ) = 0.2f;
rtDeclareVariable(float, rustbump, , ) = 0.85f;
#define MAXOCTAVES 6

RT_PROGRAM void box_closest_hit_radiance() {
  float3 ffnormal = ffnormal_world();
  float3 hit_point = ray.origin + t_hit * ray.direction;

  // Sum several octaves of abs(snoise), i.e. turbulence.
  float3 PP = txtscale * hit_point;
  float a = 1;
  float sum = 0;
  for (int i = 0; i < MAXOCTAVES; i++) {
    sum += a * fabsf(snoise(PP));
    PP *= 2;
    a *= 0.5f;
  }

  // Scale the rust appropriately, modulate it by another noise computation, then sharpen it by
  // squaring its value.
  float rustiness = step(1 - rusty, clamp(sum, 0.0f, 1.0f));
  rustiness *= clamp(fabsf(snoise(PP)), 0.0f, .08f) / 0.08f;
  rustiness *= rustiness;

  // If it's rusty, also add a high frequency bumpiness to the normal.
  float3 Nrust = ffnormal;
  if (rustiness > 0) {
    Nrust = normalize(ffnormal + rustbump * snoise(PP));
  }

  // Shade the rust like matte and the metal like plastic with a sharp highlight.
  float3 color = mix(metalcolor * metalKa, rustcolor * rustKa, rustiness) * ambient_light_color;
  for (unsigned int i = 0; i < lights.size(); ++i) {
    BasicLight light = lights[i];
    float3 L = normalize(light.pos - hit_point);
    float nmDl = dot(ffnormal, L);
    float nrDl = dot(Nrust, L);

    if (nmDl > 0.0f || nrDl > 0.0f) {
      float3 attenuation = light_attenuation(hit_point, light, L);
      if (fmaxf(attenuation) > 0.0f) {
        float3 Lc = light.color * attenuation;
        nrDl = fmaxf(nrDl * rustiness, 0.0f);
        color += rustKd * rustcolor * nrDl * Lc;

        float r = nmDl * (1.0f - rustiness);
        if (nmDl > 0.0f) {
          float3 H = normalize(L - ray.direction);
          float nmDh = dot(ffnormal, H);
          if (nmDh > 0) color += r * metalKs * Lc * powf(nmDh, 1.f / metalroughness);
        }
      }
    }
  }

  float3 r = schlick(-dot(ffnormal, ray.direction), reflectivity_n * (1 - rustiness));
  color += reflect_ray(hit_point, ffnormal, r);

  prd_radiance.result = color;
}
