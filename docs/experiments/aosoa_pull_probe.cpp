// A measurement, not part of the build (the version it led to, joined rows with the join slots
// moved by a row, is the fluid's own since: core/fluid/blocked_kernel.h): the in-place D3Q19 pulling sweep (the odd step of the
// AA pattern, BGK, no force) and the local (even) sweep over one long line of a box's interior,
// in today's layout (19 arrays of cells; the pulling sweep is ShiftedPull::run as the fluid
// uses it, the local one a plain loop here, slower than the fluid's) and in blocks of W cells
// with a block's 19 population vectors side by side (cell c's population j at
// a[(c / W) Q W + j W + c mod W]). In blocks every stream is addressed from the block pointer
// plus one of 9 offsets (one per (c_y, c_z)) and a constant, instead of 38 stream pointers. Row
// ends are not treated (both layouts alike; the fluid handles them apart). Both layouts start
// from the same random state; every slot is compared after a pulling and a local sweep, then
// each sweep is timed (best of `reps` rounds, the variants in turn), and a gather of the 3D
// scene's nodes' moments (what the coupling reads) right after a local sweep. Last, a pulling
// sweep in blocks with each row periodic in x, row by row and as joined rows (chunks of
// JOINED_ROWS rows swept as one line, the joins put right in two ways), checked against a scalar
// reference and timed against the line and the fluid's own steps (which need the core library
// built).
//
//   g++ -std=c++20 -O3 -march=native -ffp-contract=off -DNDEBUG -Icore
//       docs/experiments/aosoa_pull_probe.cpp build/core/liblbsolid_core.a -lpthread
//       -o /tmp/aosoa_pull_probe                                    (-DFLOAT for float)
//   taskset -c 1 /tmp/aosoa_pull_probe 128 20     (a 128^3 box, 20 rounds; a third argument:
//                                                  the pulling sweeps alone)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>
#include <algorithm>
#include <cmath>
#include "fluid/fluid_lattice.h"
#include "fluid/population_storage.h"
#include "fluid/shifted_pull.h"
#include "lattice/d3q19.h"
using namespace lbsolid;
using L = lattice::D3Q19;
#ifdef FLOAT
using T = float;
constexpr int W = 16, Q = L::Q;
#else
using T = double;
constexpr int W = 8, Q = L::Q;
#endif
// A block's length in values: its Q population vectors (padding it by 1, 3 or 5 vectors changed
// nothing measurable).
constexpr long BS = Q * W;
#ifndef JOINED_ROWS
#define JOINED_ROWS 32
#endif
constexpr int kJoinedRows = JOINED_ROWS;  // rows a chunk of blocks_joined_run
#ifndef AHEAD
#define AHEAD 8
#endif

using V = fluid::Lanes<T, W>;
using Bgk = fluid::BgkCollision<L, V>;
constexpr auto opp = lattice::opposite_table<L>();
constexpr int cx(int k) { return static_cast<int>(L::c[k][0]); }
constexpr int cy(int k) { return static_cast<int>(L::c[k][1]); }
constexpr int cz(int k) { return static_cast<int>(L::c[k][2]); }
// (cy, cz) combination of direction k: 0..8
constexpr int combo(int k) { return (cy(k) + 1) * 3 + (cz(k) + 1); }

