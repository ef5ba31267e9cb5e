// The worker's side of authentication: where tokens come from, which listen addresses need TLS and
// a token, the constant-time comparison, and the token check in front of a real Worker service.
#include "auth.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "absl/synchronization/mutex.h"
#include "worker_service.h"

namespace tessera::worker {
namespace {

using Metadata = std::multimap<grpc::string_ref, grpc::string_ref>;

// A file in a private directory, removed with the object.
class TempFile {
 public:
  explicit TempFile(const std::string& contents) {
    char dir[] = "/tmp/tessera-auth-XXXXXX";
    EXPECT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
    path_ = dir_ + "/file";
    FILE* f = std::fopen(path_.c_str(), "w");
    EXPECT_NE(f, nullptr);
    std::fputs(contents.c_str(), f);
    std::fclose(f);
  }
  ~TempFile() {
    unlink(path_.c_str());
    rmdir(dir_.c_str());
  }
  const std::string& path() const { return path_; }

 private:
  std::string dir_;
  std::string path_;
};

TEST(WorkerAuthTest, TokenFileGivesItsFirstLineTrimmed) {
  TempFile file("  s3cret-token \nsecond line\n");
  absl::StatusOr<std::string> token = ResolveToken(file.path(), nullptr);
  ASSERT_TRUE(token.ok()) << token.status();
  EXPECT_EQ(*token, "s3cret-token");
}

TEST(WorkerAuthTest, TokenComesFromTheEnvironmentWithoutAFile) {
  absl::StatusOr<std::string> token = ResolveToken("", " from-env\n");
  ASSERT_TRUE(token.ok()) << token.status();
  EXPECT_EQ(*token, "from-env");
  token = ResolveToken("", nullptr);
  ASSERT_TRUE(token.ok()) << token.status();
  EXPECT_EQ(*token, "");
  token = ResolveToken("", "");
  ASSERT_TRUE(token.ok()) << token.status();
  EXPECT_EQ(*token, "");
}

TEST(WorkerAuthTest, UnusableTokensAreRefusedWithTheReason) {
  TempFile file("s3cret\n");
  absl::StatusOr<std::string> both = ResolveToken(file.path(), "other");
  ASSERT_FALSE(both.ok());
  EXPECT_NE(both.status().message().find("--token-file and TESSERA_WORKER_TOKEN"),
            std::string::npos)
      << both.status();

  TempFile empty("   \nsecond line is not the token\n");
  absl::StatusOr<std::string> blank = ResolveToken(empty.path(), nullptr);
  ASSERT_FALSE(blank.ok());
  EXPECT_NE(blank.status().message().find("empty"), std::string::npos) << blank.status();
  EXPECT_NE(blank.status().message().find(empty.path()), std::string::npos) << blank.status();

  absl::StatusOr<std::string> missing = ResolveToken("/nonexistent/tessera-token", nullptr);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("/nonexistent/tessera-token"), std::string::npos)
      << missing.status();

