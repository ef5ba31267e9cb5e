#include "transport/grpc_log.h"

#include <grpc/support/log.h>

#include <mutex>

#include "tessera/scheduler/log.h"

namespace tessera::transport {
namespace {

void ToTesseraLog(gpr_log_func_args* args) {
  log::Level level = log::Level::kError;
  switch (args->severity) {
    case GPR_LOG_SEVERITY_DEBUG:
      level = log::Level::kDebug;
      break;
    case GPR_LOG_SEVERITY_INFO:
      level = log::Level::kInfo;
      break;
    case GPR_LOG_SEVERITY_ERROR:
      level = log::Level::kError;
      break;
  }
  if (!log::Enabled(level)) return;
  log::Log(log::Component::kGrpc, level, "%s (%s:%d)",
           args->message != nullptr ? args->message : "", args->file != nullptr ? args->file : "?",
           args->line);
}

}  // namespace

void RouteGrpcLogs() {
  static std::once_flag once;
  std::call_once(once, [] { gpr_set_log_function(&ToTesseraLog); });
}

}  // namespace tessera::transport
