// A measurement, not part of the build: what a ThreadPool::parallel_for on two threads costs
// beyond its parts' work (docs/performance.md, "A caller that watches for the end"). Each of
// the two parts spins `work_us`, the second `skew_us` longer; the caller spins 5 us between
// jobs, as a coupled step's serial work does.
//   pool_handoff [work_us] [skew_us]
// Build (from the tree's root, after building ./build):
//   g++ -std=c++20 -O2 -Icore docs/experiments/pool_handoff.cpp build/core/liblbsolid_core.a \
//     -lpthread -o pool_handoff
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "parallel/thread_pool.h"

using namespace std::chrono;

static void spin_for(double us) {
  const auto end = steady_clock::now() + duration<double, std::micro>(us);
  while (steady_clock::now() < end) {
  }
}

int main(int argc, char** argv) {
  const double work = argc > 1 ? std::atof(argv[1]) : 50, skew = argc > 2 ? std::atof(argv[2]) : 0;
  constexpr double kBetween = 5;  // us of the caller's own between jobs
  lbsolid::parallel::ThreadPool pool(2);
  for (int rep = 0; rep < 3; ++rep) {
    constexpr int kCalls = 2000;
    const auto start = steady_clock::now();
    for (int i = 0; i < kCalls; ++i) {
      pool.parallel_for(2, 2, [&](long first, long) { spin_for(first == 0 ? work : work + skew); });
      spin_for(kBetween);
    }
    const double per_call = duration<double, std::micro>(steady_clock::now() - start).count() / kCalls;
    const double longest = work + (skew > 0 ? skew : 0);
    std::printf("parts of %.0f and %.0f us: %.1f us a call, %.1f beyond the longer part and the caller's own\n",
                work, work + skew, per_call, per_call - longest - kBetween);
  }
}
