#include "status_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <list>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "tessera/scheduler/log.h"

namespace tessera::worker {
namespace {

using Clock = std::chrono::steady_clock;

const char* ReasonPhrase(int code) {
  switch (code) {
    case 200:
      return "OK";
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 431:
      return "Request Header Fields Too Large";
    case 500:
      return "Internal Server Error";
    case 503:
      return "Service Unavailable";
  }
  return "Unknown";
}

HttpResponse Plain(int code, std::string body) {
  HttpResponse r;
  r.code = code;
  r.body = std::move(body);
  return r;
}

struct Connection {
  int fd = -1;
  Clock::time_point deadline;
  std::string in;
  std::string out;
  size_t sent = 0;
  bool answered = false;  // `out` holds the whole answer
};

// The answer to the request in `in` (which holds at least its request line and headers).
std::string Answer(const std::string& in, const HttpHandler& handler) {
  const size_t eol = in.find('\n');
  absl::string_view line(in.data(), eol == std::string::npos ? in.size() : eol);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<absl::string_view> parts = absl::StrSplit(line, ' ');
  if (parts.size() != 3 || parts[0].empty() || parts[1].empty() || parts[1].front() != '/' ||
      !absl::StartsWith(parts[2], "HTTP/1.")) {
    return FormatHttpResponse(Plain(400, "bad request\n"), false);
  }
  for (char c : parts[0]) {
    if (!absl::ascii_isupper(static_cast<unsigned char>(c))) {
      return FormatHttpResponse(Plain(400, "bad request\n"), false);
    }
  }
  const bool head = parts[0] == "HEAD";
  if (parts[0] != "GET" && !head) {
    HttpResponse r = Plain(405, "only GET and HEAD\n");
    return FormatHttpResponse(r, false);
  }
  absl::string_view path = parts[1];
  path = path.substr(0, path.find('?'));
  HttpResponse response;
  try {
    response = handler(path);
  } catch (const std::exception& e) {
    response = Plain(500, absl::StrCat("error: ", e.what(), "\n"));
  }
  return FormatHttpResponse(response, head);
}

bool RequestComplete(const std::string& in) {
  return in.find("\r\n\r\n") != std::string::npos || in.find("\n\n") != std::string::npos;
}

void CloseFd(int fd) {
  if (fd >= 0) close(fd);
}

}  // namespace

std::string FormatHttpResponse(const HttpResponse& response, bool head) {
  std::string text = absl::StrCat("HTTP/1.1 ", response.code, " ", ReasonPhrase(response.code),
                                  "\r\nContent-Type: ", response.content_type,
                                  "\r\nContent-Length: ", response.body.size(),
                                  "\r\nCache-Control: no-store\r\nConnection: close\r\n");
  if (response.code == 405) absl::StrAppend(&text, "Allow: GET, HEAD\r\n");
  absl::StrAppend(&text, "\r\n");
  if (!head) absl::StrAppend(&text, response.body);
  return text;
}

absl::StatusOr<StatusAddress> ParseStatusAddress(absl::string_view text) {
  auto bad = [&](absl::string_view why) {
    return absl::InvalidArgumentError(absl::StrCat(
        "--status-listen '", text, "' is not PORT, :PORT, HOST:PORT or [IPV6]:PORT (", why, ")"));
  };
  StatusAddress address;
  absl::string_view port = text;
  if (!text.empty() && text.front() == '[') {
    const size_t close = text.find("]:");
    if (close == absl::string_view::npos) return bad("an IPv6 address needs [ADDRESS]:PORT");
    address.host = std::string(text.substr(1, close - 1));
    port = text.substr(close + 2);
  } else if (const size_t colon = text.rfind(':'); colon != absl::string_view::npos) {
    address.host = std::string(text.substr(0, colon));
    port = text.substr(colon + 1);
    if (address.host.find(':') != std::string::npos) {
      return bad("put an IPv6 address in brackets");
    }
  }
  if (address.host.empty()) address.host = "127.0.0.1";
  int number = 0;
  if (port.empty() || !absl::SimpleAtoi(port, &number) || number < 0 || number > 65535 ||
      !absl::ascii_isdigit(static_cast<unsigned char>(port.front()))) {
    return bad("the port is a number from 0 to 65535");
  }
  address.port = number;
  return address;
}

absl::StatusOr<std::unique_ptr<StatusServer>> StatusServer::Start(absl::string_view text,
                                                                  HttpHandler handler,
                                                                  StatusServerOptions options) {
  absl::StatusOr<StatusAddress> address = ParseStatusAddress(text);
  if (!address.ok()) return address.status();
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(address->port);
  if (int e = getaddrinfo(address->host.c_str(), port.c_str(), &hints, &found); e != 0) {
    return absl::FailedPreconditionError(absl::StrCat("cannot serve status on ", address->host, ":",
                                                      address->port, " (--status-listen ", text,
                                                      "): ", gai_strerror(e)));
  }
  int fd = -1;
  std::string why = "no address";
  for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
    fd = socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      why = std::strerror(errno);
      continue;
    }
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    if (bind(fd, a->ai_addr, a->ai_addrlen) == 0 && listen(fd, 64) == 0) break;
    why = std::strerror(errno);
    close(fd);
    fd = -1;
  }
  freeaddrinfo(found);
  if (fd < 0) {
    return absl::FailedPreconditionError(absl::StrCat("cannot serve status on ", address->host, ":",
                                                      address->port, " (--status-listen ", text,
                                                      "): ", why));
  }
  sockaddr_storage bound{};
  socklen_t size = sizeof(bound);
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &size);
  const int bound_port = bound.ss_family == AF_INET6
                             ? ntohs(reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port)
                             : ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  const int wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake < 0) {
    const std::string error = std::strerror(errno);
    close(fd);
    return absl::FailedPreconditionError(absl::StrCat("cannot serve status: eventfd: ", error));
  }
  std::unique_ptr<StatusServer> server(new StatusServer);
  server->handler_ = std::move(handler);
  server->options_ = options;
  server->listen_fd_ = fd;
  server->wake_fd_ = wake;
  server->port_ = bound_port;
  server->address_ = address->host.find(':') != std::string::npos
                         ? absl::StrCat("[", address->host, "]:", bound_port)
                         : absl::StrCat(address->host, ":", bound_port);
  server->thread_ = std::thread([s = server.get()] { s->Serve(); });
  return server;
}

