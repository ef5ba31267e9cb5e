// What tessera-worker's status endpoint answers (--status-listen; docs/devices.md "Running
// workers as a service"): GET /healthz and GET /status over a WorkerService.
#ifndef TESSERA_WORKER_SERVICE_WORKER_STATUS_H_
#define TESSERA_WORKER_SERVICE_WORKER_STATUS_H_

#include <string>

#include "status_server.h"
#include "worker_service.h"

namespace tessera::worker {

// GET /healthz: 200 "ok" while the worker serves, 503 "shutting down" once it stops
// (WorkerService::BeginShutdown). GET /status: one JSON object,
//   {"version": "0.1.0", "uptime_s": 12.5, "sessions": 1, "launches": 40, "tiles": 2560,
//    "tiles_per_s": 204.8, "rss_bytes": 24117248, "threads": 16, "process_threads": 23,
//    "shutting_down": false}
// (threads: those it traces with; process_threads: all of the process's). Anything else: 404.
HttpHandler MakeStatusHandler(WorkerService* service, std::string version);

// The threads of this process (/proc/self/status); 0 when unknown.
int ProcessThreads();

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_WORKER_STATUS_H_
