#include "device_spec.h"

#include <cstdlib>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "status.h"

namespace tessera::api {
namespace {

constexpr int kMaxLocalWorkers = 4096;
// sockaddr_un's sun_path holds 108 bytes with the terminating NUL; gRPC refuses longer paths with
// an unhelpful "Failed to create secure client channel" (RT_ERROR_UNKNOWN) at the first launch.
constexpr size_t kMaxUnixSocketPath = 107;

bool ParseBoundedInt(absl::string_view text, int min, int max, int* out) {
  if (text.empty() || text.size() > 9) return false;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  int value = 0;
  if (!absl::SimpleAtoi(text, &value) || value < min || value > max) return false;
  *out = value;
  return true;
}

bool IsHostName(absl::string_view host) {
  if (host.empty() || host.size() > 253) return false;
  for (absl::string_view label : absl::StrSplit(host, '.')) {
    if (label.empty() || label.size() > 63 || label.front() == '-' || label.back() == '-') {
      return false;
    }
    for (char c : label) {
      if (!absl::ascii_isalnum(static_cast<unsigned char>(c)) && c != '-') return false;
    }
  }
  return true;
}

bool IsIpv6Literal(absl::string_view host) {
  if (host.size() < 2 || host.find(':') == absl::string_view::npos) return false;
  for (char c : host) {
    if (!absl::ascii_isxdigit(static_cast<unsigned char>(c)) && c != ':' && c != '.') return false;
  }
  return true;
}

absl::Status EntryError(absl::string_view spec, size_t index, absl::string_view entry,
                        absl::string_view why) {
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("device spec '", spec, "': entry ", index + 1,
                                                      " '", entry, "' ", why));
}

absl::StatusOr<DeviceSpecEntry> ParseEntry(absl::string_view spec, size_t index,
                                           absl::string_view entry) {
  DeviceSpecEntry out;
  if (entry.empty()) return EntryError(spec, index, entry, "is empty");
  if (entry == "inproc") return out;
  if (absl::StartsWith(entry, "local:")) {
    out.type = DeviceSpecEntry::Type::kLocal;
    if (!ParseBoundedInt(entry.substr(6), 1, kMaxLocalWorkers, &out.count)) {
      return EntryError(
          spec, index, entry,
          absl::StrCat("needs a worker count from 1 to ", kMaxLocalWorkers, " (local:N)"));
    }
    return out;
  }
  if (absl::StartsWith(entry, "unix:")) {
    out.type = DeviceSpecEntry::Type::kUnix;
    out.path = std::string(entry.substr(5));
    if (out.path.empty()) return EntryError(spec, index, entry, "needs a socket path (unix:PATH)");
    if (out.path.size() > kMaxUnixSocketPath) {
      return EntryError(
          spec, index, entry,
          absl::StrCat("has a socket path of ", out.path.size(),
                       " bytes; Unix socket paths hold at most ", kMaxUnixSocketPath));
    }
    return out;
  }
  size_t colon = entry.rfind(':');
  if (colon == absl::string_view::npos) {
    return EntryError(spec, index, entry, "is not one of inproc, local:N, HOST:PORT or unix:PATH");
  }
  absl::string_view host = entry.substr(0, colon);
  absl::string_view port = entry.substr(colon + 1);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
    if (!IsIpv6Literal(host)) {
      return EntryError(spec, index, entry, "has a malformed IPv6 address");
    }
  } else if (!IsHostName(host)) {
    return EntryError(spec, index, entry,
                      "is not one of inproc, local:N, HOST:PORT or unix:PATH (bad host name)");
  }
  out.type = DeviceSpecEntry::Type::kTcp;
  out.host = std::string(host);
  if (!ParseBoundedInt(port, 1, 65535, &out.port)) {
    return EntryError(spec, index, entry, "needs a port from 1 to 65535 (HOST:PORT)");
  }
  return out;
}

}  // namespace

std::string DeviceSpecEntry::ToString() const {
  switch (type) {
    case Type::kInproc:
      return "inproc";
    case Type::kLocal:
      return absl::StrCat("local:", count);
    case Type::kTcp:
      if (host.find(':') != std::string::npos) return absl::StrCat("[", host, "]:", port);
      return absl::StrCat(host, ":", port);
    case Type::kUnix:
      return absl::StrCat("unix:", path);
  }
  return "";
}

absl::StatusOr<std::vector<DeviceSpecEntry>> ParseDeviceSpec(absl::string_view spec) {
  if (absl::StripAsciiWhitespace(spec).empty()) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat("device spec '", spec,
                     "' is empty (expected e.g. inproc, local:4, host:5000, unix:PATH)"));
  }
  std::vector<DeviceSpecEntry> entries;
  size_t index = 0;
  for (absl::string_view raw : absl::StrSplit(spec, ',')) {
    auto entry = ParseEntry(spec, index++, absl::StripAsciiWhitespace(raw));
    if (!entry.ok()) return entry.status();
    entries.push_back(*std::move(entry));
  }
  return entries;
}

std::string DeviceSpecFromEnvironment(const std::string& fallback) {
  const char* env = std::getenv("TESSERA_DEVICES");
  if (env == nullptr || absl::StripAsciiWhitespace(env).empty()) return fallback;
  return env;
}

}  // namespace tessera::api
