// Workers behind TLS and a token (docs/security.md), with real tessera-worker processes and
// certificates that openssl makes for each test: what an authenticated host reaches, what others
// get (UNAUTHENTICATED and a logged reason, or a failed handshake, never a hang), and that neither
// end uses a non-loopback address without TLS and a token.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "transport/grpc_device.h"
#include "transport/worker_process.h"

namespace tessera::e2e {
namespace {

using transport::GrpcDevice;
using transport::WorkerProcess;

constexpr char kToken[] = "s3cret-token-9f2c";
constexpr char kServerName[] = "worker.tessera.test";
// Every setting a host or worker reads; each test starts with none of them.
const char* const kEnvironment[] = {
    "TESSERA_TLS_CA",          "TESSERA_TLS_CERT",   "TESSERA_TLS_KEY",     "TESSERA_TOKEN",
    "TESSERA_TLS_SERVER_NAME", "TESSERA_TOKEN_FILE", "TESSERA_WORKER_TOKEN"};

class SecurityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : kEnvironment) unsetenv(name);
    char dir[] = "/tmp/tessera-security-XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
    // A CA, a worker certificate it signed for kServerName and 127.0.0.1, a host certificate it
    // signed, and an unrelated CA. EC keys: quick to make.
    const std::string key = "-newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
    const std::string sign = "-CA ca.pem -CAkey ca.key -CAcreateserial -days 2";
    const std::string script =
        "set -e; cd " + dir_ + "; exec 2>openssl.log; " + TESSERA_OPENSSL + " req -x509 " + key +
        " -days 2 -subj /CN=tessera-test-ca -keyout ca.key -out ca.pem; " + TESSERA_OPENSSL +
        " req -new " + key + " -subj /CN=" + kServerName + " -keyout server.key -out server.csr; " +
        "echo 'subjectAltName=DNS:" + kServerName + ",IP:127.0.0.1' > server.ext; " +
        TESSERA_OPENSSL + " x509 -req -in server.csr " + sign +
        " -extfile server.ext -out server.pem; " + TESSERA_OPENSSL + " req -new " + key +
        " -subj /CN=tessera-test-host -keyout client.key -out client.csr; " + TESSERA_OPENSSL +
        " x509 -req -in client.csr " + sign + " -out client.pem; " + TESSERA_OPENSSL +
        " req -x509 " + key + " -days 2 -subj /CN=other-ca -keyout other.key -out other.pem; " +
        "printf '" + kToken + "\\n' > token; chmod 600 *.key token";
    ASSERT_EQ(std::system(script.c_str()), 0) << "openssl failed; see " << dir_ << "/openssl.log";
  }

  void TearDown() override {
    for (const char* name : kEnvironment) unsetenv(name);
    ASSERT_EQ(std::system(("rm -rf " + dir_).c_str()), 0);
  }

  std::string Path(const std::string& name) const { return dir_ + "/" + name; }

  // A worker with TLS (its certificate from our CA) and the token, plus `more` arguments.
  std::unique_ptr<WorkerProcess> StartWorker(const std::string& listen,
                                             std::vector<std::string> more = {}) {
    WorkerProcess::Options options;
    options.listen = listen;
    options.threads = 1;
    options.extra_args = {"--tls-cert",       Path("server.pem"), "--tls-key",
                          Path("server.key"), "--token-file",     Path("token")};
    options.extra_args.insert(options.extra_args.end(), more.begin(), more.end());
    absl::StatusOr<std::unique_ptr<WorkerProcess>> worker = WorkerProcess::Spawn(options);
    EXPECT_TRUE(worker.ok()) << worker.status();
    return worker.ok() ? *std::move(worker) : nullptr;
  }

  // The host's settings for our worker: trust our CA, send the token.
  void TrustOurWorker() {
    setenv("TESSERA_TLS_CA", Path("ca.pem").c_str(), 1);
    setenv("TESSERA_TOKEN", kToken, 1);
  }

  std::string dir_;
};

