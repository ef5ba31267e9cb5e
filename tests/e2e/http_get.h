// A hand-written HTTP/1.1 client for the end-to-end tests of tessera-worker's status endpoint
// (--status-listen): one request on its own connection, the whole answer back.
#ifndef TESSERA_TESTS_E2E_HTTP_GET_H_
#define TESSERA_TESTS_E2E_HTTP_GET_H_

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>

namespace tessera::e2e {

struct HttpAnswer {
  int code = 0;  // 0: no answer
  std::string headers, body;
};

// `request` as it is (e.g. "GET /status HTTP/1.1\r\nHost: x\r\n\r\n") to 127.0.0.1:`port`.
inline HttpAnswer HttpExchange(int port, const std::string& request) {
  HttpAnswer answer;
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    if (fd >= 0) close(fd);
    return answer;
  }
  (void)!send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string text;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 50) <= 0) continue;
    char buf[4096];
    const ssize_t n = recv(fd, buf, sizeof(buf), 0);
    if (n <= 0) break;
    text.append(buf, static_cast<size_t>(n));
  }
  close(fd);
  const size_t split = text.find("\r\n\r\n");
  if (text.rfind("HTTP/1.1 ", 0) != 0 || split == std::string::npos) return answer;
  answer.code = std::atoi(text.c_str() + 9);
  answer.headers = text.substr(0, split);
  answer.body = text.substr(split + 4);
  return answer;
}

inline HttpAnswer HttpGet(int port, const std::string& path) {
  return HttpExchange(port, "GET " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
}

// The number after "\"name\":" in a flat JSON object; -1 when absent.
inline double JsonNumber(const std::string& json, const std::string& name) {
  const std::string key = "\"" + name + "\":";
  const size_t at = json.find(key);
  return at == std::string::npos ? -1 : std::strtod(json.c_str() + at + key.size(), nullptr);
}

// The port of "status on http://HOST:PORT" in a worker's log; 0 when absent.
inline int StatusPort(const std::string& log) {
  const std::string key = "status on http://127.0.0.1:";
  const size_t at = log.find(key);
  return at == std::string::npos ? 0 : std::atoi(log.c_str() + at + key.size());
}

}  // namespace tessera::e2e

#endif  // TESSERA_TESTS_E2E_HTTP_GET_H_
