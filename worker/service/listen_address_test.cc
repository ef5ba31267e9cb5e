#include "listen_address.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <stdlib.h>  // mkdtemp
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace tessera::worker {
namespace {

TEST(ListenAddressTest, OnlyLoopbackAddressesAreLocal) {
  for (const char* local :
       {"127.0.0.1:0", "127.1.2.3:5000", "localhost:9", "LocalHost:9", "[::1]:5000",
        "[::ffff:127.0.0.1]:1", "unix:/tmp/w.sock", "unix:relative.sock"}) {
    EXPECT_TRUE(IsLoopbackAddress(local)) << local;
  }
  for (const char* remote :
       {"0.0.0.0:0", "10.0.0.2:5000", "[::]:5000", "[2001:db8::1]:1", "render7.example.com:5000",
        "localhost.example.com:1", "[::ffff:10.0.0.1]:1", "128.0.0.1:1"}) {
    EXPECT_FALSE(IsLoopbackAddress(remote)) << remote;
  }
}

TEST(ListenAddressTest, OnlyWellFormedAddressesAreAccepted) {
  const std::string longest_path(107, 's');
  for (const std::string& good : std::vector<std::string>{
           "127.0.0.1:0", "localhost:65535", "[::1]:5000", "0.0.0.0:7000", "render7:1",
           "unix:/tmp/w.sock", "unix:relative.sock", "unix:" + longest_path}) {
    EXPECT_TRUE(CheckListenAddress(good).ok()) << good;
  }
  for (const std::string& bad : std::vector<std::string>{
           "", "garbage", "127.0.0.1", "127.0.0.1:", "127.0.0.1:65536", "127.0.0.1:99999",
           "127.0.0.1:-1", "127.0.0.1:0x10", "127.0.0.1:0:0", "::1:0", "[::1]", "[::1]5000",
           "unix:", "unix:" + longest_path + "s"}) {
    absl::Status s = CheckListenAddress(bad);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(s.message().find("--listen " + bad + ":"), std::string::npos) << s;
  }
}

TEST(ListenAddressTest, AUnixSocketSomeoneListensOnIsInUseAndAStaleOneIsNot) {
  char dir[] = "/tmp/tessera-listen-test-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string path = std::string(dir) + "/w.sock";
  const std::string listen = "unix:" + path;
  EXPECT_TRUE(CheckUnixSocketNotInUse(listen).ok());  // nothing there
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.c_str(), path.size());
  ASSERT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0);
  ASSERT_EQ(::listen(fd, 4), 0);
  absl::Status s = CheckUnixSocketNotInUse(listen);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << s;
  EXPECT_NE(s.message().find(listen), std::string::npos) << s;
  close(fd);  // the socket file stays behind, stale
  EXPECT_TRUE(CheckUnixSocketNotInUse(listen).ok());
  EXPECT_TRUE(CheckUnixSocketNotInUse("127.0.0.1:0").ok());
  unlink(path.c_str());
  rmdir(dir);
}

// What would make the server fail to bind is said with the system's reason before it starts.
// Something that is not a socket under the name is never replaced: a file, a directory and a
// symbolic link to nothing are refused naming the path, not left to gRPC's "No address added".
TEST(ListenAddressTest, APathThatIsNotASocketIsRefused) {
  char dir[] = "/tmp/tessera-listen-test-XXXXXX";
  ASSERT_NE(mkdtemp(dir), nullptr);
  const std::string file = std::string(dir) + "/file", sub = std::string(dir) + "/dir",
                    link = std::string(dir) + "/link";
  FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fclose(f);
  ASSERT_EQ(mkdir(sub.c_str(), 0700), 0);
  ASSERT_EQ(symlink((std::string(dir) + "/nowhere").c_str(), link.c_str()), 0);
  for (const std::string& path : {file, sub, link}) {
    absl::Status s = CheckUnixSocketNotInUse("unix:" + path);
    EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << path << ": " << s;
    EXPECT_NE(s.message().find(path + " exists and is not a socket"), std::string::npos) << s;
  }
  unlink(link.c_str());
  rmdir(sub.c_str());
  unlink(file.c_str());
  rmdir(dir);
}

TEST(ListenAddressTest, AddressesThatCannotBeBoundAreNamedWithTheReason) {
  absl::Status s = CheckCanBind("unix:/nonexistent/dir/w.sock");
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_NE(s.message().find("cannot create the socket in /nonexistent/dir: No such file"),
            std::string::npos)
      << s;
  EXPECT_TRUE(CheckCanBind("127.0.0.1:0").ok());
  // A port another socket listens on.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  ASSERT_EQ(listen(fd, 1), 0);
  socklen_t length = sizeof(a);
  ASSERT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length), 0);
  s = CheckCanBind("127.0.0.1:" + std::to_string(ntohs(a.sin_port)));
  close(fd);
  EXPECT_NE(s.message().find("Address already in use"), std::string::npos) << s;
}

TEST(ListenAddressTest, ResolvedAddressCarriesTheBoundPort) {
  EXPECT_EQ(ResolvedListenAddress("127.0.0.1:0", 41234), "127.0.0.1:41234");
  EXPECT_EQ(ResolvedListenAddress("[::1]:0", 7), "[::1]:7");
  EXPECT_EQ(ResolvedListenAddress("localhost:5000", 5000), "localhost:5000");
  EXPECT_EQ(ResolvedListenAddress("unix:/tmp/w.sock", 1), "unix:/tmp/w.sock");
}

}  // namespace
}  // namespace tessera::worker
