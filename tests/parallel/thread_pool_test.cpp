#include "parallel/thread_pool.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>
#include <system_error>
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

// The address space of this process now, in bytes (/proc/self/statm's first field is pages).
long address_space_bytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0;
  statm >> pages;
  return pages * sysconf(_SC_PAGESIZE);
}

// A pool whose threads cannot all start (each needs an 8 MiB stack; the address space is capped at
// what the process has plus 64 MiB, root or not) throws std::system_error and stops the threads it
// had started; it used to leave them joinable, which ends the process in std::terminate.
TEST(ThreadPoolTest, AThreadThatCannotStartIsACleanError) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlim_t cap = static_cast<rlim_t>(address_space_bytes()) + (64L << 20);
    const rlimit limit{cap, cap};
    if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(3);
    try {
      ThreadPool pool(256);
      _exit(2);  // all 255 threads started: the cap did not bite
    } catch (const std::system_error&) {
      _exit(0);
    }
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace lbsolid::parallel
