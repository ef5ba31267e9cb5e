// gRPC's own log lines (connection errors, TLS handshake failures) through Tessera's log
// (tessera/scheduler/log.h), as the "grpc" component, instead of gRPC's own stderr format.
#ifndef TESSERA_SCHEDULER_TRANSPORT_GRPC_LOG_H_
#define TESSERA_SCHEDULER_TRANSPORT_GRPC_LOG_H_

namespace tessera::transport {

// Installs the routing, once per process (later calls do nothing). gRPC still chooses which of
// its lines to write (GRPC_VERBOSITY, default ERROR); Tessera's level then filters them: gRPC's
// DEBUG lines are debug, INFO info, ERROR error.
void RouteGrpcLogs();

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_GRPC_LOG_H_