template <class F> LBSOLID_FORCE_INLINE void each(F&& body) {
  [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA { (body(std::integral_constant<int, K>{}), ...); }(
      std::make_integer_sequence<int, Q>{});
}

// The sweep in blocks: population K of cell c is read from array opp(K) at cell c - off(K);
// o[m]: the element offset from a cell's block to the block of its source cell for the (c_y,
// c_z) combination m (a multiple of BS: the y and z shifts move whole blocks).
__attribute__((noinline)) void aosoa_run_offsets(T* a, const long (&o)[9], long begin, long end, T omega, T rho0) {
  const T force[3] = {0, 0, 0};
  const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
  const V omega_v(omega), rho0_v(rho0);
  V last[Q];
  T* p0 = a + (begin / W) * BS;
  // f*_K is written into the slot read for opp(K): array K at cell c + off(K). As in
  // ShiftedPull::run, each x-shifted stream's aligned block is completed from this vector's
  // results and the last one's; before the first, those lanes hold the slots as they are.
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    constexpr int x = cx(K);
    const T* blk = p0 + o[combo(opp[K])] + K * W;  // array K, the block of cells begin + (cy nx + cz nxy)
    if constexpr (x == 1) last[K] = fluid::lanes_from<1>(V::load_aligned(blk - BS), V::load_aligned(blk));
    else if constexpr (x == -1) last[K] = fluid::lanes_from<W - 1>(V(0.0), V::load_aligned(blk - BS));
  });
  for (T* p = p0, *pend = a + (end / W) * BS; p < pend; p += BS) {
    V f[Q];
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K), j = opp[K];
      const T* blk = p + o[combo(K)] + j * W;  // array j, block of cells c - (cy nx + cz nxy)
      if constexpr (x == 0) f[K] = V::load_aligned(blk);
      else if constexpr (x == 1) f[K] = fluid::lanes_from<W - 1>(V::load_aligned(blk - BS), V::load_aligned(blk));  // cells c-1..
      else f[K] = fluid::lanes_from<1>(V::load_aligned(blk), V::load_aligned(blk + BS));  // cells c+1..
    });
    const auto state = Bgk::template node_state<false>(f, rho0_v, force_v);
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      f[K] = Bgk::template relaxed<false, K>(f[K], state, omega_v, force_v);
    });
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      T* blk = p + o[combo(opp[K])] + K * W;  // array K, block of cells c + (cy nx + cz nxy)
      if constexpr (x == 0) f[K].store_aligned(blk);
      else if constexpr (x == 1) {  // the block holds the results of cells c-1 .. c+W-2
        fluid::lanes_from<W - 1>(last[K], f[K]).store_aligned(blk);
      } else {  // the block before holds those of cells c-W+1 .. c
        fluid::lanes_from<1>(last[K], f[K]).store_aligned(blk - BS);
      }
      last[K] = f[K];
    });
  }
  T* pe = a + (end / W) * BS;
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    constexpr int x = cx(K);
    T* blk = pe + o[combo(opp[K])] + K * W;
    if constexpr (x == 1) {
      const V cur = V::load_aligned(blk);
      fluid::lanes_from<W - 1>(last[K], fluid::lanes_from<1>(cur, cur)).store_aligned(blk);
    } else if constexpr (x == -1) {
      const V cur = V::load_aligned(blk - BS);
      fluid::lanes_from<1>(last[K], fluid::lanes_from<W - 1>(cur, cur)).store_aligned(blk - BS);
    }
  });
}

// The same with the flat offsets of an interior row (cell c - (c_y n_x + c_z n_xy)).
void aosoa_run(T* a, long nx, long nxy, long begin, long end, T omega, T rho0) {
  long o[9];
  for (int m = 0; m < 9; ++m) o[m] = -((m / 3 - 1) * nx + (m % 3 - 1) * nxy) / W * BS;
  aosoa_run_offsets(a, o, begin, end, omega, rho0);
}

// Block p's results in f: its inputs from the blocks of the 9 row offsets o, the x-shifted
// lanes from the blocks `prev` and `next` values away (the row's wrap where it applies).
LBSOLID_FORCE_INLINE void pull_collide_block(const T* p, const long (&o)[9], long prev, long next, V omega_v,
                                             V rho0_v, V (&f)[Q]) {
  const V force_v[3] = {V(0.0), V(0.0), V(0.0)};
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    constexpr int x = cx(K), j = opp[K];
    const T* blk = p + o[combo(K)] + j * W;
    if constexpr (x == 0) f[K] = V::load_aligned(blk);
    else if constexpr (x == 1) f[K] = fluid::lanes_from<W - 1>(V::load_aligned(blk + prev), V::load_aligned(blk));
    else f[K] = fluid::lanes_from<1>(V::load_aligned(blk), V::load_aligned(blk + next));
  });
  const auto state = Bgk::template node_state<false>(f, rho0_v, force_v);
  each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
    f[K] = Bgk::template relaxed<false, K>(f[K], state, omega_v, force_v);
  });
}

