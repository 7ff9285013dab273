#pragma once
// The in-place (AA) steps of BGK on populations stored in blocks (population_storage.h: cell c's
// population i at (c / W) Q W + i W + c mod W), for a 3D lattice with velocities of at most 1 a
// component (D3Q19) and every side periodic, rows whole blocks (n_x a multiple of W).
//
// Why blocks: a block's Q lines lie side by side, so a sweep walks one region of memory, 9 of
// them for the pulling step (one a (c_y, c_z) row offset) instead of Q arrays at Q offsets. A
// probe of both layouts (docs/experiments/aosoa_pull_probe.cpp, docs/performance.md) ran the
// whole periodic box's pulling step 14-26% faster than the arrays' kernel at 96^3 to 160^3,
// and the local step about as fast.
//
// The pulling step sweeps chunks of rows that share their sources' row offsets (a plane's
// interior rows; rows at y = 0 or n_y - 1 alone, their y sources wrapping) as one line, every
// stream addressed from the block pointer. In that line a row's first cell reads across the
// join, in the row before, the inputs it should take from its own row's last cell (c_x = +1),
// and a row's last cell those it should take from its own row's first (c_x = -1). So before
// the line those 5 + 5 slots a row are moved by one row, where the line's cells look for them;
// the line then computes every cell right, and writes each such result where the next step's
// cell looks for it, a row off: the same slots are moved back after. The chunk's first cell
// reads (and writes) one slot of the row before it, and its last cell one of the row after:
// those 10 slots are saved first and put back, so a chunk changes only its own cells' slots and
// chunks may run in any order (blocks_rows() and the lattice's threads rely on it).
// The collision is BgkCollision on Lanes, as in shifted_pull.h: the same arithmetic as the
// scalar kernel lane by lane, so the populations are the arrays' kernels' bit for bit.
#include <algorithm>
#include <cstdint>
#include <utility>

#include "fluid/bgk_collision.h"
#include "fluid/force_inline.h"
#include "fluid/in_step_exchange.h"
#include "fluid/population_storage.h"
#include "fluid/simd_lanes.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T>
struct BlockedKernels {
  static constexpr int Q = L::Q;
  static constexpr int W = PopulationStorage<T>::kBlockCells;
  static constexpr long kBlock = static_cast<long>(Q) * W;  // a block's length in elements
  static constexpr bool kLatticeFits = [] {
    if (L::D != 3 || L::hexagonal) return false;
    for (int k = 0; k < Q; ++k)
      for (int a = 0; a < 3; ++a)
        if (L::c[k][a] < -1.0 || L::c[k][a] > 1.0) return false;
    return true;
  }();
  using V = Lanes<T, W>;
  using Bgk = BgkCollision<L, V>;

  static constexpr int cx(int k) { return static_cast<int>(L::c[k][0]); }
  // Which of the 9 row offsets direction k's source is at: (c_y + 1) 3 + (c_z + 1).
  static constexpr int row_offset_of(int k) {
    return (static_cast<int>(L::c[k][1]) + 1) * 3 + static_cast<int>(L::c[k][2]) + 1;
  }

  struct Grid {
    long nx, ny, nz;
    long blocks_per_row() const { return nx / W; }
    long row_length() const { return nx / W * kBlock; }
  };
  // From a block of row (y, z) to the block of the same x in the row its direction's source lies
  // in, per row_offset_of(): rows (y - c_y, z - c_z), wrapped.
  using RowOffsets = long[9];
  static void row_offsets(const Grid& g, long row, RowOffsets& o) {
    const long y = row % g.ny, z = row / g.ny;
    for (int m = 0; m < 9; ++m) {
      const long dy = m / 3 - 1, dz = m % 3 - 1;
      const long ys = (y - dy + g.ny) % g.ny, zs = (z - dz + g.nz) % g.nz;
      o[m] = ((ys - y) + (zs - z) * g.ny) * g.row_length();
    }
  }

