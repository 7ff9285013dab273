#pragma once
// The one fused kernel: for every cell, pull the populations from upstream (walls and periodic
// sides resolved by the row plan), collide, and write the result to the other buffer. Generic
// over the lattice descriptor and the collision; the interior of each row is a branch-free loop
// over x that the compiler vectorises.
#include "fluid/row_plan.h"

namespace lbsolid::fluid {

template <class L, class T, class Collision, bool kForce>
void stream_collide_rows(const RowPlans<L, T>& plans, const T* src, T* dst, long cells, int nx,
                         int ny, long row_begin, long row_end, T omega, T rho0) {
  constexpr int Q = L::Q;
  for (long row = row_begin; row < row_end; ++row) {
    const int y = static_cast<int>(row % ny);
    const int z = static_cast<int>(row / ny);
    const auto& plan = plans.for_row(y, z);
    const long row_start = row * nx;
    const T force[3] = {plan.force[0], plan.force[1], plan.force[2]};

    auto update_cells = [&](int part, int x_begin, int x_end) {
      const T* in[Q];
      T* out[Q];
      T corr[Q];
      for (int i = 0; i < Q; ++i) {
        const auto& s = plan.sources[part][i];
        in[i] = src + s.dir * cells + row_start + s.delta;
        out[i] = dst + i * cells + row_start;
        corr[i] = s.correction;
      }
#pragma GCC ivdep
      for (int x = x_begin; x < x_end; ++x) {
        T f[Q];
        for (int i = 0; i < Q; ++i) f[i] = in[i][x] + corr[i];
        Collision::template collide<kForce>(f, omega, rho0, force);
        for (int i = 0; i < Q; ++i) out[i][x] = f[i];
      }
    };
    update_cells(0, 0, 1);
    if (nx > 2) update_cells(1, 1, nx - 1);
    if (nx > 1) update_cells(2, nx - 1, nx);
  }
}

}  // namespace lbsolid::fluid
