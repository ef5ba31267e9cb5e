// How the worker's gRPC server guards itself against hosts that misbehave or vanish, and against a
// client that floods it: message sizes, keepalive and ping policy, concurrent calls and threads.
// The values and why are in server_options.cc; docs/security.md ("Denial of service") says what a
// user sees.
#ifndef TESSERA_WORKER_SERVICE_SERVER_OPTIONS_H_
#define TESSERA_WORKER_SERVICE_SERVER_OPTIONS_H_

#include <grpcpp/grpcpp.h>

namespace tessera::worker {

// Calls the worker serves at once, on as many threads of gRPC's synchronous server, for a worker
// that holds at most `max_sessions` sessions (0: no limit): a few per session (a host keeps two
// Launch calls in flight and sends Apply, Health and EndSession calls) and some to spare. Calls
// past it are refused with RESOURCE_EXHAUSTED ("Server Threadpool Exhausted") instead of starting
// a thread each until the process can start no more.
int CallCapacity(int max_sessions);

// Sets everything above on `builder` (its listening port and services are the caller's).
void ConfigureServer(grpc::ServerBuilder* builder, int max_sessions);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_SERVER_OPTIONS_H_
