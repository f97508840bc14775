#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "vifusion/scene/row_pool.hpp"

namespace vifusion::scene {
namespace {

TEST(RowPool, EveryRowRunsExactlyOnceForManyJobs) {
  for (int threads : {1, 2, 5}) {
    RowPool pool(threads);
    EXPECT_EQ(pool.threadCount(), threads);
    for (int rows : {0, 1, 3, 480, 1001}) {
      for (int chunk : {1, 4, 64}) {
        std::vector<std::atomic<int>> runs(static_cast<std::size_t>(rows));
        pool.forRows(
            rows,
            [&](int begin, int end) {
              for (int r = begin; r < end; ++r) runs[static_cast<std::size_t>(r)].fetch_add(1);
            },
            chunk);
        for (int r = 0; r < rows; ++r) ASSERT_EQ(runs[static_cast<std::size_t>(r)].load(), 1) << r;
      }
    }
  }
}

TEST(RowPool, DefaultUsesEveryHardwareThread) {
  const RowPool pool;
  EXPECT_GE(pool.threadCount(), 1);
}

}  // namespace
}  // namespace vifusion::scene
