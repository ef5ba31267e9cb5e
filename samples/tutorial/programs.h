// Loads the tutorial's programs from its program modules, once per (module, function).
#ifndef TESSERA_SAMPLES_TUTORIAL_PROGRAMS_H_
#define TESSERA_SAMPLES_TUTORIAL_PROGRAMS_H_

#include <map>
#include <string>
#include <utility>

#include "tessera/rt.h"
#include "tutorial/steps.h"

namespace tessera::tutorial {

class ProgramLoader {
 public:
  ProgramLoader(RTcontext context, std::string module_dir);

  // The program `ref` names; throws TutorialError if the module is missing or does not load.
  RTprogram Get(const ProgramRef& ref);

  // <module_dir>/<module>.so
  std::string ModulePath(const char* module) const;

 private:
  RTcontext context_;
  std::string module_dir_;
  std::map<std::pair<std::string, std::string>, RTprogram> programs_;
};

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_PROGRAMS_H_
