// A measurement, not part of the build (what it led to is the fluid's own since: the exchange
// inside the kernels, fluid/in_step_exchange.h; docs/performance.md): what the 3D scene's
// exchange costs when it is done inside the fluid's step, row by row while a row's populations
// are still in the L1 cache, against the way the tree did it (a read of each coupled node's pre-collision fluid before the step, and the
// gain added to its post-collision populations after it: two passes over lines long evicted).
//
// A D3Q19 box of n^3 cells in 19 arrays, double, BGK, no force, stepped in place (AA pattern):
// the even (local) sweep a plain vector loop here, the odd (pulling) one ShiftedPull::run as the
// fluid uses it, a plane's rows swept as one line and cut at each row join as the fluid's
// sweep_copying_joins cuts it. Row ends are not put right (both variants alike; the coupled nodes
// are far from them). The coupled nodes are those of the bench's 3D suspension: 27 balls of
// radius 4 on a pitch of n/3, marked in a bitmap of 64-cell words with the slot of each word's
// first marked node (MomentumExchange's MarkWord); each slot holds the node's particles' mass and
// momentum sums (made up: one particle of mass 1 moving at 0.01).
//
//   apart: gather (pre-collision rho, j of every slot, cell order, prefetched 16 nodes ahead as
//          FluidLattice::gather_momenta does), u* and the gain, the step, then the gain added
//          to every node's post-collision populations (prefetched the same way);
//   fused: the step, and after each row is swept, its marked nodes: rho and j from the
//          post-collision populations (BGK keeps both), u*, the gain, added at once.
// Both start from the same state; after a pair of steps every slot's u* and every population are
// compared (the two read the density and momentum before and after the collision: equal to
// round-off). Then each is timed against the step alone, in alternating rounds.
//
//   g++ -std=c++20 -O3 -march=native -ffp-contract=off -DNDEBUG -Icore
//       docs/experiments/fused_exchange_probe.cpp -o /tmp/fused_exchange_probe
//   taskset -c 1 /tmp/fused_exchange_probe 96 20       (a 96^3 box, 20 rounds of 10 steps)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "fluid/shifted_pull.h"
#include "lattice/d3q19.h"
using namespace lbsolid;
using L = lattice::D3Q19;
using T = double;
constexpr int W = 8, Q = L::Q;
using V = fluid::Lanes<T, W>;
using Bgk = fluid::BgkCollision<L, V>;
constexpr auto opp = lattice::opposite_table<L>();
constexpr T kOmega = 1.0, kRho0 = 1.0;

