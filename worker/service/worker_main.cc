// tessera-worker: serves one Tessera device over gRPC (docs/devices.md "Device specs").
//
//   tessera-worker [--listen 127.0.0.1:0 | HOST:PORT | unix:PATH] [--threads N]
//                  [--tls-cert FILE --tls-key FILE [--tls-client-ca FILE]] [--token-file FILE]
//                  [--session-idle-timeout SECONDS] [--max-sessions N]
//                  [--status-listen [HOST:]PORT] [--log-level LEVEL] [--version]
//
// A non-loopback address needs TLS and a token (docs/security.md); the token may also come from
// $TESSERA_WORKER_TOKEN. --allow-remote is still accepted but allows nothing by itself.
//
// Program modules arrive by content hash and are kept in --module-cache DIR (module_cache.h).
//
// Once it listens it prints exactly one line to stdout, `tessera-worker listening on <address>`
// (with the real port when asked for port 0), so that a parent process can read where it is; its
// log goes to stderr (tessera/scheduler/log.h). SIGTERM, SIGINT or SIGHUP stop it gracefully:
// no new sessions or launches, those under way finish within a few seconds, exit 0. A usage
// error exits 2, a failure to start (an address in use) 1 (docs/devices.md "Running workers as a
// service").
#include <grpcpp/grpcpp.h>
#include <malloc.h>
#include <signal.h>
#include <sys/auxv.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "auth.h"
#include "listen_address.h"
#include "server_options.h"
#include "status_server.h"
#include "tessera/scheduler/log.h"
#include "tessera/scheduler/module_cache_files.h"
#include "tessera/worker/crash_report.h"
#include "tessera/worker/module_cache.h"
#include "tessera/worker/static_tls.h"
#include "transport/grpc_log.h"
#include "transport/result_arena.h"
#include "transport/worker_wire.h"
#include "worker_service.h"
#include "worker_status.h"

#ifndef TESSERA_VERSION
#define TESSERA_VERSION "unknown"
#endif

namespace {

namespace log = tessera::log;

// Exit statuses (docs/devices.md "Running workers as a service").
constexpr int kExitStopped = 0;      // a clean stop (SIGTERM, SIGINT, SIGHUP)
constexpr int kExitCannotStart = 1;  // an address in use, credentials that cannot be used
constexpr int kExitUsage = 2;        // a flag or address that is not one

// How long a stopping worker lets launches under way finish before it cancels them; a second
// signal cancels them at once.
constexpr std::chrono::seconds kStopGrace{5};

// SIGTERM, SIGINT and SIGHUP: taken by sigwait in AwaitStop, and blocked in every thread from
// the start of main, before anything starts a thread (the server credentials start gRPC's first
// threads): a thread that did not block them took the signal and its default action ended the
// worker with SIGTERM, now and then, when the signal came right after it said it listens.
sigset_t StopSignals() {
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGHUP);
  return stop;
}

void Say(log::Level level, const std::string& text) {
  log::Write(log::Component::kWorker, level, text);
}

// Waits for the stop signals in `stop`, then stops gracefully: the worker takes no new sessions
// or launches (and its /healthz says 503), the calls of launches under way get kStopGrace to end,
// and the server is shut down, cancelling what is left. Returns the first signal's name.
const char* AwaitStop(const sigset_t& stop, tessera::worker::WorkerService* service,
                      grpc::Server* server) {
  int signal_number = 0;
  sigwait(&stop, &signal_number);
  const char* name = signal_number == SIGTERM  ? "SIGTERM"
                     : signal_number == SIGINT ? "SIGINT"
                                               : "SIGHUP";
  service->BeginShutdown(name);
  Say(log::Level::kInfo,
      absl::StrCat("stopping (", name, "): no new sessions or launches; ",
                   service->calls_in_progress(), " call(s) under way get up to ",
                   kStopGrace.count(), " s to finish (a second signal cancels them)"));
  // Idle for a tenth of a second in a row: a launch's next call follows the last at once.
  const auto end = std::chrono::steady_clock::now() + kStopGrace;
  auto idle_since = std::chrono::steady_clock::time_point::max();
  const timespec tick{0, 20 * 1000 * 1000};
  while (std::chrono::steady_clock::now() < end) {
    const auto now = std::chrono::steady_clock::now();
    if (service->calls_in_progress() > 0) {
      idle_since = std::chrono::steady_clock::time_point::max();
    } else if (idle_since == std::chrono::steady_clock::time_point::max()) {
      idle_since = now;
    } else if (now - idle_since >= std::chrono::milliseconds(100)) {
      break;
    }
    if (sigtimedwait(&stop, nullptr, &tick) > 0) {
      Say(log::Level::kInfo, "second stop signal: cancelling the calls under way");
      break;
    }
  }
  const int left = service->calls_in_progress();
  if (left > 0) {
    Say(log::Level::kWarn, absl::StrCat("cancelling ", left, " call(s) still under way"));
  }
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
  server->Wait();
  return name;
}

