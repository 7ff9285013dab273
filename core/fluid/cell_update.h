#pragma once
// The one fused cell update every kernel runs: for cells [begin, end), read the Q populations
// (each from its own stream, plus a wall correction), collide, write them (each to its own
// stream, plus a correction). The kernels differ only in the pointers they hand in: two-buffer
// pull, in-place local collision, or in-place pull.
#include <utility>

#include "fluid/bgk_collision.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

// What the walls do to each population a cell reads or writes: value * scale + shift (row_plan.h:
// a wall's correction is the shift; scale is 0 only at a pressure outlet, which ignores what comes).
template <class T, int Q>
struct WallMap {
  T scale[Q];
  T shift[Q];
  static constexpr WallMap identity() {
    WallMap m{};
    for (int i = 0; i < Q; ++i) m.scale[i] = T(1);
    return m;
  }
  bool is_identity() const {
    for (int i = 0; i < Q; ++i)
      if (scale[i] != T(1) || shift[i] != T(0)) return false;
    return true;
  }
  // x * 1 + 0 is x (with -ffp-contract=off no multiply-add is fused): walls that only shift, or
  // none, give what they gave before scales existed, bit for bit.
  T apply(int i, T value) const { return value * scale[i] + shift[i]; }
};

template <class L, class T, class Collision, bool kForce, bool kCorrections>
LBSOLID_FORCE_INLINE void update_cells_together(const T* const (&in)[L::Q], const WallMap<T, L::Q>& in_map,
                                                T* const (&out)[L::Q], const WallMap<T, L::Q>& out_map,
                                                const T (&force)[3], typename Collision::Rates rates, T rho0,
                                                long begin, long end) {
  constexpr int Q = L::Q;
  // Distinct cells never share a slot (in place, a cell writes only the slots it read).
#pragma GCC ivdep
  for (long c = begin; c < end; ++c) {
    T f[Q];
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) f[i] = kCorrections ? in_map.apply(i, in[i][c]) : in[i][c];
    Collision::template collide<kForce>(f, rates, rho0, force);
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) out[i][c] = kCorrections ? out_map.apply(i, f[i]) : f[i];
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
LBSOLID_FORCE_INLINE void update_cells_by_pairs(const T* const (&in)[L::Q], const WallMap<T, L::Q>& in_map,
                                                T* const (&out)[L::Q], const WallMap<T, L::Q>& out_map,
                                                const T (&force)[3], T omega, T rho0, long begin, long end) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
#pragma GCC ivdep
  for (long c = begin; c < end; ++c) {
    auto read = [&](int i) __attribute__((always_inline)) { return kCorrections ? in_map.apply(i, in[i][c]) : in[i][c]; };
    auto write = [&](int i, T v) __attribute__((always_inline)) { out[i][c] = kCorrections ? out_map.apply(i, v) : v; };
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
LBSOLID_FORCE_INLINE void update_cells(const T* const (&in)[L::Q], const WallMap<T, L::Q>& in_map,
                                       T* const (&out)[L::Q], const WallMap<T, L::Q>& out_map,
                                       const T (&force)[3], typename Collision::Rates rates, T rho0, long begin, long end) {
  if constexpr (L::Q > 9 && std::is_same_v<Collision, BgkCollision<L, T>>)
    update_cells_by_pairs<L, T, Collision, kForce, kCorrections>(in, in_map, out, out_map, force, rates, rho0, begin,
                                                                 end);
  else
    update_cells_together<L, T, Collision, kForce, kCorrections>(in, in_map, out, out_map, force, rates, rho0, begin,
                                                                 end);
}

// update_cells for cells whose reads and writes may cross walls: with the maps only if one of
// them does something. Cells away from walls have none, and applying 2 Q identities per cell
// costs the arithmetic and the registers to hold them (D3Q19 in place: about 8% of the pulling
// step). x * 1 + 0 is x (a zero may change sign, which no later arithmetic sees).
template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void update_corrected_cells(const T* const (&in)[L::Q], const WallMap<T, L::Q>& in_map,
                                                 T* const (&out)[L::Q], const WallMap<T, L::Q>& out_map,
                                                 const T (&force)[3], typename Collision::Rates rates, T rho0,
                                                 long begin, long end) {
  if (!in_map.is_identity() || !out_map.is_identity())
    update_cells<L, T, Collision, kForce, true>(in, in_map, out, out_map, force, rates, rho0, begin, end);
  else
    update_cells<L, T, Collision, kForce, false>(in, in_map, out, out_map, force, rates, rho0, begin, end);
}

}  // namespace lbsolid::fluid
