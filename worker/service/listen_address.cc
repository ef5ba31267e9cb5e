#include "listen_address.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <cstring>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"

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
