#include "auth.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <utility>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "listen_address.h"
#include "transport/credentials.h"

namespace tessera::worker {

absl::StatusOr<std::string> ResolveToken(const std::string& token_file, const char* env_token) {
  const bool from_env = env_token != nullptr && *env_token != '\0';
  if (!token_file.empty() && from_env) {
    // Two sources that may disagree: refusing is better than guessing which one the hosts use.
    return absl::FailedPreconditionError(
        absl::StrCat("both --token-file and ", kWorkerTokenEnv, " are given; give one"));
  }
  if (!token_file.empty()) return transport::ReadTokenFile(token_file);
  if (!from_env) return std::string();
  const std::string token(absl::StripAsciiWhitespace(env_token));
  if (absl::Status s = transport::ValidateToken(token); !s.ok()) {
    return absl::FailedPreconditionError(absl::StrCat(kWorkerTokenEnv, ": ", s.message()));
  }
  return token;
}

absl::Status CheckListenPolicy(absl::string_view listen, const SecurityOptions& options,
                               bool has_token) {
  if (IsLoopbackAddress(listen)) return absl::OkStatus();
  std::vector<std::string> missing;
  if (options.tls_cert_file.empty()) missing.push_back("--tls-cert FILE");
  if (options.tls_key_file.empty()) missing.push_back("--tls-key FILE");
  if (!has_token) {
    missing.push_back(absl::StrCat("a token (--token-file FILE or ", kWorkerTokenEnv, ")"));
  }
  if (missing.empty()) return absl::OkStatus();
  return absl::FailedPreconditionError(absl::StrCat(
      "refusing to listen on ", listen,
      ": it is not a loopback address, and a worker runs whatever code its host sends, so other "
      "machines may reach it only over TLS with a token. Missing: ",
      absl::StrJoin(missing, ", "),
      ". (--allow-remote alone no longer allows this; see docs/security.md.)"));
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const SecurityOptions& options) {
  if (!options.tls()) {
    if (!options.tls_client_ca_file.empty()) {
      return absl::FailedPreconditionError("--tls-client-ca needs --tls-cert and --tls-key");
    }
    return grpc::InsecureServerCredentials();
  }
  if (options.tls_cert_file.empty() || options.tls_key_file.empty()) {
    return absl::FailedPreconditionError("--tls-cert and --tls-key go together; one is missing");
  }
  absl::StatusOr<std::string> cert =
      transport::ReadPemFile(options.tls_cert_file, "--tls-cert", "-----BEGIN CERTIFICATE");
  if (!cert.ok()) return cert.status();
  absl::StatusOr<std::string> key =
      transport::ReadPemFile(options.tls_key_file, "--tls-key", "PRIVATE KEY-----");
  if (!key.ok()) return key.status();
  const bool verify_clients = !options.tls_client_ca_file.empty();
  grpc::SslServerCredentialsOptions ssl(
      verify_clients ? GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY
                     : GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE);
  if (verify_clients) {
    absl::StatusOr<std::string> roots = transport::ReadPemFile(
        options.tls_client_ca_file, "--tls-client-ca", "-----BEGIN CERTIFICATE");
    if (!roots.ok()) return roots.status();
    ssl.pem_root_certs = *std::move(roots);
  }
  ssl.pem_key_cert_pairs.push_back({*std::move(key), *std::move(cert)});
  return grpc::SslServerCredentials(ssl);
}

bool TokenMatches(absl::string_view expected, absl::string_view presented) {
  if (expected.empty()) return false;
  // No early exit: every byte of `presented` is compared, wherever the first difference is.
  // Indexing `expected` modulo its size keeps the loop's length that of the guess, which the
  // caller knows anyway, rather than that of the secret.
  unsigned char difference = expected.size() == presented.size() ? 0 : 1;
  for (size_t i = 0; i < presented.size(); ++i) {
    difference |= static_cast<unsigned char>(presented[i]) ^
                  static_cast<unsigned char>(expected[i % expected.size()]);
  }
  return difference == 0;
}

absl::Status CheckAuthorization(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata,
                                absl::string_view expected) {
  auto [first, last] = metadata.equal_range(transport::kAuthorizationKey);
  if (first == last) {
    return absl::UnauthenticatedError(
        "authentication failed: no token (the host sets TESSERA_TOKEN or TESSERA_TOKEN_FILE)");
  }
  if (std::next(first) != last) {
    return absl::UnauthenticatedError("authentication failed: more than one authorization entry");
  }
  const absl::string_view value(first->second.data(), first->second.size());
  const absl::string_view scheme(transport::kBearerPrefix);
  if (value.size() < scheme.size() ||
      !absl::EqualsIgnoreCase(value.substr(0, scheme.size()), scheme)) {
    return absl::UnauthenticatedError("authentication failed: authorization is not a Bearer token");
  }
  if (!TokenMatches(expected, value.substr(scheme.size()))) {
    return absl::UnauthenticatedError("authentication failed: wrong token");
  }
  return absl::OkStatus();
}

AuthenticatedWorker::AuthenticatedWorker(v1::Worker::Service* inner, std::string token, Log log)
    : inner_(inner), token_(std::move(token)), log_(std::move(log)) {}

grpc::Status AuthenticatedWorker::Admit(grpc::ServerContext* context,
                                        absl::string_view method) const {
  absl::Status status = CheckAuthorization(context->client_metadata(), token_);
  if (status.ok()) return grpc::Status::OK;
  log_(absl::StrCat("refused ", method, " from ", context->peer(), ": ", status.message()));
  return grpc::Status(grpc::StatusCode::UNAUTHENTICATED, std::string(status.message()));
}

grpc::Status AuthenticatedWorker::Apply(grpc::ServerContext* context,
                                        grpc::ServerReader<v1::ApplyChunk>* reader,
                                        v1::ApplyReply* reply) {
  if (grpc::Status s = Admit(context, "Apply"); !s.ok()) return s;
  return inner_->Apply(context, reader, reply);
}

grpc::Status AuthenticatedWorker::Launch(grpc::ServerContext* context,
                                         const v1::LaunchRequest* request,
                                         grpc::ServerWriter<v1::TileResult>* writer) {
  if (grpc::Status s = Admit(context, "Launch"); !s.ok()) return s;
  return inner_->Launch(context, request, writer);
}

grpc::Status AuthenticatedWorker::Health(grpc::ServerContext* context,
                                         const v1::HealthRequest* request, v1::HealthReply* reply) {
  if (grpc::Status s = Admit(context, "Health"); !s.ok()) return s;
  return inner_->Health(context, request, reply);
}

grpc::Status AuthenticatedWorker::EndSession(grpc::ServerContext* context,
                                             const v1::EndSessionRequest* request,
                                             v1::EndSessionReply* reply) {
  if (grpc::Status s = Admit(context, "EndSession"); !s.ok()) return s;
  return inner_->EndSession(context, request, reply);
}

}  // namespace tessera::worker
