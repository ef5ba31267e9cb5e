// AttributeLayout: where each attribute of a hit lives in its fixed-size block.
#include "binding.h"

#include <gtest/gtest.h>

namespace tessera::worker {
namespace {

// Padding does not count against the block: each attribute is aligned only as far as its size
// allows, so a 500-byte struct and a float3 fill 512 bytes, as documented.
TEST(AttributeLayoutTest, TheWholeBlockIsUsable) {
  AttributeLayout layout;
  ASSERT_EQ(layout.Offset("big", 500, "m").value(), 0u);
  const size_t normal = layout.Offset("normal", 12, "m").value();
  EXPECT_EQ(normal, 500u);
  EXPECT_EQ(normal % 4, 0u);
  EXPECT_EQ(layout.used(), AttributeLayout::kMaxBytes);
  EXPECT_FALSE(layout.Offset("one_more", 1, "m").ok());
  // Sixteen-byte values stay sixteen-byte aligned.
  AttributeLayout aligned;
  ASSERT_TRUE(aligned.Offset("byte", 1, "m").ok());
  EXPECT_EQ(aligned.Offset("vec", 16, "m").value(), 16u);
  EXPECT_EQ(aligned.Offset("byte", 1, "m").value(), 0u);  // asked again: the same place
}

}  // namespace
}  // namespace tessera::worker
