#include "parallel/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace lbsolid::parallel {
namespace {

TEST(ThreadPoolTest, ParallelForVisitsEveryIndexExactlyOnce) {
  for (int threads : {1, 2, 5}) {
    ThreadPool pool(threads);
    for (long n : {0L, 1L, 3L, 1000L}) {
      std::vector<std::atomic<int>> visits(n);
      pool.parallel_for(n, [&](long begin, long end) {
        for (long k = begin; k < end; ++k) visits[k]++;
      });
      for (long k = 0; k < n; ++k) EXPECT_EQ(visits[k].load(), 1) << "threads " << threads << " n " << n;
    }
  }
}

TEST(ThreadPoolTest, RepeatedJobsReuseTheWorkers) {
  ThreadPool pool(3);
  std::atomic<long> total{0};
  for (int round = 0; round < 200; ++round) {
    pool.parallel_for(10, [&](long begin, long end) { total += end - begin; });
  }
  EXPECT_EQ(total.load(), 2000);
}

}  // namespace
}  // namespace lbsolid::parallel
