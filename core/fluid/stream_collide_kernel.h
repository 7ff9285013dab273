#pragma once
// The one fused kernel: for every cell, pull the populations from upstream (walls and periodic
// sides resolved by the row plan), collide, and write the result to the other buffer. Generic
// over the lattice descriptor and the collision.
//
// Consecutive rows that share a plan are swept as one contiguous run of cells: a long branch-free
// loop that the compiler vectorises and the hardware prefetcher can follow (short 3D rows defeat
// it). The first and last cell of each row, whose sources wrap or hit a wall, are then computed
// again with their own plan, overwriting what the long sweep wrote there. Every read of the sweep
// stays inside the buffer: its two ends are interior cells, whose sources are real cells.
#include "fluid/cell_update.h"
#include "fluid/line_aligned_parts.h"
#include "fluid/force_inline.h"
#include "fluid/row_plan.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce>
LBSOLID_FORCE_INLINE void stream_collide_rows(const RowPlans<L, T>& plans, const T* src, T* dst, long stride, int nx,
                         long row_begin, long row_end, typename Collision::Rates rates, T rho0) {
  constexpr int Q = L::Q;
  // Updates cells [begin, end) reading population i at cell + sources[i].delta.
  auto sweep = [&](const RowPlan<T, Q>& plan, const PullSources<T, Q>& sources, long begin, long end)
                   LBSOLID_FORCE_INLINE_LAMBDA {
    const T* in[Q];
    T* out[Q];
    WallMap<T, Q> in_map;
    constexpr auto no_wall = WallMap<T, Q>::identity();
    for (int i = 0; i < Q; ++i) {
      const auto& s = sources[i];
      in[i] = src + s.dir * stride + s.delta;
      out[i] = dst + i * stride;
      in_map.scale[i] = s.scale;
      in_map.shift[i] = s.correction;
    }
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};
    update_corrected_cells<L, T, Collision, kForce>(in, in_map, out, no_wall, force, rates, rho0, begin, end);
  };
  for (long first = row_begin; first < row_end;) {
    const RowPlan<T, Q>& plan = plans.for_row(first);
    const long last = plans.last_row_sharing_plan(first, row_end);
    if (nx > 2)
      for_line_aligned_parts<T>(first * nx + 1, last * nx + nx - 1, [&](long begin, long end) LBSOLID_FORCE_INLINE_LAMBDA {
        sweep(plan, plan.sources[1], begin, end);
      });
    for (long row = first; row <= last; ++row) {
      sweep(plan, plans.sources(row, 0), row * nx, row * nx + 1);
      if (nx > 1) sweep(plan, plans.sources(row, 2), row * nx + nx - 1, row * nx + nx);
    }
    first = last + 1;
  }
}

}  // namespace lbsolid::fluid