template <class F>
LBSOLID_FORCE_INLINE void each(F&& body) {
  [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA {
    (body(std::integral_constant<int, K>{}), ...);
  }(std::make_integer_sequence<int, Q>{});
}

struct MarkWord {
  std::uint64_t cells = 0;
  std::uint32_t first_slot = 0;
};

struct Box {
  long n, nx, nxy, cells, stride, pad;
  std::vector<T, std::allocator<T>> raw;
  T* a[Q];
  long off[Q];  // cell offset of direction k
  std::vector<MarkWord> marks;
  std::vector<long> slot_cell;
  std::vector<double> mass, momentum, velocity, gain;  // per slot (3 a slot for vectors)

  explicit Box(long size) : n(size), nx(size), nxy(size * size), cells(size * size * size) {
    pad = 2 * nxy + 64;  // a plane and more on each side: the line's ends read a plane off
    stride = cells + 2 * pad + 8 * 17;  // arrays a few lines apart, not a power of two
    raw.assign(static_cast<std::size_t>(Q * stride + 8), 0.0);
    T* base = raw.data();
    base += (8 - (reinterpret_cast<std::uintptr_t>(base) / sizeof(T)) % 8) % 8;
    for (int k = 0; k < Q; ++k) {
      a[k] = base + k * stride + pad;
      off[k] = static_cast<long>(L::c[k][0]) + static_cast<long>(L::c[k][1]) * nx + static_cast<long>(L::c[k][2]) * nxy;
    }
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    for (int k = 0; k < Q; ++k)
      for (long c = -pad; c < cells + pad; ++c) a[k][c] = L::w[k] * (1.0 + jitter(rng));
    // The balls: every node within 4 of a centre (n/3 apart, on the pitch's middles).
    marks.assign(static_cast<std::size_t>(cells / 64 + 1), {});
    const double pitch = static_cast<double>(n) / 3;
    std::vector<char> in_ball(static_cast<std::size_t>(cells), 0);
    for (int bz = 0; bz < 3; ++bz)
      for (int by = 0; by < 3; ++by)
        for (int bx = 0; bx < 3; ++bx) {
          const double cx = (bx + 0.5) * pitch, cy = (by + 0.5) * pitch, cz = (bz + 0.5) * pitch;
          for (long z = 0; z < n; ++z)
            for (long y = 0; y < n; ++y)
              for (long x = 0; x < n; ++x)
                if ((x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) <= 16.0)
                  in_ball[static_cast<std::size_t>(x + nx * y + nxy * z)] = 1;
        }
    for (long c = 0; c < cells; ++c)
      if (in_ball[static_cast<std::size_t>(c)]) {
        auto& word = marks[static_cast<std::size_t>(c >> 6)];
        if (word.cells == 0) word.first_slot = static_cast<std::uint32_t>(slot_cell.size());
        word.cells |= std::uint64_t{1} << (c & 63);
        slot_cell.push_back(c);
      }
    const long s = static_cast<long>(slot_cell.size());
    mass.assign(s, 1.0);
    momentum.assign(3 * s, 0.0);
    for (long k = 0; k < s; ++k) momentum[3 * k] = 0.01;
    velocity.assign(3 * s, 0.0);
    gain.assign(3 * s, 0.0);
  }
  long slots() const { return static_cast<long>(slot_cell.size()); }
};

// Where a node's populations are, before (pre) and after (post) the step: population k of cell c
// at pre[k][c], post[k][c]. Even step: pre A[k][c], post A[opp k][c]. Odd step: pre
// A[opp k][c - off k], post A[k][c + off k].
struct Slots {
  T* pre[Q];
  T* post[Q];
  Slots(const Box& b, bool odd) {
    for (int k = 0; k < Q; ++k) {
      pre[k] = odd ? b.a[opp[k]] - b.off[k] : b.a[k];
      post[k] = odd ? b.a[k] + b.off[k] : b.a[opp[k]];
    }
  }
};

// u* and the gain of slot s from the node's rho and j.
LBSOLID_FORCE_INLINE void compare(Box& b, long s, double rho, const double (&j)[3]) {
  const double m = b.mass[s], inv = 1.0 / (rho + m);
  for (int d = 0; d < 3; ++d) {
    const double p = b.momentum[3 * s + d];
    const double u = (j[d] + p) * inv;
    b.velocity[3 * s + d] = u;
    b.gain[3 * s + d] = p - m * u;
  }
}

LBSOLID_FORCE_INLINE void moments(T* const (&at)[Q], long c, double& rho, double (&j)[3]) {
  rho = 0;
  j[0] = j[1] = j[2] = 0;
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    const double f = at[K][c];
    rho += f;
    if constexpr (L::c[K][0] != 0) j[0] += L::c[K][0] * f;
    if constexpr (L::c[K][1] != 0) j[1] += L::c[K][1] * f;
    if constexpr (L::c[K][2] != 0) j[2] += L::c[K][2] * f;
  });
}

// Direction by direction (zero components cost nothing), the gain over c_s^2 worked out once.
LBSOLID_FORCE_INLINE void add_gain(T* const (&at)[Q], long c, const double* gain) {
  const double g[3] = {gain[0] / L::cs2, gain[1] / L::cs2, gain[2] / L::cs2};
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    if constexpr (K != 0) {
      double cg = 0;
      if constexpr (L::c[K][0] != 0) cg += L::c[K][0] * g[0];
      if constexpr (L::c[K][1] != 0) cg += L::c[K][1] * g[1];
      if constexpr (L::c[K][2] != 0) cg += L::c[K][2] * g[2];
      at[K][c] += L::w[K] * cg;
    }
  });
}