int Serve(const std::string& listen, int threads, tessera::transport::ResultArena* arena,
          const tessera::worker::SecurityOptions& security,
          const tessera::worker::SessionLimits& limits, const std::string& status_listen) {
  // An address that is not one is a usage error; one that cannot be bound now (in use, not this
  // machine's, a live worker's socket) a failure to start.
  if (absl::Status address = tessera::worker::CheckListenAddress(listen); !address.ok()) {
    Say(log::Level::kError, std::string(address.message()));
    return kExitUsage;
  }
  absl::Status address = tessera::worker::CheckUnixSocketNotInUse(listen);
  if (address.ok()) address = tessera::worker::CheckCanBind(listen);
  if (!address.ok()) {
    Say(log::Level::kError, std::string(address.message()));
    return kExitCannotStart;
  }
  if (!status_listen.empty()) {
    if (absl::Status parsed = tessera::worker::ParseStatusAddress(status_listen).status();
        !parsed.ok()) {
      Say(log::Level::kError, std::string(parsed.message()));
      return kExitUsage;
    }
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
    Say(log::Level::kError, std::string(credentials.status().message()));
    return kExitUsage;
  }
  // From here on the token is known (possibly empty: no token required).

  const sigset_t stop = StopSignals();
  // Nothing reads stdout after the ready line (the host closes its end): a stray printf from a
  // program module must not kill the worker.
  signal(SIGPIPE, SIG_IGN);

  tessera::worker::WorkerService service(threads, arena, limits);
  // One line per refused call on stderr, where the host's log of a spawned worker also goes.
  tessera::worker::AuthenticatedWorker authenticated(
      &service, *token, [](const std::string& line) { Say(log::Level::kWarn, line); });
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
    Say(log::Level::kError,
        absl::StrCat("cannot listen on ", listen, " (address in use or not allowed",
                     security.tls() ? ", or the TLS key does not match the certificate" : "",
                     "?)"));
    return kExitCannotStart;
  }
  std::unique_ptr<tessera::worker::StatusServer> status;
  if (!status_listen.empty()) {
    absl::StatusOr<std::unique_ptr<tessera::worker::StatusServer>> started =
        tessera::worker::StatusServer::Start(
            status_listen, tessera::worker::MakeStatusHandler(&service, TESSERA_VERSION));
    if (!started.ok()) {
      Say(log::Level::kError, std::string(started.status().message()));
      server->Shutdown(std::chrono::system_clock::now());
      return kExitCannotStart;
    }
    status = *std::move(started);
  }
  if (security.tls() || !token->empty()) {
    Say(log::Level::kInfo,
        absl::StrCat(!security.tls()                       ? "no TLS"
                     : security.tls_client_ca_file.empty() ? "TLS"
                                                           : "TLS with client certificates",
                     "; ", token->empty() ? "no token" : "every call must carry the token"));
  }
  const std::string resolved = tessera::worker::ResolvedListenAddress(listen, port);
  Say(log::Level::kInfo,
      absl::StrCat("tessera-worker ", TESSERA_VERSION, " (pid ", getpid(), ") serves ", resolved,
                   " with ", service.thread_count(), " threads; sessions: at most ",
                   limits.max_sessions, ", dropped after ",
                   absl::ToDoubleSeconds(limits.idle_timeout), " s idle",
                   status != nullptr ? absl::StrCat("; status on http://", status->address())
                                     : std::string()));
  std::printf("tessera-worker listening on %s\n", resolved.c_str());
  std::fflush(stdout);

  const char* signal_name = AwaitStop(stop, &service, server.get());
  status.reset();
  Say(log::Level::kInfo, absl::StrCat("stopped (", signal_name, ")"));
  // Skip the orderly teardown: gRPC 1.51's library shutdown can block for up to 10 s joining an
  // executor thread that sits in epoll_wait, and a parent waiting for us would SIGKILL us first.
  // Nothing is left to save (stdout is flushed; sessions live in memory only), and a temporary
  // module cache goes with us.
  std::fflush(nullptr);
  tessera::RemoveTemporaryModuleCaches();
  std::_Exit(kExitStopped);
}

}  // namespace

