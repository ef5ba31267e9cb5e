#include "listen_address.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"

namespace tessera::worker {
namespace {

// The host part, without IPv6 brackets, and everything before the port separator.
struct Split {
  std::string host;
  absl::string_view host_part;  // as written, brackets included
};

Split SplitHost(absl::string_view listen) {
  Split s;
  if (absl::StartsWith(listen, "[")) {
    size_t close = listen.find(']');
    if (close != absl::string_view::npos) {
      s.host = std::string(listen.substr(1, close - 1));
      s.host_part = listen.substr(0, close + 1);
      return s;
    }
  }
  size_t colon = listen.rfind(':');
  s.host_part = colon == absl::string_view::npos ? listen : listen.substr(0, colon);
  s.host = std::string(s.host_part);
  return s;
}

}  // namespace

absl::Status CheckListenAddress(absl::string_view listen) {
  if (absl::StartsWith(listen, "unix:")) {
    const size_t path = listen.size() - 5;
    const size_t max_path = sizeof(sockaddr_un{}.sun_path) - 1;  // and a terminating NUL
    if (path == 0 || path > max_path) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--listen ", listen, ": a unix socket path needs 1 to ", max_path, " bytes, not ", path));
    }
    return absl::OkStatus();
  }
  const Split split = SplitHost(listen);
  absl::string_view port = listen.substr(split.host_part.size());
  const bool bracketed = absl::StartsWith(split.host_part, "[");
  int value = -1;
  if (!absl::ConsumePrefix(&port, ":") || port.empty() || port.size() > 5 ||
      !std::all_of(port.begin(), port.end(), absl::ascii_isdigit) ||
      !absl::SimpleAtoi(port, &value) || value > 65535 ||
      (!bracketed && split.host.find(':') != std::string::npos)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--listen ", listen,
                     ": expected HOST:PORT or [IPV6]:PORT with a port from 0 to 65535 (0: any "
                     "free one), or unix:PATH"));
  }
  return absl::OkStatus();
}

absl::Status CheckUnixSocketNotInUse(absl::string_view listen) {
  if (!absl::StartsWith(listen, "unix:")) return absl::OkStatus();
  const std::string path(listen.substr(5));
  sockaddr_un address{};
  struct stat st {};
  if (path.empty() || path.size() >= sizeof(address.sun_path)) return absl::OkStatus();
  // Something else under that name (a file, a directory, a symbolic link to nothing) is never
  // replaced, and binding there fails: say so rather than leave it to gRPC's "No address added".
  if (struct stat own{};
      lstat(path.c_str(), &own) == 0 && (stat(path.c_str(), &st) != 0 || !S_ISSOCK(st.st_mode))) {
    return absl::FailedPreconditionError(
        absl::StrCat("--listen ", listen, ": ", path, " exists and is not a socket",
                     S_ISLNK(own.st_mode) ? " (a symbolic link to no socket)" : "",
                     "; give a path where nothing is, or remove it"));
  }
  if (stat(path.c_str(), &st) != 0 || !S_ISSOCK(st.st_mode)) return absl::OkStatus();
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return absl::OkStatus();
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.data(), path.size());
  // Refused: nobody listens (a stale socket). Accepted, or a full backlog: someone does.
  const bool live =
      connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0 ||
      errno == EAGAIN;
  close(fd);
  if (!live) return absl::OkStatus();
  return absl::FailedPreconditionError(
      absl::StrCat("--listen ", listen,
                   ": another process is listening on that socket (a worker already "
                   "running there?); a stale socket nobody listens on would be replaced"));
}

absl::Status CheckCanBind(absl::string_view listen) {
  if (absl::StartsWith(listen, "unix:")) {
    std::string dir(listen.substr(5));
    const size_t slash = dir.rfind('/');
    dir = slash == std::string::npos ? "." : slash == 0 ? "/" : dir.substr(0, slash);
    struct stat st {};
    int error = 0;
    if (stat(dir.c_str(), &st) != 0) {
      error = errno;
    } else if (!S_ISDIR(st.st_mode)) {
      error = ENOTDIR;
    } else if (access(dir.c_str(), W_OK | X_OK) != 0) {
      error = errno;
    }
    if (error != 0) {
      return absl::FailedPreconditionError(absl::StrCat(
          "--listen ", listen, ": cannot create the socket in ", dir, ": ", std::strerror(error)));
    }
    return absl::OkStatus();
  }
  const Split split = SplitHost(listen);
  const std::string port(listen.substr(split.host_part.size() + 1));
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  if (const int rc = getaddrinfo(split.host.empty() ? nullptr : split.host.c_str(), port.c_str(),
                                 &hints, &found);
      rc != 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("--listen ", listen, ": cannot resolve ", split.host, ": ", gai_strerror(rc)));
  }
  int error = 0;
  for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
    const int fd = socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));  // as gRPC binds
    const bool bound = bind(fd, a->ai_addr, a->ai_addrlen) == 0;
    if (!bound) error = errno;
    close(fd);
    if (bound) {
      freeaddrinfo(found);
      return absl::OkStatus();
    }
  }
  freeaddrinfo(found);
  return absl::FailedPreconditionError(absl::StrCat(
      "--listen ", listen, ": cannot bind: ", std::strerror(error),
      error == EADDRINUSE ? " (another process listens on that port; port 0 picks a free one)"
                          : ""));
}

bool IsLoopbackAddress(absl::string_view listen) {
  if (absl::StartsWith(listen, "unix:")) return true;
  const std::string host = SplitHost(listen).host;
  if (absl::EqualsIgnoreCase(host, "localhost")) return true;
  in_addr v4;
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) {
    return (ntohl(v4.s_addr) >> 24) == 127;
  }
  in6_addr v6;
  if (inet_pton(AF_INET6, host.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    if (IN6_IS_ADDR_V4MAPPED(&v6)) return v6.s6_addr[12] == 127;
  }
  return false;
}

std::string ResolvedListenAddress(absl::string_view listen, int bound_port) {
  if (absl::StartsWith(listen, "unix:")) return std::string(listen);
  return absl::StrCat(SplitHost(listen).host_part, ":", bound_port);
}

}  // namespace tessera::worker