// The pulling sweep in blocks row by row, each row periodic in x (as the fluid's rows are).
// A row's blocks are taken in the order 1, 2, .., nb - 1, 0, so that the wrapped inputs (block
// 0's c_x = +1 lanes from block nb - 1, block nb - 1's c_x = -1 lanes from block 0) are read
// where the sweep has just been, not a row ahead. The shifted streams' lines that hold block 0's
// or block 1's results are written once block 0 is done, from block 1's and block nb - 1's
// results kept until then. (The order 0 .. nb - 1, in which block 0 reads the row's last
// block a row ahead of the sweep, measured the same.)
__attribute__((noinline)) void blocks_rows_run(T* a, long nx, long nxy, long first_row, long end_row, T omega,
                                               T rho0) {
  const V omega_v(omega), rho0_v(rho0);
  const long nb = nx / W;
  long o[9];
  for (int m = 0; m < 9; ++m) o[m] = -((m / 3 - 1) * nx + (m % 3 - 1) * nxy) / W * BS;
  // Block 1 (taken first), blocks 2 .. nb - 2, block nb - 1, block 0 (taken last). Only blocks 0
  // and nb - 1 reach across the row's wrap; the others' neighbours are constant offsets, which
  // the compiler folds into the loads (a neighbour offset chosen at run time for every block
  // made the sweep twice as slow at 64^3). nb >= 3.
  enum Kind { kSecond, kMiddle, kLastBlock, kFirst };
  for (long row = first_row; row < end_row; ++row) {
    T* const r0 = a + row * nb * BS;
    V last[Q];
    // Blocks 1's and nb - 1's results wait in memory for the row's end: kept as values (20
    // more vector registers through the row) GCC spilled the double sweep's registers and it
    // ran at a third of the line's speed; this way double runs near the line at 128^3 and float
    // at half of it (docs/performance.md).
    alignas(64) T second[Q][W], last_block[Q][W];
    auto block = [&]<int kKind>(std::integral_constant<int, kKind>, long b) LBSOLID_FORCE_INLINE_LAMBDA {
      T* const p = r0 + b * BS;
      long prev = -BS, next = BS;  // the blocks before and after in x, wrapping in the row
      if constexpr (kKind == kFirst) prev = (nb - 1) * BS;
      if constexpr (kKind == kLastBlock) next = -(nb - 1) * BS;
      V f[Q];
      pull_collide_block(p, o, prev, next, omega_v, rho0_v, f);
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int x = cx(K);
        T* blk = p + o[combo(opp[K])] + K * W;
        if constexpr (x == 0) {
          f[K].store_aligned(blk);
        } else {
          if constexpr (kKind == kSecond) f[K].store_aligned(second[K]);
          else if constexpr (kKind == kFirst) last[K].store_aligned(last_block[K]);
          else if constexpr (x == 1) fluid::lanes_from<W - 1>(last[K], f[K]).store_aligned(blk);
          else fluid::lanes_from<1>(last[K], f[K]).store_aligned(blk - BS);
          last[K] = f[K];
        }
      });
    };
    block(std::integral_constant<int, kSecond>{}, 1);
    for (long b = 2; b < nb - 1; ++b) block(std::integral_constant<int, kMiddle>{}, b);
    block(std::integral_constant<int, kLastBlock>{}, nb - 1);
    block(std::integral_constant<int, kFirst>{}, 0);
    // last: block 0's results; last_block: block nb - 1's; second: block 1's.
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      T* blk0 = r0 + o[combo(opp[K])] + K * W;
      if constexpr (x == 1) {
        fluid::lanes_from<W - 1>(V::load_aligned(last_block[K]), last[K]).store_aligned(blk0);
        fluid::lanes_from<W - 1>(last[K], V::load_aligned(second[K])).store_aligned(blk0 + BS);
      } else if constexpr (x == -1) {
        fluid::lanes_from<1>(V::load_aligned(last_block[K]), last[K]).store_aligned(blk0 + (nb - 1) * BS);
        fluid::lanes_from<1>(last[K], V::load_aligned(second[K])).store_aligned(blk0);
      }
    });
  }
}

// The same with the line's own loop (aosoa_run, which compiles well in both precisions) over a
// row's middle blocks 1 .. nb - 2, then blocks 0 and nb - 1 with the row's wrap, and the lines
// they share with the middle corrected lane by lane. nb >= 3.
__attribute__((noinline)) void blocks_rows_run_line(T* a, long nx, long nxy, long first_row, long end_row,
                                                    T omega, T rho0) {
  const V omega_v(omega), rho0_v(rho0);
  const long nb = nx / W;
  long o[9];
  for (int m = 0; m < 9; ++m) o[m] = -((m / 3 - 1) * nx + (m % 3 - 1) * nxy) / W * BS;
  for (long row = first_row; row < end_row; ++row) {
    aosoa_run(a, nx, nxy, row * nx + W, row * nx + nx - W, omega, rho0);
    T* const r0 = a + row * nb * BS;
    T* const rl = r0 + (nb - 1) * BS;
    const long wrap = (nb - 1) * BS;
    V f0[Q], fl[Q];
    pull_collide_block(r0, o, wrap, BS, omega_v, rho0_v, f0);
    pull_collide_block(rl, o, -BS, -wrap, omega_v, rho0_v, fl);
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      T* d0 = r0 + o[combo(opp[K])] + K * W;  // block 0's line of this stream's results
      T* dl = rl + o[combo(opp[K])] + K * W;  // block nb - 1's
      if constexpr (x == 0) {
        f0[K].store_aligned(d0);
        fl[K].store_aligned(dl);
      } else if constexpr (x == 1) {  // a block's line holds the results of cells bW - 1 .. bW + W - 2
        fluid::lanes_from<W - 1>(fl[K], f0[K]).store_aligned(d0);
        const V next = V::load_aligned(d0 + BS);  // lane 0 (cell W - 1) left as it was by the middle
        fluid::lanes_from<W - 1>(f0[K], fluid::lanes_from<1>(next, next)).store_aligned(d0 + BS);
        const V own = V::load_aligned(dl);  // lane 0 (cell nx - W - 1) is the middle's
        fluid::lanes_from<W - 1>(fluid::lanes_from<1>(own, own), fl[K]).store_aligned(dl);
      } else {  // a block's line holds the results of cells bW + 1 .. bW + W
        const V own = V::load_aligned(d0);  // lane W - 1 (cell W) is the middle's
        fluid::lanes_from<1>(f0[K], fluid::lanes_from<W - 1>(own, own)).store_aligned(d0);
        const V before = V::load_aligned(dl - BS);  // lanes 0 .. W - 2 are the middle's
        fluid::lanes_from<1>(fluid::lanes_from<W - 1>(before, before), fl[K]).store_aligned(dl - BS);
        fluid::lanes_from<1>(fl[K], f0[K]).store_aligned(dl);
      }
    });
  }
}

