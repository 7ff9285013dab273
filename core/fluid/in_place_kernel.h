#pragma once
// In-place streaming on one buffer (the AA pattern, Bailey et al. 2009): two fused kernels that
// alternate, each reading and writing the same slots, so no second buffer is needed and every
// cache line a cell reads is the one it writes back.
//
//   even step: a cell reads its own slots f_i = A[i][x], collides, and writes each result reversed
//              into its own cell, A[opp(i)][x] = f*_i. No neighbour is touched.
//   odd step:  a cell pulls through the row plan: population k comes from f*_j at node s, which
//              the even step left in A[opp(j)][s]. After colliding it writes f*_k into the slot it
//              read for opp(k), adding that entry's wall correction; that slot is where the next
//              even step finds the population arriving downstream. The wall rules are involutions,
//              so the slots a cell reads are exactly the slots it writes and cells never collide
//              (FluidLattice checks this once per configuration).
#include "fluid/row_plan.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce>
void collide_local_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx, int ny,
                        long row_begin, long row_end, T omega, T rho0) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
  auto plan_of = [&](long row) -> const RowPlan<T, Q>& {
    return plans.for_row(static_cast<int>(row % ny), static_cast<int>(row / ny));
  };
  for (long first = row_begin; first < row_end;) {
    // Rows with one plan share their force: sweep them as one run of cells.
    const RowPlan<T, Q>& plan = plan_of(first);
    long last = first;
    while (last + 1 < row_end && &plan_of(last + 1) == &plan) ++last;
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    T* slot[Q];
    for (int i = 0; i < Q; ++i) slot[i] = f + i * stride;
#pragma GCC ivdep
    for (long c = first * nx; c < (last + 1) * nx; ++c) {
      T g[Q];
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) g[i] = slot[i][c];
      Collision::template collide<kForce>(g, omega, rho0, force);
#pragma GCC unroll 32
      for (int i = 0; i < Q; ++i) slot[opp[i]][c] = g[i];
    }
    first = last + 1;
  }
}

template <class L, class T, class Collision, bool kForce>
void stream_collide_in_place_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx, int ny,
                                  long row_begin, long row_end, T omega, T rho0) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
  for (long row = row_begin; row < row_end; ++row) {
    const auto& plan = plans.for_row(static_cast<int>(row % ny), static_cast<int>(row / ny));
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    auto sweep = [&](int part, long begin, long end) {
      T* slot[Q];
      T corr[Q];
      for (int k = 0; k < Q; ++k) {
        const auto& s = plan.sources[part][k];
        slot[k] = f + opp[s.dir] * stride + s.delta;
        corr[k] = s.correction;
      }
#pragma GCC ivdep
      for (long c = begin; c < end; ++c) {
        T g[Q];
#pragma GCC unroll 32
        for (int k = 0; k < Q; ++k) g[k] = slot[k][c] + corr[k];
        Collision::template collide<kForce>(g, omega, rho0, force);
#pragma GCC unroll 32
        for (int k = 0; k < Q; ++k) slot[opp[k]][c] = g[k] + corr[opp[k]];
      }
    };
    const long row_start = row * nx;
    sweep(0, row_start, row_start + 1);
    if (nx > 2) sweep(1, row_start + 1, row_start + nx - 1);
    if (nx > 1) sweep(2, row_start + nx - 1, row_start + nx);
  }
}

}  // namespace lbsolid::fluid
