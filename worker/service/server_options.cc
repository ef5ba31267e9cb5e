#include "server_options.h"

#include <grpc/grpc.h>
#include <grpcpp/resource_quota.h>

#include <algorithm>
#include <climits>

#include "transport/worker_wire.h"

namespace tessera::worker {
namespace {

// The host's keepalive (scheduler/transport/grpc_device.cc): a ping every 30 s during calls,
// answered within 20 s. Pings at a third of that interval are still allowed, so a host is never
// mistaken for a flood; faster ones are strikes, and a client past kMaxPingStrikes of them gets
// GOAWAY (ENHANCE_YOUR_CALM "too_many_pings") and loses its connection. gRPC's own default of 2
// strikes; this worker used to set 0, which means unlimited.
constexpr int kMinRecvPingIntervalMs = 10000;
constexpr int kMaxPingStrikes = 2;

// The worker's own pings find a host that vanished without closing its connection (a machine
// that lost power): its calls end within a minute and a half (their sessions are then idle, and
// dropped after --session-idle-timeout), and its connection is closed. On idle connections too,
// and without waiting for data in between: a host that sends a state update of gigabytes gets
// none back for minutes.
constexpr int kKeepaliveTimeMs = 60000;
constexpr int kKeepaliveTimeoutMs = 20000;

// Calls per session and calls to spare (CallCapacity), and the capacity of a worker without a
// session limit, still far below the threads a process may start.
constexpr int kCallsPerSession = 3;
constexpr int kSpareCalls = 32;
constexpr int kUnlimitedSessionsCalls = 4096;

}  // namespace

int CallCapacity(int max_sessions) {
  if (max_sessions <= 0) return kUnlimitedSessionsCalls;
  return std::min<long long>(kUnlimitedSessionsCalls,
                             static_cast<long long>(max_sessions) * kCallsPerSession + kSpareCalls);
}

void ConfigureServer(grpc::ServerBuilder* builder, int max_sessions) {
  builder->SetMaxReceiveMessageSize(transport::kMaxMessageBytes);
  builder->SetMaxSendMessageSize(transport::kMaxMessageBytes);
  // gRPC sets SO_REUSEPORT by default: a second worker on a taken port would share it and receive
  // half of the connections (and so half of a host's sessions). Taken means taken.
  builder->AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);

  builder->AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS,
                              kMinRecvPingIntervalMs);
  builder->AddChannelArgument(GRPC_ARG_HTTP2_MAX_PING_STRIKES, kMaxPingStrikes);
  // A host's keepalive ping may cross the end of its last call: not a strike for that.
  builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, kKeepaliveTimeMs);
  builder->AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, kKeepaliveTimeoutMs);
  builder->AddChannelArgument(GRPC_ARG_HTTP2_MAX_PINGS_WITHOUT_DATA, 0);
  // No GRPC_ARG_MAX_CONNECTION_AGE_MS: one Launch call may render for hours, and an aged
  // connection's grace period would cut it. No GRPC_ARG_MAX_CONNECTION_IDLE_MS: keepalive closes
  // dead connections already, a live idle host's costs a descriptor and a few KiB, and closing it
  // would race the host's next call against the GOAWAY.

  // Every call of the synchronous server holds a thread while it runs (a Launch for the whole
  // call): bound the threads, and the streams one connection may open, by what the sessions need.
  const int calls = CallCapacity(max_sessions);
  builder->AddChannelArgument(GRPC_ARG_MAX_CONCURRENT_STREAMS, calls);
  grpc::ResourceQuota quota("tessera-worker");
  quota.SetMaxThreads(calls);
  builder->SetResourceQuota(quota);
}

}  // namespace tessera::worker