TEST_F(SecurityTest, TlsAndTheTokenReachTheWorker) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  TrustOurWorker();
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_TRUE(device.ok()) << device.status() << "\nworker log:\n" << worker->LogTail();
  EXPECT_EQ((*device)->health().pid, worker->pid());
  auto again = (*device)->Health();
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(worker->LogTail().find("refused"), std::string::npos) << worker->LogTail();
  // The token may come from a file as well.
  unsetenv("TESSERA_TOKEN");
  setenv("TESSERA_TOKEN_FILE", Path("token").c_str(), 1);
  auto from_file = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  EXPECT_TRUE(from_file.ok()) << from_file.status();
}

TEST_F(SecurityTest, TheWorkerCertificateIsCheckedAgainstTheServerName) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  TrustOurWorker();
  setenv("TESSERA_TLS_SERVER_NAME", kServerName, 1);
  auto named = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  EXPECT_TRUE(named.ok()) << named.status();
  setenv("TESSERA_TLS_SERVER_NAME", "someone-else.test", 1);
  auto misnamed = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(misnamed.ok());
  EXPECT_EQ(misnamed.status().code(), absl::StatusCode::kUnavailable) << misnamed.status();
}

TEST_F(SecurityTest, AWrongTokenIsUnauthenticatedAndTheWorkerLogsWhy) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  TrustOurWorker();
  setenv("TESSERA_TOKEN", "a-guess", 1);
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.status().code(), absl::StatusCode::kUnauthenticated) << device.status();
  EXPECT_NE(device.status().message().find("authentication failed"), std::string::npos)
      << device.status();
  EXPECT_NE(device.status().message().find(worker->address()), std::string::npos)
      << device.status();
  const std::string log = worker->LogTail();
  EXPECT_NE(log.find("refused Health from ipv4:127.0.0.1:"), std::string::npos) << log;
  EXPECT_NE(log.find("wrong token"), std::string::npos) << log;
  EXPECT_EQ(log.find("a-guess"), std::string::npos) << log;
  EXPECT_EQ(log.find(kToken), std::string::npos) << log;
}

TEST_F(SecurityTest, AHostWithoutTheTokenIsUnauthenticated) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  setenv("TESSERA_TLS_CA", Path("ca.pem").c_str(), 1);
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.status().code(), absl::StatusCode::kUnauthenticated) << device.status();
  EXPECT_NE(device.status().message().find("TESSERA_TOKEN"), std::string::npos) << device.status();
  EXPECT_NE(worker->LogTail().find("no token"), std::string::npos) << worker->LogTail();
}

TEST_F(SecurityTest, AHostWithoutTlsFailsWithinItsTimeout) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  setenv("TESSERA_TOKEN", kToken, 1);  // loopback without TESSERA_TLS_CA: a plain connection
  const absl::Time start = absl::Now();
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(2));
  const absl::Duration took = absl::Now() - start;
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.status().code(), absl::StatusCode::kUnavailable) << device.status();
  EXPECT_LT(took, absl::Seconds(4)) << "the connection attempt outlived its timeout";
  // The message says what to set, not only gRPC's "Socket closed".
  EXPECT_TRUE(absl::StrContains(device.status().message(), "set TESSERA_TLS_CA"))
      << device.status();
}

TEST_F(SecurityTest, AWorkerCertificateFromAnotherCaIsRejected) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("127.0.0.1:0");
  ASSERT_NE(worker, nullptr);
  TrustOurWorker();
  setenv("TESSERA_TLS_CA", Path("other.pem").c_str(), 1);
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(device.ok());
  EXPECT_EQ(device.status().code(), absl::StatusCode::kUnavailable) << device.status();
}