  template <class Body>
  static LBSOLID_FORCE_INLINE void each(Body&& body) {
    [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA {
      (body(std::integral_constant<int, K>{}), ...);
    }(std::make_integer_sequence<int, Q>{});
  }

  // The local (even) step over blocks [first, end): each cell's own populations, written back
  // reversed. Each block's lines are asked for kAhead blocks early: one population's lines cross
  // a 4 KB page every few blocks, and the hardware prefetcher does not follow across pages (the
  // probe's local sweep ran 30-40% slower without).
  static constexpr long kAhead = 8;
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void local(T* f, long first, long end, const T (&force)[3], T omega, T rho0) {
    constexpr auto opp = lattice::opposite_table<L>();
    const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
    const V omega_v(omega), rho0_v(rho0);
    const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(f);
    for (long b = first; b < end; ++b) {
      T* at = f + b * kBlock;
      // As an integer: past the buffer's end no pointer may point, and a prefetch cannot fault.
      for (int line = 0; line < Q; ++line)
        __builtin_prefetch(reinterpret_cast<const void*>(base + ((b + kAhead) * kBlock + line * W) * sizeof(T)), 1);
      V v[Q];
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        v[K] = V::load_aligned(at + K * W);
      });
      const auto state = Bgk::template node_state<kForce>(v, rho0_v, force_v);
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        Bgk::template relaxed<kForce, K>(v[K], state, omega_v, force_v).store_aligned(at + opp[K] * W);
      });
    }
  }

  // The pulling step's sweep of blocks [first, end) as one line whose sources lie at the row
  // offsets o: population K of cell c from array opp(K) at cell c - c_K, its result into array K
  // at c + c_K. Each x-shifted stream's line is completed from this block's results and the last
  // one's; the lanes before `first` and after `end` are written back as they were.
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void line(T* f, const RowOffsets& o, long first, long end, const T (&force)[3], T omega,
                                        T rho0) {
    constexpr auto opp = lattice::opposite_table<L>();
    const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
    const V omega_v(omega), rho0_v(rho0);
    V last[Q];
    T* const p0 = f + first * kBlock;
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      const T* out = p0 + o[row_offset_of(opp[K])] + K * W;  // array K, the rows of cells c + c_K
      if constexpr (x == 1) last[K] = lanes_from<1>(V::load_aligned(out - kBlock), V::load_aligned(out));
      else if constexpr (x == -1) last[K] = lanes_from<W - 1>(V(0.0), V::load_aligned(out - kBlock));
    });
    for (T *p = p0, *p_end = f + end * kBlock; p < p_end; p += kBlock) {
      V v[Q];
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int x = cx(K);
        const T* in = p + o[row_offset_of(K)] + opp[K] * W;  // array opp(K), the rows of cells c - c_K
        if constexpr (x == 0) v[K] = V::load_aligned(in);
        else if constexpr (x == 1) v[K] = lanes_from<W - 1>(V::load_aligned(in - kBlock), V::load_aligned(in));
        else v[K] = lanes_from<1>(V::load_aligned(in), V::load_aligned(in + kBlock));
      });
      const auto state = Bgk::template node_state<kForce>(v, rho0_v, force_v);
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        v[K] = Bgk::template relaxed<kForce, K>(v[K], state, omega_v, force_v);
      });
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int x = cx(K);
        T* out = p + o[row_offset_of(opp[K])] + K * W;
        if constexpr (x == 0) {
          v[K].store_aligned(out);
        } else if constexpr (x == 1) {  // this line holds the results of cells c - 1 .. c + W - 2
          lanes_from<W - 1>(last[K], v[K]).store_aligned(out);
        } else {  // the line before holds those of cells c - W + 1 .. c
          lanes_from<1>(last[K], v[K]).store_aligned(out - kBlock);
        }
        last[K] = v[K];
      });
    }
    T* const pe = f + end * kBlock;
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      T* out = pe + o[row_offset_of(opp[K])] + K * W;
      if constexpr (x == 1) {
        const V now = V::load_aligned(out);
        lanes_from<W - 1>(last[K], lanes_from<1>(now, now)).store_aligned(out);
      } else if constexpr (x == -1) {
        const V now = V::load_aligned(out - kBlock);
        lanes_from<1>(last[K], lanes_from<W - 1>(now, now)).store_aligned(out - kBlock);
      }
    });
  }

  // The pulling step of rows [r0, r1), which share the row offsets o, with the join slots moved
  // (the header). For c_x(K) = +1, the slot S(r) = r row_length + at: array opp(K) at cell
  // (n_x - 1) of the row o names, cell (0, r)'s input, which the line reads at S(r - 1); for
  // c_x(K) = -1, T(r) the same at cell 0, cell (n_x - 1, r)'s, read at T(r + 1).
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void chunk(T* f, const Grid& g, const RowOffsets& o, long r0, long r1,
                                         const T (&force)[3], T omega, T rho0) {
    constexpr auto opp = lattice::opposite_table<L>();
    constexpr int kJoin = [] {
      int n = 0;
      for (int k = 0; k < Q; ++k) n += cx(k) == 1;
      return n;
    }();
    const long nb = g.blocks_per_row(), row = g.row_length();
    long s_at[kJoin], t_at[kJoin];
    T s_outside[kJoin], t_outside[kJoin];
    for (int k = 0, s = 0, t = 0; k < Q; ++k) {
      if (cx(k) == 1) s_at[s++] = o[row_offset_of(k)] + (nb - 1) * kBlock + opp[k] * W + (W - 1);
      if (cx(k) == -1) t_at[t++] = o[row_offset_of(k)] + opp[k] * W;
    }
    // Indices, not pointers: S(0) and T(0) may lie outside the buffer when row 0 does not.
    auto s_slot = [&](int i, long r) -> T& { return f[s_at[i] + r * row]; };
    auto t_slot = [&](int i, long r) -> T& { return f[t_at[i] + r * row]; };
    for (int i = 0; i < kJoin; ++i) {
      s_outside[i] = s_slot(i, r0 - 1);
      for (long r = r0; r < r1; ++r) s_slot(i, r - 1) = s_slot(i, r);
      t_outside[i] = t_slot(i, r1);
      for (long r = r1 - 1; r >= r0; --r) t_slot(i, r + 1) = t_slot(i, r);
    }
    line<kForce>(f, o, r0 * nb, r1 * nb, force, omega, rho0);
    for (int i = 0; i < kJoin; ++i) {
      for (long r = r1 - 1; r >= r0; --r) s_slot(i, r) = s_slot(i, r - 1);
      s_slot(i, r0 - 1) = s_outside[i];
      for (long r = r0; r < r1; ++r) t_slot(i, r) = t_slot(i, r + 1);
      t_slot(i, r1) = t_outside[i];
    }
  }

  // The pulling step of rows [first, end) in chunks of up to kChunkRows rows sharing their row
  // offsets. 32 rows measured as well as 16 and 128 in the probe. With `finished`, each chunk's
  // rows are reported once it is done: only then are its join slots back where they belong, and
  // a chunk changes no other cell's slots for good (chunk()), so its cells' results are final.
  // Chunks with nodes were cut at 8 rows (bf604b5), so that the nodes' lines were still in the
  // cache when exchanged; once a node's slots came from a table (1d14dbc) the cut cost 5-14 ns a
  // particle on one thread in the 3D suspension, and nothing measurable on two
  // (docs/performance.md).
  static constexpr long kChunkRows = 32;
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void rows(T* f, const Grid& g, long first, long end, const T (&force)[3], T omega,
                                        T rho0, FinishedCells* finished = nullptr) {
    RowOffsets o, next;
    for (long r0 = first; r0 < end;) {
      row_offsets(g, r0, o);
      long r1 = r0 + 1;
      for (; r1 < end && r1 - r0 < kChunkRows; ++r1) {
        row_offsets(g, r1, next);
        if (!std::equal(o, o + 9, next)) break;
      }
      chunk<kForce>(f, g, o, r0, r1, force, omega, rho0);
      if (finished)
        for (long r = r0; r < r1; ++r) (*finished)(r * g.nx, (r + 1) * g.nx);
      r0 = r1;
    }
  }
};

}  // namespace lbsolid::fluid
