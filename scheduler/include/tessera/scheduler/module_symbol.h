// Finding a program in a program module, alike on the host (rtProgramCreateFromPTXFile checks the
// name) and on devices (which call it).
#ifndef TESSERA_SCHEDULER_MODULE_SYMBOL_H_
#define TESSERA_SCHEDULER_MODULE_SYMBOL_H_

namespace tessera::scheduler {

// The global function `name` that the shared object opened as `handle` defines itself, or null.
// dlsym alone also finds what the object's libraries define (libc's `write`), its data (an
// rtBuffer object) and weak functions its headers instantiate: called as a program, any of them
// would run on arguments it does not take. A program (RT_PROGRAM) is a global function.
void* FindModuleFunction(void* handle, const char* name);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_MODULE_SYMBOL_H_
