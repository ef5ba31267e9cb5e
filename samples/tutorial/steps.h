// Which programs each tutorial step uses (the OptiX SDK tutorial's numbering).
#ifndef TESSERA_SAMPLES_TUTORIAL_STEPS_H_
#define TESSERA_SAMPLES_TUTORIAL_STEPS_H_

namespace tessera::tutorial {

// A program in a module: `module` is the module's file stem in the module directory
// ("tutorial_phong" → <dir>/tutorial_phong.so). A null `function` means "none".
struct ProgramRef {
  const char* module;
  const char* function;
  bool present() const { return function != nullptr; }
};

struct StepConfig {
  int step;
  const char* title;
  ProgramRef miss;
  ProgramRef box_closest_hit;
  ProgramRef floor_closest_hit;
  ProgramRef opaque_any_hit;  // shadow rays (ray type 1) against the box and floor
  ProgramRef chull_closest_hit;
  ProgramRef chull_any_hit;
  // The ray generation program: the pinhole camera, or step 11's environment camera.
  ProgramRef camera = {"tutorial_camera", "pinhole_camera"};
  bool has_chull() const { return chull_closest_hit.present(); }
  // Steps 5 on read the environment map (envmap), step 8 on the noise texture (noise_texture).
  bool has_envmap() const { return step >= 5; }
  bool has_noise() const { return step >= 8; }
};

inline constexpr int kFirstStep = 0;
// The last step of the Whitted scene seen through the pinhole camera (what the benchmarks render).
inline constexpr int kLastStep = 10;
// Step 10's scene seen by an environment camera: the whole sphere around the eye.
inline constexpr int kEnvironmentCameraStep = 11;

// The configuration of `step` (kFirstStep to kEnvironmentCameraStep); throws TutorialError for
// steps that do not exist.
const StepConfig& GetStep(int step);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_STEPS_H_