  absl::StatusOr<std::string> spaced = ResolveToken("", "two words");
  ASSERT_FALSE(spaced.ok());
  EXPECT_NE(spaced.status().message().find("printable ASCII"), std::string::npos)
      << spaced.status();
}

TEST(WorkerAuthTest, LoopbackNeedsNothingAndOtherAddressesNeedTlsAndAToken) {
  SecurityOptions none;
  EXPECT_TRUE(CheckListenPolicy("127.0.0.1:0", none, false).ok());
  EXPECT_TRUE(CheckListenPolicy("unix:/tmp/w.sock", none, false).ok());
  EXPECT_TRUE(CheckListenPolicy("[::1]:7000", none, false).ok());

  absl::Status bare = CheckListenPolicy("0.0.0.0:7000", none, false);
  EXPECT_EQ(bare.code(), absl::StatusCode::kFailedPrecondition);
  for (const char* missing : {"0.0.0.0:7000", "--tls-cert", "--tls-key", "--token-file",
                              "TESSERA_WORKER_TOKEN", "docs/security.md"}) {
    EXPECT_NE(bare.message().find(missing), std::string::npos) << missing << ": " << bare;
  }

  SecurityOptions tls;
  tls.tls_cert_file = "cert.pem";
  tls.tls_key_file = "key.pem";
  absl::Status no_token = CheckListenPolicy("10.1.2.3:7000", tls, false);
  EXPECT_EQ(no_token.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(no_token.message().find("a token"), std::string::npos) << no_token;
  EXPECT_EQ(no_token.message().find("--tls-cert"), std::string::npos) << no_token;

  absl::Status no_tls = CheckListenPolicy("10.1.2.3:7000", none, true);
  EXPECT_EQ(no_tls.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(no_tls.message().find("--tls-key"), std::string::npos) << no_tls;

  EXPECT_TRUE(CheckListenPolicy("10.1.2.3:7000", tls, true).ok());
}

TEST(WorkerAuthTest, ServerCredentialsNeedBothTlsFiles) {
  SecurityOptions plain;
  EXPECT_TRUE(MakeServerCredentials(plain).ok());

  SecurityOptions cert_only;
  cert_only.tls_cert_file = "cert.pem";
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> half = MakeServerCredentials(cert_only);
  ASSERT_FALSE(half.ok());
  EXPECT_NE(half.status().message().find("go together"), std::string::npos) << half.status();

  SecurityOptions client_ca_only;
  client_ca_only.tls_client_ca_file = "ca.pem";
  EXPECT_FALSE(MakeServerCredentials(client_ca_only).ok());

  TempFile not_pem("hello\n");
  SecurityOptions wrong;
  wrong.tls_cert_file = not_pem.path();
  wrong.tls_key_file = not_pem.path();
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> bad = MakeServerCredentials(wrong);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("--tls-cert file " + not_pem.path()), std::string::npos)
      << bad.status();

  SecurityOptions unreadable;
  unreadable.tls_cert_file = "/nonexistent/cert.pem";
  unreadable.tls_key_file = "/nonexistent/key.pem";
  absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> gone = MakeServerCredentials(unreadable);
  ASSERT_FALSE(gone.ok());
  EXPECT_NE(gone.status().message().find("/nonexistent/cert.pem"), std::string::npos)
      << gone.status();
}

TEST(WorkerAuthTest, TokenMatchesOnlyTheWholeToken) {
  EXPECT_TRUE(TokenMatches("s3cret", "s3cret"));
  EXPECT_FALSE(TokenMatches("s3cret", "s3creT"));
  EXPECT_FALSE(TokenMatches("s3cret", "s3cre"));
  EXPECT_FALSE(TokenMatches("s3cret", "s3crets3cret"));  // the secret repeated is not the secret
  EXPECT_FALSE(TokenMatches("s3cret", "s3cret "));
  EXPECT_FALSE(TokenMatches("s3cret", ""));
  EXPECT_FALSE(TokenMatches("", ""));  // no token configured matches nothing
}

TEST(WorkerAuthTest, AuthorizationNeedsExactlyOneBearerToken) {
  Metadata good = {{"authorization", "Bearer s3cret"}, {"user-agent", "test"}};
  EXPECT_TRUE(CheckAuthorization(good, "s3cret").ok());
  Metadata lower = {{"authorization", "bearer s3cret"}};  // the scheme is case-insensitive
  EXPECT_TRUE(CheckAuthorization(lower, "s3cret").ok());

  struct Case {
    Metadata metadata;
    const char* reason;
  };
  const std::vector<Case> cases = {
      {{}, "no token"},
      {{{"authorization", "Bearer wrong"}}, "wrong token"},
      {{{"authorization", "Basic s3cret"}}, "not a Bearer token"},
      {{{"authorization", "Bear"}}, "not a Bearer token"},
      {{{"authorization", "Bearer s3cret"}, {"authorization", "Bearer wrong"}}, "more than one"},
  };
  for (const Case& c : cases) {
    absl::Status status = CheckAuthorization(c.metadata, "s3cret");
    EXPECT_EQ(status.code(), absl::StatusCode::kUnauthenticated) << c.reason;
    EXPECT_NE(status.message().find("authentication failed"), std::string::npos) << status;
    EXPECT_NE(status.message().find(c.reason), std::string::npos) << status;
    EXPECT_EQ(status.message().find("s3cret"), std::string::npos) << status;
  }
}

// The check in front of the real service, through a gRPC server on 127.0.0.1.
class AuthenticatedWorkerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
    builder.RegisterService(&authenticated_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    ASSERT_NE(port_, 0);
    stub_ = v1::Worker::NewStub(grpc::CreateChannel("127.0.0.1:" + std::to_string(port_),
                                                    grpc::InsecureChannelCredentials()));
  }
  void TearDown() override { server_->Shutdown(); }

  grpc::Status Health(const char* authorization) {
    grpc::ClientContext context;
    if (authorization != nullptr) context.AddMetadata("authorization", authorization);
    v1::HealthReply reply;
    return stub_->Health(&context, v1::HealthRequest(), &reply);
  }

  std::vector<std::string> Log() {
    absl::MutexLock lock(&mu_);
    return log_;
  }

  absl::Mutex mu_;
  std::vector<std::string> log_ ABSL_GUARDED_BY(mu_);  // appended to by the server's threads
  WorkerService service_{1};
  AuthenticatedWorker authenticated_{&service_, "s3cret", [this](const std::string& line) {
                                       absl::MutexLock lock(&mu_);
                                       log_.push_back(line);
                                     }};
  int port_ = 0;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<v1::Worker::Stub> stub_;
};

TEST_F(AuthenticatedWorkerTest, TheRightTokenReachesTheService) {
  grpc::Status status = Health("Bearer s3cret");
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_TRUE(Log().empty());
}

TEST_F(AuthenticatedWorkerTest, EveryMethodRefusesAWrongTokenAndLogsOneLine) {
  grpc::Status health = Health("Bearer guess");
  EXPECT_EQ(health.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(health.error_message().find("wrong token"), std::string::npos);

  {
    grpc::ClientContext context;
    context.AddMetadata("authorization", "Bearer guess");
    v1::ApplyReply reply;
    auto writer = stub_->Apply(&context, &reply);
    writer->WritesDone();
    EXPECT_EQ(writer->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
  {
    grpc::ClientContext context;
    context.AddMetadata("authorization", "Bearer guess");
    auto reader = stub_->Launch(&context, v1::LaunchRequest());
    v1::TileResult result;
    EXPECT_FALSE(reader->Read(&result));
    EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }

  const std::vector<std::string> log = Log();
  ASSERT_EQ(log.size(), 3u);
  const char* methods[] = {"refused Health from ", "refused Apply from ", "refused Launch from "};
  for (size_t i = 0; i < log.size(); ++i) {
    EXPECT_NE(log[i].find(methods[i]), std::string::npos) << log[i];
    EXPECT_NE(log[i].find("127.0.0.1"), std::string::npos) << log[i];  // the peer
    EXPECT_NE(log[i].find("wrong token"), std::string::npos) << log[i];
    EXPECT_EQ(log[i].find("guess"), std::string::npos) << log[i];
  }
}

TEST_F(AuthenticatedWorkerTest, AMissingTokenIsRefusedWithoutQuotingAnything) {
  grpc::Status status = Health(nullptr);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_NE(status.error_message().find("no token"), std::string::npos);
  const std::vector<std::string> log = Log();
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("no token"), std::string::npos) << log[0];
  EXPECT_EQ(log[0].find("s3cret"), std::string::npos) << log[0];
}

}  // namespace
}  // namespace tessera::worker