TEST_F(SecurityTest, AWorkerWithAClientCaNeedsTheHostCertificate) {
  std::unique_ptr<WorkerProcess> worker =
      StartWorker("127.0.0.1:0", {"--tls-client-ca", Path("ca.pem")});
  ASSERT_NE(worker, nullptr);
  TrustOurWorker();
  auto anonymous = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(anonymous.ok());
  EXPECT_EQ(anonymous.status().code(), absl::StatusCode::kUnavailable) << anonymous.status();
  setenv("TESSERA_TLS_CERT", Path("client.pem").c_str(), 1);
  setenv("TESSERA_TLS_KEY", Path("client.key").c_str(), 1);
  auto known = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  EXPECT_TRUE(known.ok()) << known.status() << "\nworker log:\n" << worker->LogTail();
}

TEST_F(SecurityTest, ANonLoopbackWorkerWithoutTlsAndATokenExitsSayingWhatIsMissing) {
  WorkerProcess::Options options;
  options.listen = "0.0.0.0:0";
  options.extra_args = {"--allow-remote"};  // allows nothing by itself any more
  auto bare = WorkerProcess::Spawn(options);
  ASSERT_FALSE(bare.ok());
  for (const char* part : {"exited with status 2", "not a loopback address", "--tls-cert",
                           "--tls-key", "--token-file", "TESSERA_WORKER_TOKEN"}) {
    EXPECT_NE(bare.status().message().find(part), std::string::npos)
        << part << ": " << bare.status();
  }

  options.extra_args = {"--tls-cert", Path("server.pem"), "--tls-key", Path("server.key")};
  auto no_token = WorkerProcess::Spawn(options);
  ASSERT_FALSE(no_token.ok());
  EXPECT_NE(no_token.status().message().find("Missing: a token"), std::string::npos)
      << no_token.status();
}

TEST_F(SecurityTest, ANonLoopbackWorkerWithTlsAndATokenServesAuthenticatedHosts) {
  std::unique_ptr<WorkerProcess> worker = StartWorker("0.0.0.0:0");
  ASSERT_NE(worker, nullptr);
  const std::string& address = worker->address();
  ASSERT_EQ(address.rfind("0.0.0.0:", 0), 0u) << address;
  TrustOurWorker();
  const std::string loopback = "127.0.0.1:" + address.substr(address.find(':') + 1);
  auto device = GrpcDevice::Connect(loopback, absl::Seconds(5));
  EXPECT_TRUE(device.ok()) << device.status() << "\nworker log:\n" << worker->LogTail();
}