LBSOLID_FORCE_INLINE void prefetch_node(T* const (&at)[Q], long c, bool write) {
  for (int k = 0; k < Q; ++k) __builtin_prefetch(at[k] + c, write ? 1 : 0);
}

// The separate passes: the pre-collision read and comparison, the post-collision injection.
__attribute__((noinline)) void gather_compare(Box& b, const Slots& at) {
  const long s_count = b.slots();
  for (long s = 0; s < s_count; ++s) {
    if (s + 16 < s_count) prefetch_node(at.pre, b.slot_cell[s + 16], false);
    double rho, j[3];
    moments(at.pre, b.slot_cell[s], rho, j);
    compare(b, s, rho, j);
  }
}
__attribute__((noinline)) void inject(Box& b, const Slots& at) {
  const long s_count = b.slots();
  for (long s = 0; s < s_count; ++s) {
    if (s + 16 < s_count) prefetch_node(at.post, b.slot_cell[s + 16], true);
    add_gain(at.post, b.slot_cell[s], &b.gain[3 * s]);
  }
}

// The fused work for the cells [first, end) just swept: their marked nodes, read after the
// collision and given their gain at once.
LBSOLID_FORCE_INLINE void exchange_row(Box& b, const Slots& at, long first, long end) {
  for (long w = first >> 6; w <= (end - 1) >> 6; ++w) {
    const MarkWord word = b.marks[static_cast<std::size_t>(w)];
    std::uint64_t bits = word.cells;
    if (bits == 0) continue;
    const long word_first = w << 6;
    while (bits) {
      const int bit = __builtin_ctzll(bits);
      const long c = word_first + bit;
      bits &= bits - 1;
      if (c < first || c >= end) continue;
      const long s = word.first_slot + __builtin_popcountll(word.cells & ((std::uint64_t{1} << bit) - 1));
      double rho, j[3];
      moments(at.post, c, rho, j);
      compare(b, s, rho, j);
      add_gain(at.post, c, &b.gain[3 * s]);
    }
  }
}

// The even sweep over the planes' cells [begin, end) (multiples of W), row by row when fused.
template <bool kFused>
__attribute__((noinline)) void even_step(Box& b, const Slots& at) {
  const V omega_v(kOmega), rho0_v(kRho0);
  const V force_v[3] = {V(0.0), V(0.0), V(0.0)};
  for (long row = 0; row < b.n * b.n; ++row) {
    const long first = row * b.nx, end = first + b.nx;
    for (long c = first; c < end; c += W) {
      V f[Q];
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA { f[K] = V::load_aligned(b.a[K] + c); });
      const auto state = Bgk::template node_state<false>(f, rho0_v, force_v);
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        Bgk::template relaxed<false, K>(f[K], state, omega_v, force_v).store_aligned(b.a[opp[K]] + c);
      });
    }
    if constexpr (kFused) exchange_row(b, at, first, end);
  }
}