// Joined rows, as the fluid sweeps its 19 arrays today, carried over to blocks: chunks of R rows
// swept as one line by aosoa_run (wrong only at the joins, where a row's first cell reads the
// row before's last and the other way round), with each row's two edge cells redone apart. Per
// chunk: the edge cells' inputs saved (periodic in x), a row's into lane r mod W of a vector per
// direction; the line swept; the edge cells collided W rows at a time from the saved inputs and
// their 19 results written to their own slots. The line's first and last cells also write 5
// slots outside the chunk each, owned by the edge cells of the rows just before and after it:
// those are saved first and put back. R a multiple of W.
template <int R>
__attribute__((noinline)) void blocks_joined_run(T* a, long nx, long ny, long first_row, long end_row, T omega,
                                                 T rho0) {
  const long nxy = nx * ny, nb = nx / W, row_len = nb * BS;
  const V omega_v(omega), rho0_v(rho0);
  const V force_v[3] = {V(0.0), V(0.0), V(0.0)};
  // Slot (array j, cell (x, row r + dr)) at r row_len + at(j, x, dr).
  auto at = [&](int j, long x, long dr) { return dr * row_len + (x / W) * BS + j * W + x % W; };
  // Per direction K and edge e (x = 0, nx - 1): its input, array opp(K) at x - c_x, wrapped in
  // the row, row r - c_y - c_z ny; its result, array K at x + c_x, row r + c_y + c_z ny.
  long in_at[2][Q], out_at[2][Q];
  for (int e = 0; e < 2; ++e) for (int k = 0; k < Q; ++k) {
    const long x = e == 0 ? 0 : nx - 1, dr = cy(k) + cz(k) * ny;
    in_at[e][k] = at(opp[k], (x - cx(k) + nx) % nx, -dr);
    out_at[e][k] = at(k, (x + cx(k) + nx) % nx, dr);
  }
  alignas(64) T saved[2][Q][R];
  for (long r0 = first_row; r0 < end_row; r0 += R) {
    const long r1 = std::min(end_row, r0 + R);
    // The 10 slots outside the chunk that the line's end cells write (array K at the line's
    // first cell + off(K) for c_x = -1, at its last + off(K) for c_x = +1).
    long outside[10];
    T outside_value[10];
    int n_outside = 0;
    for (int k = 0; k < Q; ++k) {
      const long yz = cy(k) * nx + cz(k) * nxy;
      long c = -1;
      if (cx(k) == -1) c = r0 * nx - 1 + yz;
      if (cx(k) == 1) c = r1 * nx + yz;
      if (c < 0) continue;
      outside[n_outside] = (c / W) * BS + k * W + c % W;
      outside_value[n_outside] = a[outside[n_outside]];
      ++n_outside;
    }
    for (long r = r0; r < r1; ++r) {
      const T* row = a + r * row_len;
      for (int e = 0; e < 2; ++e) for (int k = 0; k < Q; ++k) saved[e][k][r - r0] = row[in_at[e][k]];
    }
    aosoa_run(a, nx, nxy, r0 * nx, r1 * nx, omega, rho0);
    for (long g = r0; g < r1; g += W) {
      for (int e = 0; e < 2; ++e) {
        V f[Q];
        each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
          f[K] = V::load_aligned(&saved[e][K][g - r0]);
        });
        const auto state = Bgk::template node_state<false>(f, rho0_v, force_v);
        alignas(64) T result[Q][W];
        each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
          Bgk::template relaxed<false, K>(f[K], state, omega_v, force_v).store_aligned(result[K]);
        });
        for (long r = g; r < std::min(r1, g + W); ++r) {
          T* row = a + r * row_len;
          for (int k = 0; k < Q; ++k) row[out_at[e][k]] = result[k][r - g];
        }
      }
    }
    for (int i = 0; i < n_outside; ++i) a[outside[i]] = outside_value[i];
  }
}

