// tessera-worker: serves one Tessera device over gRPC (DESIGN.md "Devices").
//
//   tessera-worker [--listen 127.0.0.1:0 | HOST:PORT | unix:PATH] [--threads N] [--allow-remote]
//
// Once it listens it prints exactly one line to stdout, `tessera-worker listening on <address>`
// (with the real port when asked for port 0), so that a parent process can read where it is.
// SIGTERM or SIGINT stops it.
#include <grpcpp/grpcpp.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "listen_address.h"
#include "transport/worker_wire.h"
#include "worker_service.h"

namespace {

// Pings from clients' keepalive (scheduler/transport/grpc_device.cc) must not count as abuse.
constexpr int kMinPingIntervalMs = 10000;

int Serve(const std::string& listen, int threads, bool allow_remote) {
  using tessera::worker::IsLoopbackAddress;
  if (!IsLoopbackAddress(listen)) {
    if (!allow_remote) {
      std::fprintf(stderr,
                   "tessera-worker: refusing to listen on %s: it is not a loopback address, and a "
                   "worker runs whatever code its host sends. Pass --allow-remote to accept "
                   "connections from other machines (no TLS or authentication yet: use a trusted "
                   "network only).\n",
                   listen.c_str());
      return 2;
    }
    std::fprintf(stderr,
                 "tessera-worker: WARNING: listening on %s without TLS or authentication; any "
                 "host that can reach it can run code in this process\n",
                 listen.c_str());
  }

  // Stop signals are taken by sigwait below; blocked here, before gRPC starts its threads, so that
  // they inherit the mask and none of them receives the signal instead.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  // Nothing reads stdout after the ready line (the host closes its end): a stray printf from a
  // program module must not kill the worker.
  signal(SIGPIPE, SIG_IGN);

  tessera::worker::WorkerService service(threads);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(listen, grpc::InsecureServerCredentials(), &port);
  builder.RegisterService(&service);
  builder.SetMaxReceiveMessageSize(tessera::transport::kMaxMessageBytes);
  builder.SetMaxSendMessageSize(tessera::transport::kMaxMessageBytes);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS,
                             kMinPingIntervalMs);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MAX_PING_STRIKES, 0);
  // gRPC sets SO_REUSEPORT by default: a second worker on a taken port would share it and receive
  // half of the connections (and so half of a host's sessions). Taken means taken.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (server == nullptr || port == 0) {
    std::fprintf(stderr, "tessera-worker: cannot listen on %s (address in use or not allowed?)\n",
                 listen.c_str());
    return 1;
  }
  std::printf("tessera-worker listening on %s\n",
              tessera::worker::ResolvedListenAddress(listen, port).c_str());
  std::fflush(stdout);

  int signal_number = 0;
  sigwait(&stop, &signal_number);
  // In-flight calls get a moment to finish; launches still running are cancelled.
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  server->Wait();
  // Skip the orderly teardown: gRPC 1.51's library shutdown can block for up to 10 s joining an
  // executor thread that sits in epoll_wait, and a parent waiting for us would SIGKILL us first.
  // Nothing is left to save (stdout is flushed; sessions live in memory only).
  std::fflush(nullptr);
  std::_Exit(0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "tessera-worker: serves a Tessera device (context replica, tiles, Embree) over gRPC"};
  std::string listen = "127.0.0.1:0";
  int threads = 0;
  bool allow_remote = false;
  app.add_option("--listen", listen,
                 "HOST:PORT (port 0: ephemeral), [IPV6]:PORT or unix:PATH; loopback unless "
                 "--allow-remote")
      ->capture_default_str();
  app.add_option("--threads", threads, "threads per launch (0: one per core)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--allow-remote", allow_remote,
               "allow a non-loopback --listen address (no TLS or authentication yet)");
  CLI11_PARSE(app, argc, argv);
  return Serve(listen, threads, allow_remote);
}
