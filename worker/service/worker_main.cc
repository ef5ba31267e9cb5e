// tessera-worker: serves one Tessera device over gRPC (docs/devices.md "Device specs").
//
//   tessera-worker [--listen 127.0.0.1:0 | HOST:PORT | unix:PATH] [--threads N]
//                  [--tls-cert FILE --tls-key FILE [--tls-client-ca FILE]] [--token-file FILE]
//                  [--session-idle-timeout SECONDS] [--max-sessions N]
//
// A non-loopback address needs TLS and a token (docs/security.md); the token may also come from
// $TESSERA_WORKER_TOKEN. --allow-remote is still accepted but allows nothing by itself.
//
// Program modules arrive by content hash and are kept in --module-cache DIR (module_cache.h).
//
// Once it listens it prints exactly one line to stdout, `tessera-worker listening on <address>`
// (with the real port when asked for port 0), so that a parent process can read where it is.
// SIGTERM or SIGINT stops it.
#include <grpcpp/grpcpp.h>
#include <malloc.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "auth.h"
#include "listen_address.h"
#include "server_options.h"
#include "tessera/scheduler/module_cache_files.h"
#include "tessera/worker/crash_report.h"
#include "tessera/worker/module_cache.h"
#include "transport/result_arena.h"
#include "transport/worker_wire.h"
#include "worker_service.h"

