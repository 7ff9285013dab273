#pragma once
// The in-place pulling step of BGK over whole vectors of a row's interior, with the x-shifted
// streams read and written as aligned vectors and shifted in registers.
//
// In the pulling step population k of cell c is read at slot[k] + c, and the populations of the
// directions with c_x = +-1 sit one cell off the others: when a row's length is a whole number of
// vectors, every load and store of those streams straddles two cache lines, and the step ran at a
// third of the local step's speed (D3Q19, 96^3 doubles, AVX-512: 58 MLUPS against 150). Here
// each such stream is loaded one aligned vector ahead and the cells' lanes taken from two
// neighbouring vectors; results are written back the same way, each aligned line completed from
// this vector's results and the last one's (measured outside the tree on the same box: 58 -> 100
// MLUPS for the step alone). The collision is BgkCollision on Lanes (simd_lanes.h): the same
// arithmetic as the scalar kernel, lane by lane, so the results are the same bit for bit.
#include <cstdint>

#include "fluid/bgk_collision.h"
#include "fluid/force_inline.h"
#include "fluid/simd_lanes.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T, int W>
struct ShiftedPull {
  static constexpr int Q = L::Q;
  // Applies where every x offset is -1, 0 or +1 cell (not the staggered D2Q7 rows).
  static constexpr bool kLatticeFits = !L::hexagonal;
  static constexpr int cx(int k) { return static_cast<int>(L::c[k][0]); }

  // The cells of a line [begin, end) that whole vectors may cover: every slot they read or write
  // (a vector beyond each end included) then belongs to a cell of the line.
  static long first_cell(long begin) { return (begin + W + W - 1) / W * W; }
  static long end_cell(long end) { return (end - W) / W * W; }

  static bool lanes_fit(const T* p, int offset) {
    const long lane = static_cast<long>(reinterpret_cast<std::uintptr_t>(p) / sizeof(T) % W);
    return reinterpret_cast<std::uintptr_t>(p) % sizeof(T) == 0 && lane == ((offset % W) + W) % W;
  }
  // Whether the streams sit where the shifts expect: population k of cell c at slot[k] + c with
  // slot[k] offset -c_x(k) lanes from a vector boundary, written at out[k] offset c_x(k).
  static bool streams_fit(const T* const (&in)[Q], T* const (&out)[Q]) {
    for (int k = 0; k < Q; ++k)
      if (!lanes_fit(in[k], -cx(k)) || !lanes_fit(out[k], cx(k))) return false;
    return true;
  }