StatusServer::~StatusServer() {
  if (thread_.joinable()) {
    const uint64_t one = 1;
    (void)!write(wake_fd_, &one, sizeof(one));
    thread_.join();
  }
  CloseFd(listen_fd_);
  CloseFd(wake_fd_);
}

void StatusServer::Serve() {
  std::list<Connection> connections;
  std::vector<pollfd> fds;
  std::vector<Connection*> polled;
  const auto timeout = absl::ToChronoMilliseconds(options_.request_timeout);
  // Out of descriptors: the listening socket stays readable, so it is left alone for a while
  // rather than polled in a busy loop.
  Clock::time_point accept_after = Clock::time_point::min();
  while (true) {
    fds.clear();
    polled.clear();
    fds.push_back({wake_fd_, POLLIN, 0});
    const bool accepting = Clock::now() >= accept_after;
    fds.push_back({listen_fd_, static_cast<short>(accepting ? POLLIN : 0), 0});
    Clock::time_point next = accepting ? Clock::time_point::max() : accept_after;
    for (Connection& c : connections) {
      fds.push_back({c.fd, static_cast<short>(c.answered ? POLLOUT : POLLIN), 0});
      polled.push_back(&c);
      next = std::min(next, c.deadline);
    }
    int wait_ms = -1;
    if (next != Clock::time_point::max()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(next - Clock::now());
      wait_ms = static_cast<int>(std::max<int64_t>(0, left.count()) + 1);
    }
    const int ready = poll(fds.data(), fds.size(), wait_ms);
    if (ready < 0 && errno != EINTR) {
      log::Error(log::Component::kWorker, "status server stopped: poll: %s", std::strerror(errno));
      break;
    }
    if (fds[0].revents != 0) break;  // the destructor
    const Clock::time_point now = Clock::now();
    for (size_t i = 0; i < polled.size(); ++i) {
      Connection& c = *polled[i];
      const short events = fds[i + 2].revents;
      if (!c.answered && (events & (POLLIN | POLLHUP | POLLERR))) {
        char buf[4096];
        const ssize_t n = recv(c.fd, buf, sizeof(buf), 0);
        if (n <= 0) {
          if (n < 0 && (errno == EAGAIN || errno == EINTR)) continue;
          c.deadline = Clock::time_point::min();  // closed or broken before a whole request
          c.answered = true;
          c.out.clear();
          continue;
        }
        c.in.append(buf, static_cast<size_t>(n));
        if (RequestComplete(c.in)) {
          c.out = Answer(c.in, handler_);
          c.answered = true;
        } else if (c.in.size() > options_.max_request_bytes) {
          c.out = FormatHttpResponse(Plain(431, "request too large\n"), false);
          c.answered = true;
        }
      } else if (c.answered && (events & (POLLOUT | POLLHUP | POLLERR))) {
        if (events & (POLLHUP | POLLERR)) {
          c.sent = c.out.size();
          continue;
        }
        const ssize_t n = send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
        if (n > 0) {
          c.sent += static_cast<size_t>(n);
        } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
          c.sent = c.out.size();  // the client is gone
        }
      }
    }
    // Done, broken or out of time: closed. A slow request gets 408 if the socket takes it now.
    for (auto it = connections.begin(); it != connections.end();) {
      Connection& c = *it;
      bool done = c.answered && c.sent >= c.out.size();
      if (!done && now >= c.deadline) {
        if (!c.answered && c.deadline != Clock::time_point::min()) {
          const std::string late = FormatHttpResponse(Plain(408, "request timeout\n"), false);
          (void)!send(c.fd, late.data(), late.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        }
        done = true;
      }
      if (done) {
        close(c.fd);
        it = connections.erase(it);
      } else {
        ++it;
      }
    }
    if (fds[1].revents & POLLIN) {
      while (true) {
        const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
          if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
            accept_after = Clock::now() + std::chrono::milliseconds(100);
          }
          break;  // EAGAIN: every waiting connection taken
        }
        if (static_cast<int>(connections.size()) >= options_.max_connections) {
          const std::string busy = FormatHttpResponse(Plain(503, "too many connections\n"), false);
          (void)!send(fd, busy.data(), busy.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
          close(fd);
          continue;
        }
        Connection c;
        c.fd = fd;
        c.deadline = Clock::now() + timeout;
        connections.push_back(std::move(c));
      }
    }
  }
  for (Connection& c : connections) close(c.fd);
}

}  // namespace tessera::worker