namespace {

int Serve(const std::string& listen, int threads, tessera::transport::ResultArena* arena,
          const tessera::worker::SecurityOptions& security,
          const tessera::worker::SessionLimits& limits) {
  absl::Status address = tessera::worker::CheckListenAddress(listen);
  if (address.ok()) address = tessera::worker::CheckUnixSocketNotInUse(listen);
  if (address.ok()) address = tessera::worker::CheckCanBind(listen);
  if (!address.ok()) {
    std::fprintf(stderr, "tessera-worker: %s\n", std::string(address.message()).c_str());
    return 2;
  }
  absl::StatusOr<std::string> token = tessera::worker::ResolveToken(
      security.token_file, std::getenv(tessera::worker::kWorkerTokenEnv));
  absl::Status allowed = token.ok()
                             ? tessera::worker::CheckListenPolicy(listen, security, !token->empty())
                             : token.status();
  using Credentials = absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>>;
  Credentials credentials =
      allowed.ok() ? tessera::worker::MakeServerCredentials(security) : Credentials(allowed);
  if (!credentials.ok()) {
    std::fprintf(stderr, "tessera-worker: %s\n",
                 std::string(credentials.status().message()).c_str());
    return 2;
  }
  // From here on the token is known (possibly empty: no token required).

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

  tessera::worker::WorkerService service(threads, arena, limits);
  // One line per refused call on stderr, where the host's log of a spawned worker also goes.
  tessera::worker::AuthenticatedWorker authenticated(&service, *token, [](const std::string& line) {
    std::fprintf(stderr, "%s\n", line.c_str());
  });
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(listen, *credentials, &port);
  if (token->empty()) {
    builder.RegisterService(&service);
  } else {
    builder.RegisterService(&authenticated);
  }
  // Message sizes, keepalive and ping policy, and the calls and threads the server takes on.
  tessera::worker::ConfigureServer(&builder, limits.max_sessions);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (server == nullptr || port == 0) {
    std::fprintf(stderr, "tessera-worker: cannot listen on %s (address in use or not allowed%s?)\n",
                 listen.c_str(),
                 security.tls() ? ", or the TLS key does not match the certificate" : "");
    return 1;
  }
  if (security.tls() || !token->empty()) {
    std::fprintf(stderr, "tessera-worker: %s; %s\n",
                 !security.tls()                       ? "no TLS"
                 : security.tls_client_ca_file.empty() ? "TLS"
                                                       : "TLS with client certificates",
                 token->empty() ? "no token" : "every call must carry the token");
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
  // Nothing is left to save (stdout is flushed; sessions live in memory only), and a temporary
  // module cache goes with us.
  std::fflush(nullptr);
  tessera::RemoveTemporaryModuleCaches();
  std::_Exit(0);
}

}  // namespace

int main(int argc, char** argv) {
  tessera::InstallCrashReporter();
  // Whoever can connect to a unix socket, or write a module into the cache, runs code as this
  // worker's user: everything the worker creates is owner-only, whatever umask it inherited (000
  // or 002 would let other users or the group in). The umask is the only way to have bind()
  // create the socket so, with no window.
  umask(0077);
  // Every call builds messages of up to a few MiB of results and frees them once sent. With
  // glibc's defaults those come from fresh pages each time (mmap, or a heap trimmed back to the
  // kernel): a page fault per 4 KiB, about a fifth of a one-thread worker's time on gathering
  // launches. Kept in the heap instead, the pages are reused.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  CLI::App app{
      "tessera-worker: serves a Tessera device (context replica, tiles, Embree) over gRPC"};
  std::string listen = "127.0.0.1:0";
  int threads = 0;
  bool allow_remote = false;
  tessera::worker::SecurityOptions security;
  app.add_option("--listen", listen,
                 "HOST:PORT (port 0: ephemeral), [IPV6]:PORT or unix:PATH; a non-loopback address "
                 "needs --tls-cert, --tls-key and a token")
      ->capture_default_str();
  // Beyond any machine's cores (a host passes cores/N for local:N), and far below the counts
  // (2^30 and up) for which TBB's arena crashed the worker at its first launch.
  constexpr int kMaxThreads = 65536;
  app.add_option("--threads", threads, "threads per launch (0: one per core)")
      ->check(CLI::Range(0, kMaxThreads))
      ->capture_default_str();
  app.add_option("--tls-cert", security.tls_cert_file, "PEM certificate chain: serve over TLS");
  app.add_option("--tls-key", security.tls_key_file, "PEM private key of --tls-cert");
  app.add_option("--tls-client-ca", security.tls_client_ca_file,
                 "PEM CA: callers must present a certificate it signed (mutual TLS)");
  app.add_option("--token-file", security.token_file,
                 "file whose first line is the token every call must carry (default: "
                 "$TESSERA_WORKER_TOKEN)");
  // Kept so that old command lines get the explanation below rather than a parse error; it used
  // to allow a non-loopback address without TLS or authentication, which nothing allows now.
  app.add_flag("--allow-remote", allow_remote,
               "no effect: a non-loopback address needs --tls-cert, --tls-key and a token");
  int arena_fd = -1;
  app.add_option("--result-arena-fd", arena_fd,
                 "descriptor of memory shared with the host that spawned this worker, for "
                 "written regions (the host passes it)")
      ->check(CLI::NonNegativeNumber);
  std::string module_cache;
  app.add_option("--module-cache", module_cache,
                 "directory of the program modules hosts send, by content hash (default: "
                 "$TESSERA_MODULE_CACHE, else $TESSERA_CACHE_DIR, else "
                 "$XDG_CACHE_HOME/tessera/modules, else ~/.cache/tessera/modules)");
  // A worker its host spawned (local:N) dies with that host (PR_SET_PDEATHSIG, which survives
  // exec): its sessions end with the host, and one idle for long (an interactive application
  // between renders) must not cost a resend of its whole state.
  int parent_death_signal = 0;
  const bool dies_with_parent =
      prctl(PR_GET_PDEATHSIG, &parent_death_signal) == 0 && parent_death_signal != 0;
  double idle_timeout_seconds = 600;
  constexpr double kMaxIdleTimeoutSeconds = 365.0 * 24 * 3600;
  CLI::Option* idle_option =
      app.add_option("--session-idle-timeout", idle_timeout_seconds,
                     "drop a host session that made no call for this many seconds, freeing its "
                     "memory (0: never); a host that comes back starts afresh. A worker a host "
                     "spawned for local:N dies with that host and drops none unless given this")
          ->check(CLI::Validator(
              [](const std::string& text) -> std::string {
                // CLI::Range lets "nan" through: it compares false with both ends.
                const double v = std::strtod(text.c_str(), nullptr);
                return std::isfinite(v) ? "" : "not a number of seconds";
              },
              "", "finite"))
          ->check(CLI::Range(0.0, kMaxIdleTimeoutSeconds))
          ->capture_default_str();
  int max_sessions = 64;
  app.add_option("--max-sessions", max_sessions,
                 "host sessions held at once (one per host context); another is refused, after "
                 "dropping those idle past --session-idle-timeout (0: no limit)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  app.footer(
      "Examples:\n"
      "  tessera-worker --listen unix:/run/tessera/w0.sock --threads 16\n"
      "  tessera-worker --listen 0.0.0.0:7000 --tls-cert worker.pem --tls-key worker.key \\\n"
      "      --token-file tessera.token --session-idle-timeout 300 --max-sessions 16\n"
      "See docs/devices.md and docs/security.md.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 says which flag and why; a usage error exits 2, as the address checks do (--help: 0).
    return app.exit(e) == 0 ? 0 : 2;
  }
  tessera::SetModuleCacheDirectory(module_cache);
  // Resolved now, so that falling back to a temporary directory or ignoring a malformed bound is
  // reported at startup, where a host that spawned this worker passes it on.
  tessera::ModuleCacheDirectory();
  tessera::scheduler::ModuleCacheLimitBytes();
  std::unique_ptr<tessera::transport::ResultArena> arena;
  if (arena_fd >= 0) {
    absl::StatusOr<std::unique_ptr<tessera::transport::ResultArena>> mapped =
        tessera::transport::ResultArena::Map(arena_fd);
    if (!mapped.ok()) {
      // Results still travel, through the socket.
      std::fprintf(stderr, "tessera-worker: %s; results go through the socket\n",
                   std::string(mapped.status().message()).c_str());
    } else {
      arena = *std::move(mapped);
      arena->CloseFd();  // the mapping stays
    }
  }
  tessera::worker::SessionLimits limits;
  limits.max_sessions = max_sessions;
  limits.idle_timeout = idle_option->count() == 0 && dies_with_parent
                            ? absl::ZeroDuration()
                            : absl::Seconds(idle_timeout_seconds);
  return Serve(listen, threads, arena.get(), security, limits);
}
