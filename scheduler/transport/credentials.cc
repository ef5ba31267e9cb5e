#include "transport/credentials.h"

#include <arpa/inet.h>
#include <grpcpp/support/client_interceptor.h>
#include <grpcpp/support/interceptor.h>
#include <netinet/in.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace tessera::transport {
namespace {

std::string Env(const char* name) {
  const char* value = std::getenv(name);
  return value == nullptr ? "" : value;
}

absl::StatusOr<std::string> TokenFromEnvironment() {
  const std::string token = Env(kTokenEnv);
  const std::string file = Env(kTokenFileEnv);
  if (!token.empty() && !file.empty()) {
    return absl::FailedPreconditionError(
        absl::StrCat("both ", kTokenEnv, " and ", kTokenFileEnv, " are set; set one"));
  }
  if (!file.empty()) return ReadTokenFile(file);
  if (token.empty()) return std::string();
  const std::string trimmed(absl::StripAsciiWhitespace(token));
  if (absl::Status s = ValidateToken(trimmed); !s.ok()) {
    return absl::FailedPreconditionError(absl::StrCat(kTokenEnv, ": ", s.message()));
  }
  return trimmed;
}

// gRPC sends call credentials (the TLS path's token) over secure channels only, so a plain
// loopback or unix channel carries the token as metadata this interceptor adds to every call.
class TokenInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit TokenInterceptor(std::string value) : value_(std::move(value)) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      methods->GetSendInitialMetadata()->emplace(kAuthorizationKey, value_);
    }
    methods->Proceed();
  }

 private:
  const std::string value_;
};

class TokenInterceptorFactory final : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit TokenInterceptorFactory(const std::string& token)
      : value_(absl::StrCat(kBearerPrefix, token)) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(
      grpc::experimental::ClientRpcInfo* info) override {
    return new TokenInterceptor(value_);
  }

 private:
  const std::string value_;
};

// OK when the PEM `key` is the private key of the first certificate in the PEM `cert`.
absl::Status CheckKeyMatchesCertificate(const std::string& cert, const std::string& key) {
  BIO* cert_bio = BIO_new_mem_buf(cert.data(), static_cast<int>(cert.size()));
  BIO* key_bio = BIO_new_mem_buf(key.data(), static_cast<int>(key.size()));
  X509* x509 =
      cert_bio != nullptr ? PEM_read_bio_X509(cert_bio, nullptr, nullptr, nullptr) : nullptr;
  EVP_PKEY* pkey =
      key_bio != nullptr ? PEM_read_bio_PrivateKey(key_bio, nullptr, nullptr, nullptr) : nullptr;
  absl::Status status;
  if (x509 == nullptr) {
    status = absl::FailedPreconditionError("the certificate cannot be parsed");
  } else if (pkey == nullptr) {
    status = absl::FailedPreconditionError(
        "the private key cannot be parsed (or is encrypted; give an unencrypted key)");
  } else if (X509_check_private_key(x509, pkey) != 1) {
    status = absl::FailedPreconditionError("the key does not belong to the certificate");
  }
  ERR_clear_error();
  EVP_PKEY_free(pkey);
  X509_free(x509);
  BIO_free(key_bio);
  BIO_free(cert_bio);
  return status;
}

}  // namespace

absl::StatusOr<std::string> ReadWholeFile(const std::string& path, absl::string_view what) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    return absl::FailedPreconditionError(
        absl::StrCat("cannot read ", what, " file ", path, ": ", std::strerror(errno)));
  }
  std::string contents;
  char block[4096];
  size_t n;
  while ((n = std::fread(block, 1, sizeof block, file)) > 0) contents.append(block, n);
  const bool failed = std::ferror(file) != 0;
  std::fclose(file);
  if (failed) {
    return absl::FailedPreconditionError(absl::StrCat("cannot read ", what, " file ", path));
  }
  return contents;
}

absl::StatusOr<std::string> ReadPemFile(const std::string& path, absl::string_view what,
                                        absl::string_view label) {
  absl::StatusOr<std::string> pem = ReadWholeFile(path, what);
  if (pem.ok() && !absl::StrContains(*pem, label)) {
    return absl::FailedPreconditionError(
        absl::StrCat(what, " file ", path, " holds no PEM \"", label, "\""));
  }
  return pem;
}

