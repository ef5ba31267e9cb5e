// The status endpoint's HTTP server over real sockets, with requests written by hand: what it
// answers, and that garbage, slow clients and floods of connections cannot stop it.
#include "status_server.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "worker_service.h"
#include "worker_status.h"

namespace tessera::worker {
namespace {

using Clock = std::chrono::steady_clock;

int Connect(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

// Everything the server sends until it closes (or `limit` passes).
std::string ReadAll(int fd, std::chrono::milliseconds limit = std::chrono::seconds(10)) {
  std::string text;
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 50) <= 0) continue;
    char buf[4096];
    const ssize_t n = recv(fd, buf, sizeof(buf), 0);
    if (n <= 0) break;
    text.append(buf, static_cast<size_t>(n));
  }
  return text;
}

// Sends `request` as it is and returns the whole answer.
std::string Exchange(int port, const std::string& request) {
  const int fd = Connect(port);
  if (fd < 0) return "connect failed";
  if (!request.empty()) (void)!send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string answer = ReadAll(fd);
  close(fd);
  return answer;
}

std::string StatusLine(const std::string& answer) { return answer.substr(0, answer.find("\r\n")); }
std::string Body(const std::string& answer) {
  const size_t at = answer.find("\r\n\r\n");
  return at == std::string::npos ? "" : answer.substr(at + 4);
}

HttpResponse Echo(absl::string_view path) {
  HttpResponse r;
  if (path == "/missing") {
    r.code = 404;
    r.body = "not found\n";
  } else {
    r.body = std::string(path) + "\n";
  }
  return r;
}

std::unique_ptr<StatusServer> StartServer(StatusServerOptions options = StatusServerOptions()) {
  auto server = StatusServer::Start("127.0.0.1:0", &Echo, options);
  EXPECT_TRUE(server.ok()) << server.status();
  return server.ok() ? *std::move(server) : nullptr;
}

TEST(StatusAddressTest, PortAloneMeansLoopback) {
  auto a = ParseStatusAddress("9100");
  ASSERT_TRUE(a.ok()) << a.status();
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 9100);
  a = ParseStatusAddress(":0");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "127.0.0.1");
  a = ParseStatusAddress("0.0.0.0:9100");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "0.0.0.0");
  a = ParseStatusAddress("[::1]:9100");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "::1");
  for (const char* bad : {"", "abc", "host:", "1:2:3", "70000", "-1", "[::1]9100", "+80"}) {
    absl::StatusOr<StatusAddress> r = ParseStatusAddress(bad);
    EXPECT_FALSE(r.ok()) << bad;
    if (!r.ok()) {
      EXPECT_NE(r.status().message().find("--status-listen"), std::string::npos) << r.status();
    }
  }
}

TEST(StatusServerTest, AnswersGetAndHeadAndClosesTheConnection) {
  auto server = StartServer();
  ASSERT_NE(server, nullptr);
  EXPECT_EQ(server->address(), "127.0.0.1:" + std::to_string(server->port()));
  std::string answer = Exchange(server->port(), "GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 200 OK") << answer;
  EXPECT_NE(answer.find("Content-Length: 9\r\n"), std::string::npos) << answer;
  EXPECT_NE(answer.find("Connection: close\r\n"), std::string::npos) << answer;
  EXPECT_EQ(Body(answer), "/healthz\n");
  // A query is not part of the path; HTTP/1.0 and bare newlines are understood.
  answer = Exchange(server->port(), "GET /status?x=1 HTTP/1.0\n\n");
  EXPECT_EQ(Body(answer), "/status\n") << answer;
  answer = Exchange(server->port(), "HEAD /status HTTP/1.1\r\n\r\n");
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 200 OK");
  EXPECT_NE(answer.find("Content-Length: 8\r\n"), std::string::npos) << answer;
  EXPECT_EQ(Body(answer), "");
  answer = Exchange(server->port(), "GET /missing HTTP/1.1\r\n\r\n");
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 404 Not Found") << answer;
}

