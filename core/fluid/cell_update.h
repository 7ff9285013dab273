#pragma once
// The one fused cell update every kernel runs: for cells [begin, end), read the Q populations
// (each from its own stream, plus a wall correction), collide, write them (each to its own
// stream, plus a correction). The kernels differ only in the pointers they hand in: two-buffer
// pull, in-place local collision, or in-place pull.
#include <utility>

#include "fluid/bgk_collision.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce, bool kCorrections>
LBSOLID_FORCE_INLINE void update_cells_together(const T* const (&in)[L::Q], const T (&in_correction)[L::Q],
                                                T* const (&out)[L::Q], const T (&out_correction)[L::Q],
                                                const T (&force)[3], typename Collision::Rates rates, T rho0,
                                                long begin, long end) {
  constexpr int Q = L::Q;
  // Distinct cells never share a slot (in place, a cell writes only the slots it read).
#pragma GCC ivdep
  for (long c = begin; c < end; ++c) {
    T f[Q];
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) f[i] = kCorrections ? in[i][c] + in_correction[i] : in[i][c];
    Collision::template collide<kForce>(f, rates, rho0, force);
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) out[i][c] = kCorrections ? f[i] + out_correction[i] : f[i];
  }
}

// The same update for a collision that relaxes each direction on its own given the node's state
// (BGK): the populations are read once for the node's moments, then again a pair of opposite
// directions at a time, relaxed and written. Only the pair is live at once, not all Q: with
// Q = 19 the loop above keeps 19 populations and 19 stream pointers in flight, more than the
// registers, and spills them every cell. In place, out[i] is in[opp(i)], so a pair reads both its
// slots before writing either. The same arithmetic in the source (tests/fluid/cell_update_test.cpp;
// the compiler may fuse a multiply-add differently in the two loops).
template <class L, class T, class Collision, bool kForce, bool kCorrections>
LBSOLID_FORCE_INLINE void update_cells_by_pairs(const T* const (&in)[L::Q], const T (&in_correction)[L::Q],
                                                T* const (&out)[L::Q], const T (&out_correction)[L::Q],
                                                const T (&force)[3], T omega, T rho0, long begin, long end) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
#pragma GCC ivdep
  for (long c = begin; c < end; ++c) {
    auto read = [&](int i) __attribute__((always_inline)) { return kCorrections ? in[i][c] + in_correction[i] : in[i][c]; };
    auto write = [&](int i, T v) __attribute__((always_inline)) { out[i][c] = kCorrections ? v + out_correction[i] : v; };
    T f[Q];
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) f[i] = read(i);
    const auto state = Collision::template node_state<kForce>(f, rho0, force);
    [&]<int... K>(std::integer_sequence<int, K...>) __attribute__((always_inline)) {
      auto pair = [&]<int I>(std::integral_constant<int, I>) __attribute__((always_inline)) {
        constexpr int J = opp[I];
        if constexpr (I == J) {
          write(I, Collision::template relaxed<kForce, I>(read(I), state, omega, force));
        } else if constexpr (I < J) {
          const T a = Collision::template relaxed<kForce, I>(read(I), state, omega, force);
          const T b = Collision::template relaxed<kForce, J>(read(J), state, omega, force);
          write(I, a);
          write(J, b);
        }
      };
      (pair(std::integral_constant<int, K>{}), ...);
    }(std::make_integer_sequence<int, Q>{});
  }
}

// For cells [begin, end): read the Q populations, collide, write them. D3Q19 BGK goes by pairs
// (measured faster there); everything else collides all Q together.
template <class L, class T, class Collision, bool kForce, bool kCorrections>
LBSOLID_FORCE_INLINE void update_cells(const T* const (&in)[L::Q], const T (&in_correction)[L::Q],
                                       T* const (&out)[L::Q], const T (&out_correction)[L::Q],
                                       const T (&force)[3], typename Collision::Rates rates, T rho0, long begin, long end) {
  if constexpr (L::Q > 9 && std::is_same_v<Collision, BgkCollision<L, T>>)
    update_cells_by_pairs<L, T, Collision, kForce, kCorrections>(in, in_correction, out, out_correction, force, rates,
                                                                 rho0, begin, end);
  else
    update_cells_together<L, T, Collision, kForce, kCorrections>(in, in_correction, out, out_correction, force, rates,
                                                                 rho0, begin, end);
}

// update_cells for cells whose reads and writes may carry wall corrections: with corrections
// only if one of them is non-zero. Cells away from walls have none, and adding 2 Q zeros per cell
// costs the adds and the registers to hold them (D3Q19 in place: about 8% of the pulling step).
// x + 0 is x (a zero may change sign, which no later arithmetic sees).
template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void update_corrected_cells(const T* const (&in)[L::Q], const T (&in_correction)[L::Q],
                                                 T* const (&out)[L::Q], const T (&out_correction)[L::Q],
                                                 const T (&force)[3], typename Collision::Rates rates, T rho0,
                                                 long begin, long end) {
  bool corrected = false;
  for (int i = 0; i < L::Q; ++i) corrected = corrected || in_correction[i] != T(0) || out_correction[i] != T(0);
  if (corrected)
    update_cells<L, T, Collision, kForce, true>(in, in_correction, out, out_correction, force, rates, rho0, begin, end);
  else
    update_cells<L, T, Collision, kForce, false>(in, in_correction, out, out_correction, force, rates, rho0, begin, end);
}

}  // namespace lbsolid::fluid