// Joined rows without an edge buffer: before a chunk's line is swept, the 5 + 5 slots per row
// that the line's first and last cells of each row read across the join are moved by one row,
// so that each finds its own row's wrapped value there; the line then computes every cell
// right, and the same slots (which now hold the results, a row off) are moved back after.
// For c_x(K) = +1, cell (0, r)'s input K, S(r) = array opp(K) at (nx - 1, r - dr_K), is read
// by the line at S(r - 1); for c_x(K) = -1, cell (nx - 1, r)'s, T(r) = array opp(K) at
// (0, r - dr_K), at T(r + 1). S(r0 - 1) and T(r1), outside the chunk, are saved and put back.
// One chunk of rows [r0, r1) whose cells share the source offsets o (aosoa_run_offsets): the
// join slots moved, the line swept, the slots moved back. S(r) = r row_len + o[combo(K)] + the
// slot of cell (nx - 1) in array opp(K); T(r) the same at cell 0.
void rotated_chunk(T* a, const long (&o)[9], long nb, long r0, long r1, T omega, T rho0) {
  const long row_len = nb * BS;
  long s_at[5], t_at[5];
  int ns = 0, nt = 0;
  for (int k = 0; k < Q; ++k) {
    if (cx(k) == 1) s_at[ns++] = o[combo(k)] + (nb - 1) * BS + opp[k] * W + (W - 1);
    if (cx(k) == -1) t_at[nt++] = o[combo(k)] + opp[k] * W;
  }
  T s_outside[5], t_outside[5];
  for (int i = 0; i < 5; ++i) {
    T* s = a + s_at[i];
    s_outside[i] = s[(r0 - 1) * row_len];
    for (long r = r0; r < r1; ++r) s[(r - 1) * row_len] = s[r * row_len];
    T* t = a + t_at[i];
    t_outside[i] = t[r1 * row_len];
    for (long r = r1 - 1; r >= r0; --r) t[(r + 1) * row_len] = t[r * row_len];
  }
  aosoa_run_offsets(a, o, r0 * nb * W, r1 * nb * W, omega, rho0);
  for (int i = 0; i < 5; ++i) {
    T* s = a + s_at[i];
    for (long r = r1 - 1; r >= r0; --r) s[r * row_len] = s[(r - 1) * row_len];
    s[(r0 - 1) * row_len] = s_outside[i];
    T* t = a + t_at[i];
    for (long r = r0; r < r1; ++r) t[r * row_len] = t[(r + 1) * row_len];
    t[r1 * row_len] = t_outside[i];
  }
}

// Chunks of R interior rows (flat y and z offsets) through rotated_chunk.
template <int R>
__attribute__((noinline)) void blocks_rotated_run(T* a, long nx, long ny, long first_row, long end_row, T omega,
                                                  T rho0) {
  const long nxy = nx * ny;
  long o[9];
  for (int m = 0; m < 9; ++m) o[m] = -((m / 3 - 1) * nx + (m % 3 - 1) * nxy) / W * BS;
  for (long r0 = first_row; r0 < end_row; r0 += R) rotated_chunk(a, o, nx / W, r0, std::min(end_row, r0 + R), omega, rho0);
}

// The whole pulling step of a box periodic in x, y and z: each plane's rows y = 1 .. ny - 2 in
// chunks of up to R rows, rows 0 and ny - 1 alone (their y sources wrap), each with the source
// offsets of its (y, z) class.
template <int R>
__attribute__((noinline)) void blocks_box_pull(T* a, long nx, long ny, long nz, T omega, T rho0) {
  const long nb = nx / W;
  auto offsets = [&](long y, long z, long (&o)[9]) {
    for (int m = 0; m < 9; ++m) {
      const long dy = m / 3 - 1, dz = m % 3 - 1;  // the source is at y - dy, z - dz, wrapped
      const long ys = (y - dy + ny) % ny, zs = (z - dz + nz) % nz;
      o[m] = ((ys - y) + (zs - z) * ny) * nb * BS;
    }
  };
  for (long z = 0; z < nz; ++z) {
    long o[9];
    const long plane = z * ny;
    offsets(0, z, o);
    rotated_chunk(a, o, nb, plane, plane + 1, omega, rho0);
    offsets(1, z, o);
    for (long y = 1; y < ny - 1; y += R) rotated_chunk(a, o, nb, plane + y, plane + std::min(ny - 1, y + R), omega, rho0);
    offsets(ny - 1, z, o);
    rotated_chunk(a, o, nb, plane + ny - 1, plane + ny, omega, rho0);
  }
}

