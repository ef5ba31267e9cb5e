#include "worker_status.h"

#include <chrono>
#include <cstdio>
#include <cstring>

#include "absl/strings/str_format.h"
#include "memory_use.h"

namespace tessera::worker {
namespace {

// A JSON string's contents: the version is the project's, but nothing here trusts that.
std::string JsonEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out.push_back('\\');
      out.push_back(c);
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += absl::StrFormat("\\u%04x", c);
    } else {
      out.push_back(c);
    }
  }
  return out;
}

}  // namespace

int ProcessThreads() {
  std::FILE* status = std::fopen("/proc/self/status", "r");
  if (status == nullptr) return 0;
  char line[256];
  int threads = 0;
  while (std::fgets(line, sizeof(line), status) != nullptr) {
    if (std::strncmp(line, "Threads:", 8) == 0) {
      threads = std::atoi(line + 8);
      break;
    }
  }
  std::fclose(status);
  return threads;
}

HttpHandler MakeStatusHandler(WorkerService* service, std::string version) {
  const auto started = std::chrono::steady_clock::now();
  return [service, version = JsonEscape(version), started](absl::string_view path) {
    HttpResponse response;
    if (path == "/healthz") {
      const bool stopping = service->shutting_down();
      response.code = stopping ? 503 : 200;
      response.body = stopping ? "shutting down\n" : "ok\n";
      return response;
    }
    if (path == "/status") {
      const WorkerService::Stats stats = service->GetStats();
      const double uptime =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      response.content_type = "application/json";
      response.body = absl::StrFormat(
          "{\"version\":\"%s\",\"uptime_s\":%.3f,\"sessions\":%u,\"launches\":%u,\"tiles\":%u,"
          "\"tiles_per_s\":%.3f,\"rss_bytes\":%u,\"threads\":%d,\"process_threads\":%d,"
          "\"shutting_down\":%s}\n",
          version, uptime, stats.sessions, stats.launches, stats.tiles, stats.tiles_per_s,
          ResidentBytes(), service->thread_count(), ProcessThreads(),
          service->shutting_down() ? "true" : "false");
      return response;
    }
    response.code = 404;
    response.body = "not found: GET /healthz or /status\n";
    return response;
  };
}

}  // namespace tessera::worker
