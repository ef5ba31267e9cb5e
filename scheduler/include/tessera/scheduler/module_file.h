// Whether a program module file holds all of itself, checked before anything dlopens it, alike on
// the host (rtProgramCreateFromPTXFile, the compile cache) and on devices.
#ifndef TESSERA_SCHEDULER_MODULE_FILE_H_
#define TESSERA_SCHEDULER_MODULE_FILE_H_

#include <string>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"

namespace tessera::scheduler {

// INVALID_ARGUMENT, its message starting with `path`, when it is a 64-bit ELF file cut short: one
// whose program headers or loadable segments reach past its end. dlopen maps such a file whole and
// the process dies of SIGBUS at the first access past the end, instead of failing. OK for anything
// else (a complete module, or a file dlopen refuses with a message of its own).
absl::Status CheckModuleFileComplete(const std::string& path);

// Whether `bytes`, a program module's file, is a shared object for this machine whose dynamic
// symbol table defines `function` as a global function (and, with `require_init`,
// tessera_module_init), read from
// the bytes without loading them: dlopen would run the module's global constructors (and IFUNC
// resolvers) in the calling process, which on the host must not run program code, so that a
// module that crashes or exits as it loads takes down a worker, not the application.
// INVALID_ARGUMENT for what is no such shared object, NOT_FOUND for a missing `function`,
// FAILED_PRECONDITION for a module not built against tessera/device.h. Messages do not name the
// file. A shared object without section headers is not checked (OK): devices report it.
absl::Status CheckModuleBytes(absl::string_view bytes, absl::string_view function,
                              bool require_init);

// The section of an OptiX 3 program module that holds the same module built with
// initial-exec thread-local variables (docs/programs.md, "Thread-local storage"): not loaded
// with the module, written out and loaded in its place where the process has static TLS to spare.
inline constexpr char kInitialExecSection[] = ".tessera_initial_exec";

// The bytes of section `name` of the 64-bit ELF file `bytes`; empty when it has no such section,
// or the headers that would say where it lies are malformed.
absl::string_view FindElfSection(absl::string_view bytes, absl::string_view name);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_MODULE_FILE_H_
