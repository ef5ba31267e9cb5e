#include "memory_use.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <memory>

namespace tessera::worker {
namespace {

void AddBuffer(v1::StateDelta* d, uint64_t id, uint64_t element_size,
               std::initializer_list<uint64_t> dims) {
  v1::Buffer* b = d->add_objects()->mutable_buffer();
  b->set_id(id);
  b->set_element_size(element_size);
  for (uint64_t n : dims) b->add_dims(n);
}

TEST(BufferBytesTest, FollowsTheBuffersOfAcceptedDeltas) {
  BufferBytes bytes;
  v1::StateDelta first;
  first.set_sequence(1);
  AddBuffer(&first, 2, 16, {64, 32});
  AddBuffer(&first, 3, 4, {1000});
  AddBuffer(&first, 4, 4, {});  // unsized
  first.add_objects()->mutable_material()->set_id(5);
  bytes.Apply(first);
  EXPECT_EQ(bytes.total(), 64u * 32u * 16u + 4000u);

  v1::StateDelta second;
  second.set_sequence(2);
  AddBuffer(&second, 2, 16, {128, 128, 2});  // resized
  second.add_removed(3);
  second.add_removed(5);  // not a buffer
  bytes.Apply(second);
  EXPECT_EQ(bytes.total(), 128u * 128u * 2u * 16u);

  v1::StateDelta again;  // a new device: only what this delta holds
  again.set_sequence(1);
  AddBuffer(&again, 9, 1, {10});
  bytes.Apply(again);
  EXPECT_EQ(bytes.total(), 10u);
}

TEST(BufferBytesTest, HugeClaimsSaturate) {
  BufferBytes bytes;
  v1::StateDelta d;
  d.set_sequence(1);
  AddBuffer(&d, 1, 1u << 20, {1u << 30, 1u << 30, 1u << 30});
  AddBuffer(&d, 2, 16, {4});
  bytes.Apply(d);
  EXPECT_EQ(bytes.total(), std::numeric_limits<uint64_t>::max());
}

TEST(ResidentBytesTest, GrowsWithTouchedMemory) {
  const uint64_t before = ResidentBytes();
  ASSERT_GT(before, 0u);
  constexpr size_t kBytes = size_t{32} << 20;
  std::unique_ptr<char[]> block(new char[kBytes]);
  std::memset(block.get(), 1, kBytes);
  const uint64_t after = ResidentBytes();
  EXPECT_GT(after, before + kBytes / 2) << before << " -> " << after;
  EXPECT_EQ(block[kBytes - 1], 1);
}

}  // namespace
}  // namespace tessera::worker
