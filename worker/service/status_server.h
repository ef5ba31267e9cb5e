// tessera-worker --status-listen: a small plain HTTP/1.1 server for probes and monitoring
// (GET /healthz, GET /status; docs/devices.md "Running workers as a service"). One thread serves
// every connection with poll(2): each request is read whole (a request line and headers, at most
// 8 KiB) within a deadline, answered, and the connection closed. Garbage gets 400, a request too
// large 431, one too slow 408, and past the connection limit a new connection gets 503 at once:
// no client can hold the thread, and none costs more than a descriptor and a buffer.
#ifndef TESSERA_WORKER_SERVICE_STATUS_SERVER_H_
#define TESSERA_WORKER_SERVICE_STATUS_SERVER_H_

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "absl/time/time.h"

namespace tessera::worker {

struct HttpResponse {
  int code = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

// Answers a well-formed request: method (GET or HEAD; others get 405 before this is asked) and
// path (without the query). Runs on the server's thread: keep it short.
using HttpHandler = std::function<HttpResponse(absl::string_view path)>;

struct StatusServerOptions {
  int max_connections = 64;                           // open at once; more get 503 and are closed
  absl::Duration request_timeout = absl::Seconds(5);  // to send the request and read the answer
  size_t max_request_bytes = 8192;                    // request line and headers
};

// Where --status-listen binds: "PORT", ":PORT", "HOST:PORT" or "[IPV6]:PORT", port 0 to 65535
// (0: any free one); without a host, 127.0.0.1. INVALID_ARGUMENT naming the text otherwise.
struct StatusAddress {
  std::string host;
  int port = 0;
};
absl::StatusOr<StatusAddress> ParseStatusAddress(absl::string_view text);

class StatusServer {
 public:
  // Binds and starts serving: INVALID_ARGUMENT for an address that is not one
  // (ParseStatusAddress), FAILED_PRECONDITION naming the address and the system's reason when it
  // cannot be bound (in use, not this machine's).
  static absl::StatusOr<std::unique_ptr<StatusServer>> Start(
      absl::string_view address, HttpHandler handler,
      StatusServerOptions options = StatusServerOptions());
  // Stops the thread and closes every connection.
  ~StatusServer();
  StatusServer(const StatusServer&) = delete;
  StatusServer& operator=(const StatusServer&) = delete;

  // "HOST:PORT" with the port bound (for port 0, the one the system chose).
  const std::string& address() const { return address_; }
  int port() const { return port_; }

 private:
  StatusServer() = default;
  void Serve();

  HttpHandler handler_;
  StatusServerOptions options_;
  std::string address_;
  int port_ = 0;
  int listen_fd_ = -1;
  int wake_fd_ = -1;  // an eventfd the destructor writes to end Serve
  std::thread thread_;
};

// The text of an HTTP/1.1 response with `response`'s code, type and body (none for HEAD), and
// Connection: close.
std::string FormatHttpResponse(const HttpResponse& response, bool head);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_STATUS_SERVER_H_