absl::Status ValidateToken(absl::string_view token) {
  if (token.empty()) return absl::FailedPreconditionError("the token is empty");
  for (char c : token) {
    // Printable ASCII without space: what a metadata value carries unchanged.
    if (c <= ' ' || c > '~') {
      return absl::FailedPreconditionError(
          "the token holds a character other than printable ASCII (no spaces)");
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> ReadTokenFile(const std::string& path) {
  absl::StatusOr<std::string> contents = ReadWholeFile(path, "token");
  if (!contents.ok()) return contents.status();
  absl::string_view first_line = *contents;
  first_line = first_line.substr(0, first_line.find('\n'));
  const std::string token(absl::StripAsciiWhitespace(first_line));
  if (absl::Status s = ValidateToken(token); !s.ok()) {
    return absl::FailedPreconditionError(absl::StrCat("token file ", path, ": ", s.message()));
  }
  return token;
}

bool IsLocalAddress(absl::string_view address) {
  if (absl::StartsWith(address, "unix:")) return true;
  std::string host;
  if (absl::StartsWith(address, "[")) {
    const size_t close = address.find(']');
    if (close == absl::string_view::npos) return false;
    host = std::string(address.substr(1, close - 1));
  } else {
    const size_t colon = address.rfind(':');
    host = std::string(colon == absl::string_view::npos ? address : address.substr(0, colon));
  }
  if (absl::EqualsIgnoreCase(host, "localhost")) return true;
  in_addr v4;
  if (inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6;
  if (inet_pton(AF_INET6, host.c_str(), &v6) == 1) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    if (IN6_IS_ADDR_V4MAPPED(&v6)) return v6.s6_addr[12] == 127;
  }
  return false;
}

namespace {

// CreateWorkerChannel, with every problem of the host's settings as FAILED_PRECONDITION.
absl::StatusOr<std::shared_ptr<grpc::Channel>> CreateChannel(const std::string& address,
                                                             grpc::ChannelArguments args) {
  absl::StatusOr<std::string> token = TokenFromEnvironment();
  if (!token.ok()) return token.status();
  const std::string ca_file = Env(kTlsCaEnv);
  const bool unix_socket = absl::StartsWith(address, "unix:");
  // TLS over a unix socket protects nothing that the socket's file permissions do not.
  const bool tls = !ca_file.empty() && !unix_socket;

  if (!IsLocalAddress(address) && (!tls || token->empty())) {
    std::vector<std::string> missing;
    if (!tls) absl::StrAppend(&missing.emplace_back(), kTlsCaEnv, " (the CA of its certificate)");
    if (token->empty()) absl::StrAppend(&missing.emplace_back(), kTokenEnv, " or ", kTokenFileEnv);
    return absl::FailedPreconditionError(absl::StrCat(
        "worker ", address,
        " is not on this machine, and a worker runs the code its host sends, so Tessera reaches it "
        "only over TLS with a token: set ",
        absl::StrJoin(missing, " and "), " (see docs/security.md)"));
  }

  if (!tls) {
    if (token->empty()) {
      return grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
    }
    std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> factories;
    factories.push_back(std::make_unique<TokenInterceptorFactory>(*token));
    return grpc::experimental::CreateCustomChannelWithInterceptors(
        address, grpc::InsecureChannelCredentials(), args, std::move(factories));
  }

  grpc::SslCredentialsOptions ssl;
  absl::StatusOr<std::string> roots = ReadPemFile(ca_file, kTlsCaEnv, "-----BEGIN CERTIFICATE");
  if (!roots.ok()) return roots.status();
  ssl.pem_root_certs = *std::move(roots);
  const std::string cert_file = Env(kTlsCertEnv);
  const std::string key_file = Env(kTlsKeyEnv);
  if (cert_file.empty() != key_file.empty()) {
    return absl::FailedPreconditionError(
        absl::StrCat(kTlsCertEnv, " and ", kTlsKeyEnv, " go together; one is unset"));
  }
  if (!cert_file.empty()) {
    absl::StatusOr<std::string> cert =
        ReadPemFile(cert_file, kTlsCertEnv, "-----BEGIN CERTIFICATE");
    if (!cert.ok()) return cert.status();
    absl::StatusOr<std::string> key = ReadPemFile(key_file, kTlsKeyEnv, "PRIVATE KEY-----");
    if (!key.ok()) return key.status();
    // gRPC takes a key that does not belong to the certificate and then fails every connection
    // with "empty address list": check the pair here, where the message can name the files.
    if (absl::Status pair = CheckKeyMatchesCertificate(*cert, *key); !pair.ok()) {
      return absl::FailedPreconditionError(absl::StrCat(
          kTlsKeyEnv, " ", key_file, " and ", kTlsCertEnv, " ", cert_file, ": ", pair.message()));
    }
    ssl.pem_cert_chain = *std::move(cert);
    ssl.pem_private_key = *std::move(key);
  }
  // Certificates are often issued to a name while hosts list workers by address.
  if (const std::string name = Env(kTlsServerNameEnv); !name.empty()) {
    args.SetSslTargetNameOverride(name);
  }
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::SslCredentials(ssl);
  if (!token->empty()) {
    // Sent as `authorization: Bearer <token>`, and only ever over this TLS connection.
    credentials =
        grpc::CompositeChannelCredentials(credentials, grpc::AccessTokenCredentials(*token));
  }
  return grpc::CreateCustomChannel(address, credentials, args);
}

}  // namespace

absl::StatusOr<std::shared_ptr<grpc::Channel>> CreateWorkerChannel(const std::string& address,
                                                                   grpc::ChannelArguments args) {
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = CreateChannel(address, std::move(args));
  // The host lacks credentials it needs for this worker (TLS and a token off this machine), or
  // cannot use the ones it was given: UNAUTHENTICATED, as a worker refusing a missing or wrong
  // token answers, which the C API reports as RT_ERROR_AUTHENTICATION_FAILED. (FAILED_PRECONDITION
  // read as RT_ERROR_INVALID_CONTEXT, which sends the user looking at the context.)
  if (!channel.ok() && channel.status().code() == absl::StatusCode::kFailedPrecondition) {
    return absl::UnauthenticatedError(channel.status().message());
  }
  return channel;
}

}  // namespace tessera::transport
