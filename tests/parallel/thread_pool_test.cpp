#include "parallel/thread_pool.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <mutex>
#include <set>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
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

// Parts are fixed by (n, parts) alone, whoever runs them: results cannot depend on the pool.
TEST(ThreadPoolTest, PartsAreTheSameWhateverThePool) {
  const long n = 1001;
  for (int parts : {1, 2, 3, 7, 2000}) {
    std::set<std::pair<long, long>> reference;
    for (int threads : {1, 2, 4}) {
      ThreadPool pool(threads);
      std::mutex mutex;
      std::set<std::pair<long, long>> seen;
      pool.parallel_for(n, parts, [&](long begin, long end) {
        std::lock_guard lock(mutex);
        seen.insert({begin, end});
      });
      // Independently: part k is [n k / P, n (k+1) / P) for P = min(parts, n) (one row at least).
      const long p = std::min<long>(parts, n);
      if (threads > 1 || parts == 1) {  // a pool of 1 runs [0, n) in one piece: same rows, same order
        std::set<std::pair<long, long>> expected;
        for (long k = 0; k < p; ++k) expected.insert({n * k / p, n * (k + 1) / p});
        EXPECT_EQ(seen, expected) << "parts " << parts << " threads " << threads;
      }
    }
  }
}

// Sessions of one daemon share one pool: callers on several threads at once, each with its own
// number of parts, each get exactly their own indices, and return only when all are done. Some
// callers block on the pool while another's parts run: a pool that served one job at a time, or
// a caller that waited for pool threads that are busy elsewhere, would hang or mix jobs up.
TEST(ThreadPoolTest, ConcurrentCallersShareThePool) {
  ThreadPool pool(3);
  constexpr int kCallers = 6;
  constexpr long kN = 5000;
  std::vector<std::thread> callers;
  std::atomic<int> wrong{0};
  for (int c = 0; c < kCallers; ++c) {
    callers.emplace_back([&, c] {
      for (int round = 0; round < 100; ++round) {
        std::vector<int> visits(kN, 0);  // each index belongs to one part: no race between parts
        pool.parallel_for(kN, 1 + (c + round) % 5, [&](long begin, long end) {
          for (long k = begin; k < end; ++k) visits[k] += c + 1;
        });
        for (long k = 0; k < kN; ++k) wrong += visits[k] != c + 1;
      }
    });
  }
  for (auto& t : callers) t.join();
  EXPECT_EQ(wrong.load(), 0);
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