// The even (local) step: each cell's own 19 populations, written back reversed (array opp(K)).
// In 19 arrays: population K of cell c at f[K stride + c]; in blocks: at its block's K W + lane.
template <bool kBlocks>
__attribute__((noinline)) void local_run(T* f, long stride, long begin, long end, T omega, T rho0) {
  const V force_v[3] = {V(0.0), V(0.0), V(0.0)};
  const V omega_v(omega), rho0_v(rho0);
  for (long c = begin; c < end; c += W) {
    T* at = kBlocks ? f + (c / W) * BS : f + c;
    const long step = kBlocks ? W : stride;
    V v[Q];
    // In blocks one stream crosses a 4 KB page every 3.4 blocks, and the hardware does not fetch
    // ahead across pages: without asking for the lines AHEAD blocks early (-DAHEAD=0), the local
    // sweep in blocks ran 30-40% slower than in the 19 padded arrays; with it, about as fast.
    if constexpr (kBlocks && AHEAD > 0)
      for (int line = 0; line < Q; ++line) __builtin_prefetch(at + AHEAD * BS + line * (64 / sizeof(T)), 1);
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA { v[K] = V::load_aligned(at + K * step); });
    const auto state = Bgk::template node_state<false>(v, rho0_v, force_v);
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      Bgk::template relaxed<false, K>(v[K], state, omega_v, force_v).store_aligned(at + opp[K] * step);
    });
  }
}

// What the coupling's gather does a node: its density and momentum from its 19 populations.
template <bool kBlocks>
__attribute__((noinline)) double gather(const T* f, long stride, const std::vector<long>& nodes, double* out) {
  double total = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const long c = nodes[i];
    const T* at = kBlocks ? f + (c / W) * BS + c % W : f + c;
    const long step = kBlocks ? W : stride;
    double rho = 0, j[3] = {0, 0, 0};
    for (int k = 0; k < Q; ++k) {
      const double v = at[k * step];
      rho += v;
      j[0] += cx(k) * v;
      j[1] += cy(k) * v;
      j[2] += cz(k) * v;
    }
    out[4 * i] = rho;
    out[4 * i + 1] = j[0];
    out[4 * i + 2] = j[1];
    out[4 * i + 3] = j[2];
    total += rho;
  }
  return total;
}

