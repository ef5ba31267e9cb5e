// IdIndex: ids of buffers and programs to table indices, dense or sparse.
#include "bindless.h"

#include <gtest/gtest.h>

namespace tessera::worker {
namespace {

TEST(IdIndexTest, FindsEveryIdAndNothingElseDenseOrSparse) {
  // Ids 3, 7, 12 (dense), and ids up to 2^40 among three entries (sparse).
  for (uint64_t far : {uint64_t{12}, uint64_t{1} << 40}) {
    SCOPED_TRACE(far);
    IdIndex index;
    index.Build({{7, 1}, {far, 2}, {3, 0}});
    EXPECT_EQ(index.Find(3), 0);
    EXPECT_EQ(index.Find(7), 1);
    EXPECT_EQ(index.Find(static_cast<long long>(far)), 2);
    for (long long none : {-5LL, 0LL, 1LL, 4LL, 8LL, static_cast<long long>(far) + 1}) {
      EXPECT_EQ(index.Find(none), -1) << none;
    }
  }
  IdIndex empty;
  empty.Build({});
  EXPECT_EQ(empty.Find(1), -1);
  EXPECT_EQ(empty.Find(0), -1);
}

}  // namespace
}  // namespace tessera::worker
