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
}  // namespace

double copy_bandwidth(std::size_t bytes_per_array, int threads, int repeats) {
  const long n = static_cast<long>(bytes_per_array / sizeof(double));
  std::vector<double> a(n, 1.0), b(n, 0.0);
  parallel::ThreadPool pool(threads);
  // First touch by the threads that will copy, so pages sit near them.
  pool.parallel_for(n, [&](long begin, long end) { copy(a.data(), b.data(), begin, end); });
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    pool.parallel_for(n, [&](long begin, long end) { copy(a.data(), b.data(), begin, end); });
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return 2.0 * sizeof(double) * static_cast<double>(n) / best;
}

}  // namespace lbsolid::bench