int main(int argc, char** argv) {
  const long n = argc > 1 ? atol(argv[1]) : 128;
  const int reps = argc > 2 ? atoi(argv[2]) : 10;
  const long nx = n, ny = n, nz = n, nxy = nx * ny, cells = nxy * nz;
  // The 19 arrays as the fluid stores them (padded so that they start on distinct cache sets).
  fluid::PopulationStorage<T> storage(1, Q, cells);
  const long stride = storage.stride();
  T* soa = storage.buffer(0);
  // A block of margin at each end: a box's first row reads (and its rotation moves) a slot of
  // the block before it, and its last the block after.
  std::vector<T> aos_buf(Q * cells + 2 * BS + 64);
  T* aos = reinterpret_cast<T*>((reinterpret_cast<uintptr_t>(aos_buf.data()) + 63) & ~uintptr_t(63)) + BS;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<T> u(0.9 / 19, 1.1 / 19);
  for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) {
    const T v = u(rng); soa[j * stride + c] = v; aos[(c / W) * BS + j * W + c % W] = v; }
  const long begin = 2 * nxy, end = (nz - 2) * nxy;  // whole vectors, z neighbours inside
  auto off = [&](int k) { return cx(k) + cy(k) * nx + cz(k) * nxy; };
  const T* in[Q]; T* out[Q];
  for (int k = 0; k < Q; ++k) in[k] = soa + opp[k] * stride - off(k);
  for (int k = 0; k < Q; ++k) out[k] = soa + k * stride + off(k);
  using SP = fluid::ShiftedPull<L, T, W>;
  const T force[3] = {0, 0, 0};
  if (!SP::streams_fit(in, out)) { printf("streams do not fit\n"); return 1; }
  // One pulling sweep and one local sweep each from the same state, then every slot compared.
  auto count_differing = [&] {
    long bad = 0;
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c)
      if (soa[j * stride + c] != aos[(c / W) * BS + j * W + c % W]) ++bad;
    return bad;
  };
  SP::run<false>(in, out, force, 1.3, 1.0, begin, end);
  aosoa_run(aos, nx, nxy, begin, end, 1.3, 1.0);
  printf("slots differing after a pulling sweep: %ld of %ld\n", count_differing(), Q * cells);
  local_run<false>(soa, stride, begin, end, 1.3, 1.0);
  local_run<true>(aos, stride, begin, end, 1.3, 1.0);
  printf("slots differing after a local sweep too: %ld of %ld\n", count_differing(), Q * cells);
  double best[4] = {1e9, 1e9, 1e9, 1e9};
  const int variants = argc > 3 ? 2 : 4;  // a third argument: the pulling sweeps alone
  for (int r = 0; r < reps; ++r) for (int v = 0; v < variants; ++v) {
    auto t0 = std::chrono::steady_clock::now();
    if (v == 0) SP::run<false>(in, out, force, 1.0, 1.0, begin, end);
    else if (v == 1) aosoa_run(aos, nx, nxy, begin, end, 1.0, 1.0);
    else if (v == 2) local_run<false>(soa, stride, begin, end, 1.0, 1.0);
    else local_run<true>(aos, stride, begin, end, 1.0, 1.0);
    best[v] = std::min(best[v], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  // Rows periodic in x: blocks_rows_run against a scalar reference (rows wrap in x; y and z
  // offsets as in the line), from the same state, every slot compared; then timed against the
  // line sweep in blocks (which leaves the row ends wrong) and the fluid's own in-place pulling
  // step on a periodic box of the same size (its row ends right, through its edge buffers).
  if (nx / W >= 3) {
    std::vector<T> ref(Q * cells), before(Q * cells);
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) before[j * cells + c] = aos[(c / W) * BS + j * W + c % W];
    ref = before;
    using Scalar = fluid::BgkCollision<L, T>;
    const long first_row = 2 * ny, end_row = (nz - 2) * ny;
    auto pos = [&](long c, int sx, long yz) { const long rs = c / nx * nx; return rs + ((c - rs + sx) % nx + nx) % nx + yz; };
    for (long c = first_row * nx; c < end_row * nx; ++c) {
      T fin[Q];
      for (int k = 0; k < Q; ++k) fin[k] = before[opp[k] * cells + pos(c, -cx(k), -(cy(k) * nx + cz(k) * nxy))];
      const auto st = Scalar::template node_state<false>(fin, T(1.0), force);
      [&]<int... K>(std::integer_sequence<int, K...>) {
        ((ref[K * cells + pos(c, cx(K), cy(K) * nx + cz(K) * nxy)] = Scalar::template relaxed<false, K>(fin[K], st, T(1.3), force)), ...);
      }(std::make_integer_sequence<int, Q>{});
    }
    auto differing = [&] {
      long bad = 0;
      for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c)
        if (ref[j * cells + c] != aos[(c / W) * BS + j * W + c % W]) ++bad;
      return bad;
    };
    blocks_rows_run(aos, nx, nxy, first_row, end_row, 1.3, 1.0);
    printf("rows periodic in x, blocks against the scalar reference: %ld of %ld slots differ\n", differing(), Q * cells);
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) aos[(c / W) * BS + j * W + c % W] = before[j * cells + c];
    blocks_rows_run_line(aos, nx, nxy, first_row, end_row, 1.3, 1.0);
    printf("the same through the line's loop: %ld of %ld slots differ\n", differing(), Q * cells);
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) aos[(c / W) * BS + j * W + c % W] = before[j * cells + c];
    blocks_joined_run<kJoinedRows>(aos, nx, ny, first_row, end_row, 1.3, 1.0);
    printf("joined rows, edge cells redone: %ld of %ld slots differ\n", differing(), Q * cells);
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) aos[(c / W) * BS + j * W + c % W] = before[j * cells + c];
    blocks_rotated_run<kJoinedRows>(aos, nx, ny, first_row, end_row, 1.3, 1.0);
    printf("joined rows, join slots moved by a row: %ld of %ld slots differ\n", differing(), Q * cells);
    // The whole box periodic in x, y and z, against a scalar reference with every side wrapped.
    for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) aos[(c / W) * BS + j * W + c % W] = before[j * cells + c];
    ref = before;
    auto wrapped = [&](long c, int sx, int sy, int sz) {
      const long x = c % nx, y = c / nx % ny, z = c / nxy;
      return (x + sx + nx) % nx + (y + sy + ny) % ny * nx + (z + sz + nz) % nz * nxy;
    };
    for (long c = 0; c < cells; ++c) {
      T fin[Q];
      for (int k = 0; k < Q; ++k) fin[k] = before[opp[k] * cells + wrapped(c, -cx(k), -cy(k), -cz(k))];
      const auto st = Scalar::template node_state<false>(fin, T(1.0), force);
      [&]<int... K>(std::integer_sequence<int, K...>) {
        ((ref[K * cells + wrapped(c, cx(K), cy(K), cz(K))] = Scalar::template relaxed<false, K>(fin[K], st, T(1.3), force)), ...);
      }(std::make_integer_sequence<int, Q>{});
    }
    blocks_box_pull<kJoinedRows>(aos, nx, ny, nz, 1.3, 1.0);
    printf("the whole periodic box, join slots moved: %ld of %ld slots differ\n", differing(), Q * cells);
    fluid::FluidConfig config;
    config.nx = static_cast<int>(nx); config.ny = static_cast<int>(ny); config.nz = static_cast<int>(nz); config.omega = 1.0;
    fluid::FluidLattice<L, T> lattice(config);
    lattice.run(2);
    double t[9] = {1e9, 1e9, 1e9, 1e9, 1e9, 1e9, 1e9, 1e9, 1e9};
    for (int r = 0; r < reps; ++r) for (int v = 0; v < 9; ++v) {
      if (v == 2) lattice.step();  // the local step, untimed
      auto t0 = std::chrono::steady_clock::now();
      if (v == 0) blocks_rows_run(aos, nx, nxy, first_row, end_row, 1.0, 1.0);
      else if (v == 1) aosoa_run(aos, nx, nxy, begin, end, 1.0, 1.0);
      else if (v == 2) lattice.step();
      else if (v == 3) blocks_rows_run_line(aos, nx, nxy, first_row, end_row, 1.0, 1.0);
      else if (v == 4) blocks_joined_run<kJoinedRows>(aos, nx, ny, first_row, end_row, 1.0, 1.0);
      else if (v == 5) lattice.step();  // the fluid's local step
      else if (v == 6) local_run<true>(aos, stride, begin, end, 1.0, 1.0);
      else if (v == 7) blocks_rotated_run<kJoinedRows>(aos, nx, ny, first_row, end_row, 1.0, 1.0);
      else blocks_box_pull<kJoinedRows>(aos, nx, ny, nz, 1.0, 1.0);
      t[v] = std::min(t[v], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      if (v == 5) lattice.step();  // its pulling step, untimed, so that v == 2 times a pulling step again
    }
    printf("pulling MLUPS: blocks, rows periodic %.1f, through the line's loop %.1f, joined rows with edges redone "
           "%.1f, joined rows with the join slots moved %.1f; blocks, one line %.1f; the fluid's step (19 arrays, periodic box) %.1f\n",
           (end - begin) / t[0] / 1e6, (end - begin) / t[3] / 1e6, (end - begin) / t[4] / 1e6,
           (end - begin) / t[7] / 1e6, (end - begin) / t[1] / 1e6, cells / t[2] / 1e6);
    printf("local MLUPS: blocks %.1f, the fluid's step %.1f\n", (end - begin) / t[6] / 1e6, cells / t[5] / 1e6);
    printf("whole periodic box, pulling MLUPS: blocks, join slots moved %.1f; the fluid's step %.1f\n",
           cells / t[8] / 1e6, cells / t[2] / 1e6);
  }
  // The sweeps above stepped the blocks alone: the same state in both layouts again.
  for (int j = 0; j < Q; ++j) for (long c = 0; c < cells; ++c) aos[(c / W) * BS + j * W + c % W] = soa[j * stride + c];
  // The 3D scene's nodes: 27 balls of radius 4 on a 3 x 3 x 3 grid, in cell order. Each gather
  // runs right after a local sweep of its layout, as the coupling's runs after the fluid's step.
  std::vector<long> nodes;
  for (long c = 0; c < cells; ++c) {
    const long x = c % nx, y = c / nx % ny, z = c / nxy;
    auto near = [&](long a, long m) { const double d = (a + 0.5) - (std::floor(a * 3.0 / m) + 0.5) * m / 3.0; return d * d; };
    if (near(x, nx) + near(y, ny) + near(z, nz) <= 16.0) nodes.push_back(c);
  }
  std::vector<double> moments_a(4 * nodes.size()), moments_b(4 * nodes.size());
  double gather_best[2] = {1e9, 1e9};
  for (int r = 0; r < reps; ++r) for (int v = 0; v < 2; ++v) {
    if (v == 0) local_run<false>(soa, stride, begin, end, 1.0, 1.0);
    else local_run<true>(aos, stride, begin, end, 1.0, 1.0);
    auto t0 = std::chrono::steady_clock::now();
    if (v == 0) gather<false>(soa, stride, nodes, moments_a.data());
    else gather<true>(aos, stride, nodes, moments_b.data());
    gather_best[v] = std::min(gather_best[v], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  printf("gather of %zu nodes after a sweep: %.1f ns a node in 19 arrays, %.1f in blocks (moments equal: %d)\n",
         nodes.size(), gather_best[0] / nodes.size() * 1e9, gather_best[1] / nodes.size() * 1e9,
         moments_a == moments_b);
  const double m = (end - begin) / 1e6;
  printf("n=%ld, %ld cells, MLUPS: pulling %.1f in 19 arrays, %.1f in blocks; local %.1f in 19 arrays, %.1f in blocks\n",
         n, end - begin, m / best[0], m / best[1], m / best[2], m / best[3]);
}
