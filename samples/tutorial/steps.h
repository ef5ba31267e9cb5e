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
  bool has_chull() const { return chull_closest_hit.present(); }
};

inline constexpr int kFirstStep = 0;
inline constexpr int kLastStep = 10;

// The configuration of `step`; throws TutorialError for steps that do not exist or need
// features Tessera does not have yet (step 11).
const StepConfig& GetStep(int step);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_STEPS_H_