// The odd sweep: each plane's rows as one line, cut at each row join (as the fluid's sweep is);
// when fused, row r's nodes are done once the sweep has passed the vector holding row r + 1's
// first cell (every slot of row r's interior written by then).
template <bool kFused>
__attribute__((noinline)) void odd_step(Box& b, const Slots& at) {
  using Shifted = fluid::ShiftedPull<L, T, W>;
  const T* in[Q];
  T* out[Q];
  for (int k = 0; k < Q; ++k) {
    in[k] = b.a[opp[k]] - b.off[k];
    out[k] = b.a[k] + b.off[k];
  }
  const T force[3] = {0, 0, 0};
  for (long z = 0; z < b.n; ++z) {
    const long plane = z * b.nxy;
    long done = Shifted::first_cell(plane + 1);
    for (long y = 0; y < b.n; ++y) {
      const long join = plane + (y + 1) * b.nx;
      const long before = std::min((join - 1) / W * W, Shifted::end_cell(plane + b.nxy - 1));
      if (before > done) {
        Shifted::template run<false>(in, out, force, kOmega, kRho0, done, before);
        done = before;
      }
      if constexpr (kFused)
        if (y > 0) exchange_row(b, at, plane + (y - 1) * b.nx + 1, plane + y * b.nx - 1);
    }
    const long end = Shifted::end_cell(plane + b.nxy - 1);
    if (end > done) Shifted::template run<false>(in, out, force, kOmega, kRho0, done, end);
    if constexpr (kFused) exchange_row(b, at, plane + (b.n - 1) * b.nx + 1, plane + b.nxy - 1);
  }
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A pair of steps; `passes` gets the time the separate passes took (apart).
template <bool kFused, bool kApart>
void step_pair(Box& b, double& passes) {
  for (int parity = 0; parity < 2; ++parity) {
    const Slots at(b, parity == 1);
    if constexpr (kApart) {
      const auto t0 = Clock::now();
      gather_compare(b, at);
      passes += seconds_since(t0);
    }
    if (parity == 0) even_step<kFused>(b, at);
    else odd_step<kFused>(b, at);
    if constexpr (kApart) {
      const auto t0 = Clock::now();
      inject(b, at);
      passes += seconds_since(t0);
    }
  }
}

int main(int argc, char** argv) {
  const long n = argc > 1 ? std::atol(argv[1]) : 96;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 20;
  if (n % W != 0 || n < 4 * W) {
    std::fprintf(stderr, "n: a multiple of %d, at least %d\n", W, 4 * W);
    return 2;
  }
  Box apart(n), fused(n);
  std::printf("%ld^3 box, %ld coupled nodes\n", n, apart.slots());
  // The check: a pair of steps each way from the same state.
  double ignored = 0;
  step_pair<false, true>(apart, ignored);
  step_pair<true, false>(fused, ignored);
  double worst_u = 0, worst_f = 0;
  for (long s = 0; s < apart.slots(); ++s)
    for (int d = 0; d < 3; ++d)
      worst_u = std::max(worst_u, std::abs(apart.velocity[3 * s + d] - fused.velocity[3 * s + d]));
  for (int k = 0; k < Q; ++k)
    for (long c = 0; c < apart.cells; ++c) worst_f = std::max(worst_f, std::abs(apart.a[k][c] - fused.a[k][c]));
  std::printf("after a pair of steps: largest difference in u* %.3g, in a population %.3g\n", worst_u, worst_f);

  const int steps = 10;  // 5 pairs a round
  // A round's time a step, and (apart) its passes' time a step.
  auto time = [&](auto&& body, double* passes_per_step = nullptr) {
    double passes = 0;
    const auto t0 = Clock::now();
    for (int p = 0; p < steps / 2; ++p) body(passes);
    const double total = seconds_since(t0) / steps;
    if (passes_per_step) *passes_per_step = passes / steps;
    return total;
  };
  double best_fluid = 1e9, best_apart = 1e9, best_fused = 1e9, best_passes = 1e9;
  for (int r = 0; r < rounds; ++r) {
    double passes = 0;
    best_fluid = std::min(best_fluid, time([&](double& t) { step_pair<false, false>(apart, t); }));
    best_apart = std::min(best_apart, time([&](double& t) { step_pair<false, true>(apart, t); }, &passes));
    best_passes = std::min(best_passes, passes);
    best_fluid = std::min(best_fluid, time([&](double& t) { step_pair<false, false>(fused, t); }));
    best_fused = std::min(best_fused, time([&](double& t) { step_pair<true, false>(fused, t); }));
  }
  const double per_node = 1e9 / static_cast<double>(apart.slots());
  std::printf("best of %d rounds of %d steps: step alone %.3f ms (%.1f MLUPS)\n", rounds, steps, best_fluid * 1e3,
              static_cast<double>(apart.cells) / best_fluid * 1e-6);
  std::printf("  apart: %.3f ms, over the step alone %.1f ns a node; the passes' own clock %.1f ns a node\n",
              best_apart * 1e3, (best_apart - best_fluid) * per_node, best_passes * per_node);
  std::printf("  fused: %.3f ms, over the step alone %.1f ns a node\n", best_fused * 1e3,
              (best_fused - best_fluid) * per_node);
  return 0;
}
