// AttributeLayout: where each attribute of a hit lives in its fixed-size block.
#include "binding.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

namespace tessera::worker {
namespace {

// Attributes are packed without padding: any mix of sizes that adds up to 512 bytes fits, as
// documented (a 500-byte struct and a float3; a byte, a 476-byte struct, a uchar3, a float3 and
// 20 bytes, which size-alignment would have padded past the end).
TEST(AttributeLayoutTest, TheWholeBlockIsUsable) {
  AttributeLayout layout;
  ASSERT_EQ(layout.Offset("big", 500, "m").value(), 0u);
  EXPECT_EQ(layout.Offset("normal", 12, "m").value(), 500u);
  EXPECT_EQ(layout.used(), AttributeLayout::kMaxBytes);
  EXPECT_FALSE(layout.Offset("one_more", 1, "m").ok());

  AttributeLayout mixed;
  size_t sum = 0;
  for (const auto& [name, size] : std::vector<std::pair<const char*, size_t>>{
           {"byte", 1}, {"big", 476}, {"uchar3", 3}, {"float3", 12}, {"twenty", 20}}) {
    EXPECT_EQ(mixed.Offset(name, size, "m").value(), sum) << name;
    sum += size;
  }
  EXPECT_EQ(mixed.used(), AttributeLayout::kMaxBytes);
  EXPECT_EQ(mixed.Offset("byte", 1, "m").value(), 0u);  // asked again: the same place
  const absl::StatusOr<size_t> past = mixed.Offset("one_more", 4, "program p");
  ASSERT_FALSE(past.ok());
  EXPECT_NE(
      past.status().message().find("'one_more' (4 bytes, declared in the module of program p)"),
      std::string::npos)
      << past.status().message();
}

}  // namespace
}  // namespace tessera::worker
