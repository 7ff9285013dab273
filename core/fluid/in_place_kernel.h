#pragma once
// In-place streaming on one buffer (the AA pattern, Bailey et al. 2009): two fused kernels that
// alternate, each reading and writing the same slots, so no second buffer is needed and every
// cache line a cell reads is the one it writes back.
//
//   even step: a cell reads its own slots f_i = A[i][x], collides, and writes each result reversed
//              into its own cell, A[opp(i)][x] = f*_i. No neighbour is touched.
//   odd step:  a cell pulls through the row plan: population k comes from f*_j at node s, which
//              the even step left in A[opp(j)][s]. After colliding it writes f*_k into the slot it
//              read for opp(k), through that entry's wall rule; that slot is where the next
//              even step finds the population arriving downstream. The wall rules are involutions,
//              so the slots a cell reads are exactly the slots it writes and cells never collide
//              (FluidLattice checks this once per configuration).
#include "fluid/cell_update.h"
#include "fluid/force_inline.h"
#include "fluid/line_aligned_parts.h"
#include "fluid/row_plan.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void collide_local_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx,
                        long row_begin, long row_end, typename Collision::Rates rates, T rho0) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
  const T* in[Q];
  T* out[Q];
  for (int i = 0; i < Q; ++i) {
    in[i] = f + i * stride;
    out[i] = f + opp[i] * stride;
  }
  constexpr auto no_wall = WallMap<T, Q>::identity();
  for (long first = row_begin; first < row_end;) {
    // This step reads no neighbour, so rows that share a force are one run of cells.
    const long last = plans.last_row_sharing_force(first, row_end);
    const RowPlan<T, Q>& plan = plans.for_row(first);
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    for_line_aligned_parts<T>(first * nx, (last + 1) * nx, [&](long begin, long end) LBSOLID_FORCE_INLINE_LAMBDA {
      update_cells<L, T, Collision, kForce, false>(in, no_wall, out, no_wall, force, rates, rho0, begin, end);
    });
    first = last + 1;
  }
}

template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void stream_collide_in_place_rows(const RowPlans<L, T>& plans, T* f, long stride, int nx,
                                  long row_begin, long row_end, typename Collision::Rates rates, T rho0) {
  constexpr int Q = L::Q;
  constexpr auto opp = lattice::opposite_table<L>();
  for (long row = row_begin; row < row_end; ++row) {
    const auto& plan = plans.for_row(row);
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    auto sweep = [&](int part, long begin, long end) LBSOLID_FORCE_INLINE_LAMBDA {
      const T* in[Q];
      T* slot[Q];
      WallMap<T, Q> in_map;
      const PullSources<T, Q>& sources = plans.sources(row, part);
      for (int k = 0; k < Q; ++k) {
        const auto& s = sources[k];
        slot[k] = f + opp[s.dir] * stride + s.delta;
        in[k] = slot[k];
        in_map.scale[k] = s.scale;
        in_map.shift[k] = s.correction;
      }
      // Population k goes back into the slot read for opp(k), through that entry's wall rule.
      T* out[Q];
      WallMap<T, Q> out_map;
      for (int k = 0; k < Q; ++k) {
        out[k] = slot[opp[k]];
        out_map.scale[k] = in_map.scale[opp[k]];
        out_map.shift[k] = in_map.shift[opp[k]];
      }
      update_corrected_cells<L, T, Collision, kForce>(in, in_map, out, out_map, force, rates, rho0, begin, end);
    };
    const long row_start = row * nx;
    sweep(0, row_start, row_start + 1);
    if (nx > 2) sweep(1, row_start + 1, row_start + nx - 1);
    if (nx > 1) sweep(2, row_start + nx - 1, row_start + nx);
  }
}

}  // namespace lbsolid::fluid
