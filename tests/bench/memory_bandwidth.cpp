// Built with -fno-tree-loop-distribute-patterns so the copy loop stays a loop with ordinary stores,
// as the LB kernel's are, instead of becoming a memcpy call with non-temporal stores.
#include "bench/memory_bandwidth.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "parallel/thread_pool.h"

namespace lbsolid::bench {

std::size_t last_level_cache_bytes() {
  std::size_t best = 0;
  for (int index = 0; index < 8; ++index) {
    std::ifstream in("/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/size");
    std::string text;
    if (!(in >> text)) continue;
    std::size_t value = std::stoul(text);
    if (text.back() == 'K') value *= 1024;
    if (text.back() == 'M') value *= 1024 * 1024;
    best = std::max(best, value);
  }
  return best ? best : 32u << 20;
}

namespace {
void copy(const double* __restrict a, double* __restrict b, long begin, long end) {
  for (long i = begin; i < end; ++i) b[i] = a[i];
}
void update(double* a, double s, long begin, long end) {
  for (long i = begin; i < end; ++i) a[i] = s * a[i];
}

// Best time of `repeats` calls of `pass` (after one untimed call that pages the memory in).
template <class Pass>
double best_seconds(int repeats, Pass pass) {
  pass();
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    pass();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}
}  // namespace

double copy_bandwidth(std::size_t bytes_per_array, int threads, int repeats) {
  const long n = static_cast<long>(bytes_per_array / sizeof(double));
  std::vector<double> a(n, 1.0), b(n, 0.0);
  parallel::ThreadPool pool(threads);
  const double seconds = best_seconds(repeats, [&] {
    pool.parallel_for(n, [&](long begin, long end) { copy(a.data(), b.data(), begin, end); });
  });
  return 2.0 * sizeof(double) * static_cast<double>(n) / seconds;
}

double update_bandwidth(std::size_t bytes, int threads, int repeats) {
  const long n = static_cast<long>(bytes / sizeof(double));
  std::vector<double> a(n, 1.0);
  parallel::ThreadPool pool(threads);
  // Alternating factors keep the values bounded whatever the number of passes.
  double factor = 0.5;
  const double seconds = best_seconds(repeats, [&] {
    factor = 1.0 / factor;
    pool.parallel_for(n, [&](long begin, long end) { update(a.data(), factor, begin, end); });
  });
  return 2.0 * sizeof(double) * static_cast<double>(n) / seconds;
}

}  // namespace lbsolid::bench