TEST(StatusServerTest, GarbageAndOtherMethodsGetClearAnswers) {
  auto server = StartServer();
  ASSERT_NE(server, nullptr);
  EXPECT_EQ(StatusLine(Exchange(server->port(), "garbage\r\n\r\n")), "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(StatusLine(Exchange(server->port(), "GET healthz HTTP/1.1\r\n\r\n")),
            "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(StatusLine(Exchange(server->port(), "GET / SMTP\r\n\r\n")), "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(StatusLine(Exchange(server->port(), std::string("\0\xff\x01\r\n\r\n", 7))),
            "HTTP/1.1 400 Bad Request");
  const std::string post = Exchange(server->port(), "POST /status HTTP/1.1\r\n\r\n");
  EXPECT_EQ(StatusLine(post), "HTTP/1.1 405 Method Not Allowed");
  EXPECT_NE(post.find("Allow: GET, HEAD\r\n"), std::string::npos) << post;
  // Headers without end: refused once past the limit, not read forever.
  const std::string huge = "GET / HTTP/1.1\r\nX: " + std::string(20000, 'a');
  EXPECT_EQ(StatusLine(Exchange(server->port(), huge)),
            "HTTP/1.1 431 Request Header Fields Too Large");
  // A client that connects and leaves, or sends half a request and leaves, costs nothing.
  close(Connect(server->port()));
  const int fd = Connect(server->port());
  (void)!send(fd, "GET /", 5, MSG_NOSIGNAL);
  close(fd);
  EXPECT_EQ(StatusLine(Exchange(server->port(), "GET / HTTP/1.1\r\n\r\n")), "HTTP/1.1 200 OK");
}

TEST(StatusServerTest, ASlowClientIsCutOffAndOthersAreServedMeanwhile) {
  StatusServerOptions options;
  options.request_timeout = absl::Milliseconds(500);
  auto server = StartServer(options);
  ASSERT_NE(server, nullptr);
  const int slow = Connect(server->port());
  ASSERT_GE(slow, 0);
  (void)!send(slow, "GET /healthz HT", 15, MSG_NOSIGNAL);  // and nothing more
  const auto start = Clock::now();
  EXPECT_EQ(StatusLine(Exchange(server->port(), "GET / HTTP/1.1\r\n\r\n")), "HTTP/1.1 200 OK");
  EXPECT_LT(Clock::now() - start, std::chrono::milliseconds(400)) << "waited for the slow one";
  const std::string answer = ReadAll(slow);
  close(slow);
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 408 Request Timeout") << answer;
  EXPECT_LT(Clock::now() - start, std::chrono::seconds(3));
}

TEST(StatusServerTest, ManyConnectionsAreBoundedAndTheServerRecovers) {
  StatusServerOptions options;
  options.max_connections = 16;
  options.request_timeout = absl::Seconds(1);
  auto server = StartServer(options);
  ASSERT_NE(server, nullptr);
  // More idle connections than it keeps (fewer than the listening backlog, so that each is
  // accepted at once): those past the limit are told so and closed.
  std::vector<int> idle;
  for (int i = 0; i < 40; ++i) {
    const int fd = Connect(server->port());
    if (fd >= 0) idle.push_back(fd);
  }
  ASSERT_EQ(idle.size(), 40u);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  int refused = 0;
  for (int fd : idle) {
    char buf[256];
    const ssize_t n = recv(fd, buf, sizeof(buf) - 1, MSG_DONTWAIT);
    if (n > 0 && std::string(buf, static_cast<size_t>(n)).rfind("HTTP/1.1 503 ", 0) == 0) {
      ++refused;
    }
  }
  EXPECT_EQ(refused, 40 - 16);
  for (int fd : idle) close(fd);
  // Served again once they are gone; and many clients at once all get answers.
  std::vector<std::thread> clients;
  std::vector<std::string> answers(12);
  for (size_t i = 0; i < answers.size(); ++i) {
    clients.emplace_back(
        [&, i] { answers[i] = Exchange(server->port(), "GET /x HTTP/1.1\r\n\r\n"); });
  }
  for (std::thread& t : clients) t.join();
  for (const std::string& answer : answers) EXPECT_EQ(Body(answer), "/x\n") << answer;
}

TEST(StatusServerTest, AnAddressInUseIsAFailureToStartNamingIt) {
  auto first = StartServer();
  ASSERT_NE(first, nullptr);
  const std::string text = std::to_string(first->port());
  auto second = StatusServer::Start(text, &Echo);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(second.status().message().find("127.0.0.1:" + text), std::string::npos)
      << second.status();
  EXPECT_NE(second.status().message().find("in use"), std::string::npos) << second.status();
  auto bad = StatusServer::Start("nonsense", &Echo);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
}

// The worker's own answers: /healthz until it stops, /status with every field.
TEST(WorkerStatusTest, HealthzAndStatusDescribeTheWorker) {
  WorkerService service(2);
  auto server = StatusServer::Start("0", MakeStatusHandler(&service, "9.8.7"));
  ASSERT_TRUE(server.ok()) << server.status();
  const int port = (*server)->port();
  std::string answer = Exchange(port, "GET /healthz HTTP/1.1\r\n\r\n");
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 200 OK");
  EXPECT_EQ(Body(answer), "ok\n");
  answer = Exchange(port, "GET /status HTTP/1.1\r\n\r\n");
  EXPECT_NE(answer.find("Content-Type: application/json\r\n"), std::string::npos) << answer;
  const std::string body = Body(answer);
  for (const char* field :
       {"{\"version\":\"9.8.7\",", "\"uptime_s\":", "\"sessions\":0,", "\"launches\":0,",
        "\"tiles\":0,", "\"tiles_per_s\":0.000,", "\"rss_bytes\":", "\"threads\":2,",
        "\"process_threads\":", "\"shutting_down\":false}"}) {
    EXPECT_NE(body.find(field), std::string::npos) << field << " in " << body;
  }
  EXPECT_EQ(StatusLine(Exchange(port, "GET /metrics HTTP/1.1\r\n\r\n")), "HTTP/1.1 404 Not Found");
  service.BeginShutdown("SIGTERM");
  answer = Exchange(port, "GET /healthz HTTP/1.1\r\n\r\n");
  EXPECT_EQ(StatusLine(answer), "HTTP/1.1 503 Service Unavailable");
  EXPECT_EQ(Body(answer), "shutting down\n");
  EXPECT_NE(Body(Exchange(port, "GET /status HTTP/1.1\r\n\r\n")).find("\"shutting_down\":true"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera::worker
