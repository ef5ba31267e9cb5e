// SIGINT and SIGTERM during a render: the first asks the render to stop after the sample pass in
// flight and write what it has; a second SIGINT abandons that pass (the image then holds the
// passes before it); a third ends the process at once, as SIGINT does by default.
#ifndef TESSERA_TOOLS_TESSERA_RENDER_STOP_SIGNALS_H_
#define TESSERA_TOOLS_TESSERA_RENDER_STOP_SIGNALS_H_

namespace tessera::render {

// Installs the handlers (once).
void InstallStopSignalHandlers();

// The first stop signal received (SIGINT or SIGTERM), or 0.
int StopSignal();

// Whether the pass in flight should be abandoned (a second SIGINT or SIGTERM).
bool AbandonPass();

// The exit status for a render stopped by `signal`: 128 + its number (130 for SIGINT, 143 for
// SIGTERM), as shells report a process the signal ended.
int ExitStatusForSignal(int signal);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_RENDER_STOP_SIGNALS_H_