int main(int argc, char** argv) {
  // Modules' variables as initial-exec thread-locals (worker/core/static_tls.h).
  tessera::worker::RestartWithModuleStaticTls(argv, "TESSERA_WORKER_RESTARTED");
  const sigset_t stop = StopSignals();
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  tessera::InstallCrashReporter();
  // A worker its host spawned (local:N) dies with that host (PR_SET_PDEATHSIG, which survives
  // exec): its sessions end with the host, and one idle for long (an interactive application
  // between renders) must not cost a resend of its whole state.
  int parent_death_signal = 0;
  const bool dies_with_parent =
      prctl(PR_GET_PDEATHSIG, &parent_death_signal) == 0 && parent_death_signal != 0;
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
  std::string status_listen;
  app.add_option("--status-listen", status_listen,
                 "serve GET /healthz and GET /status (JSON) over plain HTTP on [HOST:]PORT (no "
                 "host: 127.0.0.1; port 0: any free one, said in the log); off by default");
  std::string log_level;
  app.add_option("--log-level", log_level,
                 "trace, debug, info, warn, error or off (default: $TESSERA_LOG_LEVEL, else info)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            absl::StatusOr<log::Level> level = log::ParseLevel(text);
            return level.ok() ? std::string() : std::string(level.status().message());
          },
          "LEVEL", "log level"));
  app.set_version_flag("--version", std::string("tessera-worker ") + TESSERA_VERSION,
                       "print the version and exit");
  app.footer(
      "Examples:\n"
      "  tessera-worker --listen unix:/run/tessera/w0.sock --threads 16\n"
      "  tessera-worker --listen 0.0.0.0:7000 --tls-cert worker.pem --tls-key worker.key \\\n"
      "      --token-file tessera.token --session-idle-timeout 300 --max-sessions 16\n"
      "  tessera-worker --listen 127.0.0.1:7000 --status-listen 9100 --log-level warn\n"
      "Exit status: 0 after SIGTERM, SIGINT or SIGHUP (launches under way finish first), 1 when "
      "it\n"
      "cannot start (an address in use), 2 for a usage error.\n"
      "See docs/devices.md and docs/security.md.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 says which flag and why; a usage error exits 2, as the address checks do (--help and
    // --version: 0).
    return app.exit(e) == 0 ? 0 : kExitUsage;
  }
  if (!log_level.empty()) log::SetLevel(*log::ParseLevel(log_level));
  tessera::transport::RouteGrpcLogs();
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
      Say(log::Level::kWarn,
          absl::StrCat(mapped.status().message(), "; results go through the socket"));
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
  // A worker that serves hosts which come and go must give their memory back when their sessions
  // end. glibc keeps a heap per thread (up to 8 per core), and the free space at the top of such a
  // heap is never returned (malloc_trim releases the main heap's only; the trim threshold above
  // keeps the others whole): every host that crashed left the peak of its session in the heaps of
  // whichever threads served it, 18 MB growing to 74 MB over four hosts. One heap, trimmed when a
  // session ends, returns to the worker's size after its first host. Set before any thread starts;
  // MALLOC_ARENA_MAX in the environment still decides. A worker its host spawned (local:N) ends
  // with that host's context and drops no sessions (unless given --session-idle-timeout): it keeps
  // glibc's heap per thread.
  if ((!dies_with_parent || limits.idle_timeout > absl::ZeroDuration()) &&
      std::getenv("MALLOC_ARENA_MAX") == nullptr) {
    mallopt(M_ARENA_MAX, 1);
  }
  return Serve(listen, threads, arena.get(), security, limits, status_listen);
}