  // Cells [begin, end), both multiples of W, of a row whose cells read in[k][c] and write
  // out[k][c] with no wall rule. streams_fit() must hold, and cells before `begin` must already
  // be done (the first line written may hold one of them, written back as it is).
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void run(const T* const (&in)[Q], T* const (&out)[Q], const T (&force)[3], T omega,
                                       T rho0, long begin, long end) {
    using V = Lanes<T, W>;
    using Bgk = BgkCollision<L, V>;
    const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
    const V omega_v(omega), rho0_v(rho0);
    // Per shifted stream: the last results (their lanes complete the next line written).
    V last[Q];
    auto each = [&](auto&& body) LBSOLID_FORCE_INLINE_LAMBDA {
      [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA {
        (body(std::integral_constant<int, K>{}), ...);
      }(std::make_integer_sequence<int, Q>{});
    };
    // out[K] + c sits at lane c_x(K). Lanes of the cells just before `begin`, as they are:
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      if constexpr (cx(K) != 0) last[K] = V::load(out[K] + begin - W);
    });
    for (long c = begin; c < end; c += W) {
      V f[Q];
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int x = cx(K);
        // in[K] + c sits at lane -c_x(K): its aligned vector starts at in[K] + c_x(K) (+ c). The
        // vector before or after is read again (from the L1 cache) rather than kept in a register
        // from the last step: ten registers fewer, which the compiler had spilled.
        const T* base = in[K] + x;
        if constexpr (x == 0) {
          f[K] = V::load_aligned(in[K] + c);
        } else if constexpr (x == -1) {  // cell c's value is lane 1 of the vector at c
          f[K] = lanes_from<1>(V::load_aligned(base + c), V::load_aligned(base + c + W));
        } else {  // cell c's value is the last lane of the vector before c
          f[K] = lanes_from<W - 1>(V::load_aligned(base + c - W), V::load_aligned(base + c));
        }
      });
      const auto state = Bgk::template node_state<kForce>(f, rho0_v, force_v);
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        f[K] = Bgk::template relaxed<kForce, K>(f[K], state, omega_v, force_v);
      });
      each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
        constexpr int x = cx(K);
        T* base = out[K] - x;  // out[K] + c sits at lane c_x(K)
        if constexpr (x == 0) {
          f[K].store_aligned(out[K] + c);
        } else if constexpr (x == 1) {  // the line at c holds cells c-1 .. c+W-2
          lanes_from<W - 1>(last[K], f[K]).store_aligned(base + c);
        } else {  // the line before c holds cells c-W+1 .. c
          lanes_from<1>(last[K], f[K]).store_aligned(base + c - W);
        }
        last[K] = f[K];
      });
    }
    // The line each shifted stream has not written yet: the last cells' results beside the
    // values of the cells after `end`, as they are.
    each([&]<int K>(std::integral_constant<int, K>) LBSOLID_FORCE_INLINE_LAMBDA {
      constexpr int x = cx(K);
      T* base = out[K] - x;
      if constexpr (x == 1)  // the line at end holds cells end-1 .. end+W-2
        lanes_from<W - 1>(last[K], V::load(out[K] + end)).store_aligned(base + end);
      else if constexpr (x == -1)  // the line before end holds cells end-W+1 .. end
        lanes_from<1>(last[K], V::load(out[K] + end)).store_aligned(base + end - W);
    });
  }

  // Cells [first, end), at least W of them, of a line whose cells read in[k][c] and write
  // out[k][c] with no wall rule (each slot one cell's): W cells at a time from `first`, the last
  // W ending at `end`, with unaligned loads and stores (a line's ends only, or a row too short for
  // run()). That last vector may share cells with the one before: it is read before anything is
  // written, so those cells get the same results twice.
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void span(const T* const (&in)[Q], T* const (&out)[Q], const T (&force)[3], T omega,
                                        T rho0, long first, long end) {
    using V = Lanes<T, W>;
    using Bgk = BgkCollision<L, V>;
    const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
    const V omega_v(omega), rho0_v(rho0);
    auto collide_store = [&](V (&f)[Q], long at) LBSOLID_FORCE_INLINE_LAMBDA {
      const auto state = Bgk::template node_state<kForce>(f, rho0_v, force_v);
      [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA {
        (Bgk::template relaxed<kForce, K>(f[K], state, omega_v, force_v).store(out[K] + at), ...);
      }(std::make_integer_sequence<int, Q>{});
    };
    V last[Q];
    for (int k = 0; k < Q; ++k) last[k] = V::load(in[k] + end - W);
    for (long c = first; c < end - W; c += W) {
      V f[Q];
      for (int k = 0; k < Q; ++k) f[k] = V::load(in[k] + c);
      collide_store(f, c);
    }
    collide_store(last, end - W);
  }

  // W cells `stride` apart, cell l at in[k] + l stride (the same column of W rows), each with no
  // wall rule: population k of cell l is written to into[k][l] (W values a stream).
  template <bool kForce>
  static LBSOLID_FORCE_INLINE void column(const T* const (&in)[Q], long stride, T* const (&into)[Q],
                                          const T (&force)[3], T omega, T rho0) {
    using V = Lanes<T, W>;
    using Bgk = BgkCollision<L, V>;
    const V force_v[3] = {V(force[0]), V(force[1]), V(force[2])};
    const V omega_v(omega);
    V f[Q];
    for (int k = 0; k < Q; ++k) f[k] = V::load_strided(in[k], stride);
    const auto state = Bgk::template node_state<kForce>(f, V(rho0), force_v);
    [&]<int... K>(std::integer_sequence<int, K...>) LBSOLID_FORCE_INLINE_LAMBDA {
      (Bgk::template relaxed<kForce, K>(f[K], state, omega_v, force_v).store(into[K]), ...);
    }(std::make_integer_sequence<int, Q>{});
  }
};

}  // namespace lbsolid::fluid
