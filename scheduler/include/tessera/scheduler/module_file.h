// Whether a program module file holds all of itself, checked before anything dlopens it, alike on
// the host (rtProgramCreateFromPTXFile, the compile cache) and on devices.
#ifndef TESSERA_SCHEDULER_MODULE_FILE_H_
#define TESSERA_SCHEDULER_MODULE_FILE_H_

#include <string>

#include "absl/status/status.h"

namespace tessera::scheduler {

// INVALID_ARGUMENT, its message starting with `path`, when it is a 64-bit ELF file cut short: one
// whose program headers or loadable segments reach past its end. dlopen maps such a file whole and
// the process dies of SIGBUS at the first access past the end, instead of failing. OK for anything
// else (a complete module, or a file dlopen refuses with a message of its own).
absl::Status CheckModuleFileComplete(const std::string& path);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_MODULE_FILE_H_
