// The tessera-tutorial command line:
//   tessera-tutorial --step N --width W --height H --out FILE [--modules DIR]
#ifndef TESSERA_SAMPLES_TUTORIAL_CLI_H_
#define TESSERA_SAMPLES_TUTORIAL_CLI_H_

#include <ostream>

namespace tessera::tutorial {

// Parses the arguments, renders the step and writes the image; prints the output path to `out`
// and errors to `err`. Returns the process exit status (0 on success).
int RunTutorialMain(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace tessera::tutorial

#endif  // TESSERA_SAMPLES_TUTORIAL_CLI_H_
