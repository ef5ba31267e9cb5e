// Who may call a worker, as both ends see it (docs/security.md): the shared token every call
// carries as `authorization: Bearer <token>`, and the host's side of it, a channel to a worker
// with TLS and that token as the host's environment configures them.
//
// A worker runs the code its host sends, so the host never reaches a worker on another machine
// without TLS and a token; unix sockets and loopback TCP stay plain unless configured otherwise.
#ifndef TESSERA_SCHEDULER_TRANSPORT_CREDENTIALS_H_
#define TESSERA_SCHEDULER_TRANSPORT_CREDENTIALS_H_

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace tessera::transport {

// The metadata key of the token, and the scheme before it (RFC 6750 spelling).
inline constexpr char kAuthorizationKey[] = "authorization";
inline constexpr char kBearerPrefix[] = "Bearer ";

// The host's settings (docs/security.md "Host").
inline constexpr char kTlsCaEnv[] = "TESSERA_TLS_CA";                   // PEM roots to trust
inline constexpr char kTlsCertEnv[] = "TESSERA_TLS_CERT";               // client certificate
inline constexpr char kTlsKeyEnv[] = "TESSERA_TLS_KEY";                 // its private key
inline constexpr char kTlsServerNameEnv[] = "TESSERA_TLS_SERVER_NAME";  // name to verify
inline constexpr char kTokenEnv[] = "TESSERA_TOKEN";
inline constexpr char kTokenFileEnv[] = "TESSERA_TOKEN_FILE";

// The contents of a file; FAILED_PRECONDITION naming `what` (the setting or flag, so the user
// knows which one to fix) and `path` when it cannot be read.
absl::StatusOr<std::string> ReadWholeFile(const std::string& path, absl::string_view what);

// A PEM file, which must hold `label` (e.g. "-----BEGIN CERTIFICATE"): gRPC reports a malformed
// one only as a failed handshake, much later and without naming the file.
absl::StatusOr<std::string> ReadPemFile(const std::string& path, absl::string_view what,
                                        absl::string_view label);

// A token as both ends read it from a file: the first line, surrounding whitespace trimmed.
// FAILED_PRECONDITION, naming `path`, if the file cannot be read or the token is not valid.
absl::StatusOr<std::string> ReadTokenFile(const std::string& path);

// OK for a non-empty token of printable ASCII without spaces (what gRPC metadata can carry).
absl::Status ValidateToken(absl::string_view token);

// True for unix sockets, localhost, 127.0.0.0/8 and ::1: addresses only this machine can serve.
// The same rule as the worker's (worker/service/listen_address.h), which this library cannot use.
bool IsLocalAddress(absl::string_view address);

// A channel with `args` to the worker at `address` ("HOST:PORT", "[IPV6]:PORT" or "unix:PATH"),
// configured from the environment at each call:
// - TCP addresses use TLS when $TESSERA_TLS_CA is set, trusting the certificates in that PEM file,
//   presenting $TESSERA_TLS_CERT/$TESSERA_TLS_KEY when set (mutual TLS) and verifying the
//   worker's certificate against $TESSERA_TLS_SERVER_NAME instead of the host part when set;
// - unix sockets, and loopback TCP without $TESSERA_TLS_CA, are plain;
// - $TESSERA_TOKEN, or the first line of $TESSERA_TOKEN_FILE, goes with every call when set.
// UNAUTHENTICATED (RT_ERROR_AUTHENTICATION_FAILED in the C API), before anything connects, for an
// address off this machine without TLS and a token (the message names the address and what to
// set), or for settings that cannot be used (naming the setting and its file).
absl::StatusOr<std::shared_ptr<grpc::Channel>> CreateWorkerChannel(const std::string& address,
                                                                   grpc::ChannelArguments args);

}  // namespace tessera::transport

#endif  // TESSERA_SCHEDULER_TRANSPORT_CREDENTIALS_H_
