#include "listen_address.h"

#include <gtest/gtest.h>

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

TEST(ListenAddressTest, ResolvedAddressCarriesTheBoundPort) {
  EXPECT_EQ(ResolvedListenAddress("127.0.0.1:0", 41234), "127.0.0.1:41234");
  EXPECT_EQ(ResolvedListenAddress("[::1]:0", 7), "[::1]:7");
  EXPECT_EQ(ResolvedListenAddress("localhost:5000", 5000), "localhost:5000");
  EXPECT_EQ(ResolvedListenAddress("unix:/tmp/w.sock", 1), "unix:/tmp/w.sock");
}

}  // namespace
}  // namespace tessera::worker
