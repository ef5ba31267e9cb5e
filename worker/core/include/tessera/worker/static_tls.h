// Static TLS for program modules: where their variables can be initial-exec thread-locals.
//
// An OptiX 3 module reaches its variables through local-dynamic TLS, a __tls_get_addr call in
// every program that reads one; built initial-exec they are a load from the thread pointer, but
// glibc then places them in the static TLS every thread reserves at its start, whose room for
// modules loaded later (rtld.optional_static_tls) is 512 bytes unless the process is started with
// more. Workers start themselves again with room to spare (worker_main.cc); a host process
// (`inproc` devices) uses the initial-exec build only where its user gave it the room.
#ifndef TESSERA_WORKER_STATIC_TLS_H_
#define TESSERA_WORKER_STATIC_TLS_H_

#include <cstddef>
#include <string>

#include "absl/strings/string_view.h"

namespace tessera::worker {

// The room a worker reserves: a module's variables take tens to hundreds of bytes.
inline constexpr size_t kModuleStaticTlsBytes = size_t{1} << 16;

// The static TLS for modules a GLIBC_TUNABLES value asks for (glibc.rtld.optional_static_tls, its
// last setting, decimal or 0x-hexadecimal); 0 if it asks for none.
size_t RequestedModuleStaticTls(absl::string_view tunables);

// Whether this process was started with at least kModuleStaticTlsBytes of static TLS for modules
// (GLIBC_TUNABLES' glibc.rtld.optional_static_tls, as glibc read it at the process's start).
bool ModuleStaticTlsReserved();

// GLIBC_TUNABLES `current` (null: unset) with that room added; what a worker starts itself with.
std::string TunablesWithModuleStaticTls(const char* current);

// For a program's main (the worker, the `tessera` tool): a process started without that room
// starts itself again with it, once, its environment marked with `restarted` (a variable name, set
// to 1: a process that finds it set does not try again). glibc sizes static TLS from
// GLIBC_TUNABLES as it starts a process, so only a new start gives the room; execve keeps the
// process (its pid, descriptors and parent-death signal), and children it starts inherit the room.
// Returns (doing nothing) where it cannot: no /proc, a path too long, a program started through
// the dynamic loader; its modules then keep their local-dynamic builds.
void RestartWithModuleStaticTls(char** argv, const char* restarted);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_STATIC_TLS_H_
