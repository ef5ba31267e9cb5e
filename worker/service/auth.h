// Who may use a worker (docs/security.md). A worker runs the program modules its host sends, so
// one that other machines can reach serves only over TLS and only to callers presenting the shared
// token; on loopback and unix sockets both are optional, and honoured when given.
#ifndef TESSERA_WORKER_SERVICE_AUTH_H_
#define TESSERA_WORKER_SERVICE_AUTH_H_

#include <grpcpp/grpcpp.h>

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "tessera/v1/worker.grpc.pb.h"

namespace tessera::worker {

// Where the worker reads its token when no --token-file is given.
inline constexpr char kWorkerTokenEnv[] = "TESSERA_WORKER_TOKEN";

// The command line's security settings; an empty path is "not given".
struct SecurityOptions {
  std::string tls_cert_file;       // PEM certificate chain of the worker
  std::string tls_key_file;        // its PEM private key
  std::string tls_client_ca_file;  // given: callers must present a certificate this CA signed
  std::string token_file;
  bool tls() const { return !tls_cert_file.empty() || !tls_key_file.empty(); }
};

// The token from `token_file` (its first line, trimmed) or else `env_token` ($TESSERA_WORKER_TOKEN,
// null when unset); empty when neither is given. FAILED_PRECONDITION when both are given, a file
// cannot be read, or the token is empty or not printable ASCII.
absl::StatusOr<std::string> ResolveToken(const std::string& token_file, const char* env_token);

// OK when the worker may listen on `listen` with what it was given: anything on loopback, TLS and
// a token elsewhere. FAILED_PRECONDITION otherwise, naming every missing flag.
absl::Status CheckListenPolicy(absl::string_view listen, const SecurityOptions& options,
                               bool has_token);

// TLS server credentials from the PEM files, or plain ones when no TLS was asked for.
// FAILED_PRECONDITION for a certificate without a key (or the reverse) and for unreadable files.
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const SecurityOptions& options);

// `presented` == `expected`, in a time that depends on the length of `presented` only, so that
// timing does not tell a caller how much of a guess was right. False when `expected` is empty.
bool TokenMatches(absl::string_view expected, absl::string_view presented);

// OK when `metadata` holds exactly one `authorization: Bearer <expected>`; otherwise
// UNAUTHENTICATED with the reason, which never quotes what was presented.
absl::Status CheckAuthorization(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata,
                                absl::string_view expected);

// The Worker service behind the token: every call is checked before `inner` sees it, and a refused
// one gets UNAUTHENTICATED and one line through `log` naming the method, the peer and the reason.
//
// The check sits here, at the service, rather than in a grpc::AuthMetadataProcessor or a server
// interceptor: a processor attaches only to TLS credentials and never learns the peer's address,
// and a gRPC 1.51 interceptor cannot stop a call before its handler runs. A method added to the
// Worker service later and not forwarded here answers UNIMPLEMENTED: it fails closed.
class AuthenticatedWorker final : public v1::Worker::Service {
 public:
  using Log = std::function<void(const std::string& line)>;

  // `inner` outlives this service; `token` is not empty.
  AuthenticatedWorker(v1::Worker::Service* inner, std::string token, Log log);

  grpc::Status Apply(grpc::ServerContext* context, grpc::ServerReader<v1::ApplyChunk>* reader,
                     v1::ApplyReply* reply) override;
  grpc::Status Launch(grpc::ServerContext* context, const v1::LaunchRequest* request,
                      grpc::ServerWriter<v1::TileResult>* writer) override;
  grpc::Status Health(grpc::ServerContext* context, const v1::HealthRequest* request,
                      v1::HealthReply* reply) override;
  grpc::Status EndSession(grpc::ServerContext* context, const v1::EndSessionRequest* request,
                          v1::EndSessionReply* reply) override;

 private:
  // OK, or the refusal to return (after logging it).
  grpc::Status Admit(grpc::ServerContext* context, absl::string_view method) const;

  v1::Worker::Service* const inner_;
  const std::string token_;
  const Log log_;
};

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_SERVICE_AUTH_H_
