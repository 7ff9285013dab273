#pragma once
// The one fused cell update every kernel runs: for cells [begin, end), read the Q populations
// (each from its own stream, plus a wall correction), collide, write them (each to its own
// stream, plus a correction). The kernels differ only in the pointers they hand in: two-buffer
// pull, in-place local collision, or in-place pull.
#include "fluid/bgk_collision.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce, bool kCorrections>
LBSOLID_FORCE_INLINE void update_cells(const T* const (&in)[L::Q], const T (&in_correction)[L::Q],
                                       T* const (&out)[L::Q], const T (&out_correction)[L::Q],
                                       const T (&force)[3], typename Collision::Rates rates, T rho0, long begin, long end) {
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

}  // namespace lbsolid::fluid