TEST_F(SecurityTest, TheHostReachesAnotherMachineOnlyWithTlsAndAToken) {
  // 192.0.2.0/24 is reserved for documentation: nothing answers there, and nothing is tried.
  const absl::Time start = absl::Now();
  auto plain = GrpcDevice::Connect("192.0.2.1:7000", absl::Seconds(30));
  EXPECT_LT(absl::Now() - start, absl::Seconds(5)) << "refused only after trying to connect";
  ASSERT_FALSE(plain.ok());
  EXPECT_EQ(plain.status().code(), absl::StatusCode::kUnauthenticated) << plain.status();
  for (const char* part : {"192.0.2.1:7000", "TESSERA_TLS_CA", "TESSERA_TOKEN",
                           "TESSERA_TOKEN_FILE", "docs/security.md"}) {
    EXPECT_NE(plain.status().message().find(part), std::string::npos)
        << part << ": " << plain.status();
  }

  setenv("TESSERA_TLS_CA", Path("ca.pem").c_str(), 1);
  auto no_token = GrpcDevice::Connect("192.0.2.1:7000", absl::Seconds(30));
  ASSERT_FALSE(no_token.ok());
  EXPECT_EQ(no_token.status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_NE(no_token.status().message().find("TESSERA_TOKEN"), std::string::npos);
  EXPECT_EQ(no_token.status().message().find("set TESSERA_TLS_CA"), std::string::npos)
      << no_token.status();
}

TEST_F(SecurityTest, UnusableHostSettingsAreReportedBeforeConnecting) {
  setenv("TESSERA_TLS_CA", Path("missing.pem").c_str(), 1);
  setenv("TESSERA_TOKEN", kToken, 1);
  auto missing_ca = GrpcDevice::Connect("127.0.0.1:1", absl::Seconds(30));
  ASSERT_FALSE(missing_ca.ok());
  EXPECT_EQ(missing_ca.status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_NE(missing_ca.status().message().find(Path("missing.pem")), std::string::npos)
      << missing_ca.status();

  setenv("TESSERA_TLS_CA", Path("ca.pem").c_str(), 1);
  setenv("TESSERA_TOKEN_FILE", Path("token").c_str(), 1);
  auto both = GrpcDevice::Connect("127.0.0.1:1", absl::Seconds(30));
  ASSERT_FALSE(both.ok());
  EXPECT_NE(both.status().message().find("set one"), std::string::npos) << both.status();

  // A host key that is not its certificate's: gRPC would say "empty address list".
  unsetenv("TESSERA_TOKEN_FILE");
  setenv("TESSERA_TLS_CERT", Path("client.pem").c_str(), 1);
  setenv("TESSERA_TLS_KEY", Path("other.key").c_str(), 1);
  auto mismatched = GrpcDevice::Connect("127.0.0.1:1", absl::Seconds(30));
  ASSERT_FALSE(mismatched.ok());
  EXPECT_NE(mismatched.status().message().find("the key does not belong to the certificate"),
            std::string::npos)
      << mismatched.status();
}

// Whoever can connect to a worker's unix socket runs code as its user: the socket is the
// owner's alone even when the worker inherits a umask that would share it.
TEST_F(SecurityTest, AUnixSocketWorkerIsOwnerOnlyWhateverTheUmask) {
  const mode_t old_umask = umask(0);
  WorkerProcess::Options options;
  options.threads = 1;
  options.listen = "unix:" + Path("w.sock");
  auto spawned = WorkerProcess::Spawn(options);
  umask(old_umask);
  ASSERT_TRUE(spawned.ok()) << spawned.status();
  struct stat st {};
  ASSERT_EQ(stat(Path("w.sock").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 077, 0u) << std::oct << (st.st_mode & 0777);
}

// TESSERA_WORKER_TOKEN configures workers someone starts; a host that has it in its environment
// still runs its own local:N workers, which need no token.
TEST_F(SecurityTest, ATokenForOtherWorkersDoesNotLockTheHostOutOfItsOwn) {
  setenv("TESSERA_WORKER_TOKEN", kToken, 1);
  WorkerProcess::Options options;
  options.threads = 1;
  auto spawned = WorkerProcess::Spawn(options);
  ASSERT_TRUE(spawned.ok()) << spawned.status();
  auto device = GrpcDevice::Connect((*spawned)->address(), absl::Seconds(5));
  EXPECT_TRUE(device.ok()) << device.status();
}

TEST_F(SecurityTest, APlainLoopbackWorkerWithATokenChecksIt) {
  // A unix socket, no TLS: the token travels as plain metadata and is still required.
  WorkerProcess::Options options;
  options.threads = 1;
  options.extra_args = {"--token-file", Path("token")};
  auto spawned = WorkerProcess::Spawn(options);
  ASSERT_TRUE(spawned.ok()) << spawned.status();
  std::unique_ptr<WorkerProcess> worker = *std::move(spawned);
  ASSERT_EQ(worker->address().rfind("unix:", 0), 0u) << worker->address();
  setenv("TESSERA_TLS_CA", Path("ca.pem").c_str(), 1);  // TCP only: a unix socket stays plain

  auto anonymous = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_FALSE(anonymous.ok());
  EXPECT_EQ(anonymous.status().code(), absl::StatusCode::kUnauthenticated) << anonymous.status();
  EXPECT_NE(worker->LogTail().find("refused Health from unix:"), std::string::npos)
      << worker->LogTail();

  setenv("TESSERA_TOKEN", kToken, 1);
  auto device = GrpcDevice::Connect(worker->address(), absl::Seconds(5));
  ASSERT_TRUE(device.ok()) << device.status();
  EXPECT_EQ((*device)->health().pid, worker->pid());
}

}  // namespace
}  // namespace tessera::e2e
