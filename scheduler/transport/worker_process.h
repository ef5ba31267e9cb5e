// A `tessera-worker` process the host spawns and reaps (device spec `local:N`, docs/devices.md
// "Device specs"). No orphans: the child gets PR_SET_PDEATHSIG(SIGKILL), so a host that crashes
// takes its workers along, and destruction terminates and reaps the worker.
#ifndef TESSERA_SCHEDULER_TRANSPORT_WORKER_PROCESS_H_
#define TESSERA_SCHEDULER_TRANSPORT_WORKER_PROCESS_H_

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"

namespace tessera::transport {

// The worker executable: $TESSERA_WORKER, else the path baked in at build time, else
// `tessera-worker` next to the binary holding this code (libtessera.so). NOT_FOUND names every
// place tried.
absl::StatusOr<std::string> FindWorkerBinary();

class ResultArena;

class WorkerProcess {
 public:
  struct Options {
    std::string binary;  // empty: FindWorkerBinary()
    // --listen; empty: unix:<private temporary directory>/w<index>.sock.
    std::string listen;
    int threads = 0;  // --threads; 0: the worker's default (one per core)
    int index = 0;    // names the socket and the log
    std::vector<std::string> extra_args;
    // Until the worker prints its "listening on" line.
    absl::Duration start_timeout = absl::Seconds(20);
    // Between SIGTERM and SIGKILL on destruction.
    absl::Duration stop_grace = absl::Seconds(2);
    // Memory shared with the worker for written regions (result_arena.h), bytes per slot; 0:
    // none, regions travel through the socket.
    uint64_t result_arena_slot_bytes = uint64_t{16} << 20;
  };

  // Starts the worker and waits until it listens. UNAVAILABLE if it exits or stays silent past
  // the timeout; the message includes the end of its stderr.
  static absl::StatusOr<std::unique_ptr<WorkerProcess>> Spawn(Options options);

  // SIGTERM, then SIGKILL after `stop_grace`; reaps the process and removes its directory.
  ~WorkerProcess();
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  pid_t pid() const { return pid_; }
  // What the worker printed: "unix:/tmp/tessera-w-…/w0.sock" or "127.0.0.1:41234".
  const std::string& address() const { return address_; }
  // The worker's stderr goes here (it is removed with the process).
  const std::string& log_path() const { return log_path_; }
  // The last `max_bytes` of the log.
  std::string LogTail(size_t max_bytes = 4096) const;

  // How the worker ended, waiting up to `timeout` for it to end: "was killed by signal 9", or
  // empty while it still runs. `crashed` says whether a fatal signal other than SIGKILL ended
  // it (a crash rather than something killing it). Reaps the process once it ended. Safe to call
  // from several threads (both calls in flight of a device see it go): all see the same answer.
  std::string WaitForExit(absl::Duration timeout, bool* crashed);

  // Ends a worker the host gave up on (silent past its deadline, or its connection lost) at
  // once: SIGKILL and reap, without the grace a clean stop gets, which a stopped or hung worker
  // would only spend. Safe with WaitForExit on other threads.
  void Kill();

  // The memory the worker shares for written regions; null when there is none.
  ResultArena* result_arena() const { return arena_.get(); }

 private:
  WorkerProcess() = default;

  pid_t pid_ = -1;
  pid_t host_pid_ = -1;  // the process that spawned it: only that one stops and reaps it
  std::mutex exit_mu_;   // guards reaping: pid_ (after Spawn), exit_, crashed_
  std::string exit_;     // set once reaped
  bool crashed_ = false;
  std::string address_;
  std::string directory_;
  std::string log_path_;
  std::string socket_path_;  // empty unless the worker listens in `directory_`
  absl::Duration stop_grace_;
  std::unique_ptr<ResultArena> arena_;
};

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_WORKER_PROCESS_H_
