#pragma once
// Where a population comes from in the pull scheme: the population i arriving at node (x, y, z)
// is read from population `dir` at the source node, plus `correction` (moving walls). Periodic
// sides wrap; walls answer with their rule (MODEL.md section 1):
//   bounce-back:  the node's own opposite population (half-way wall);
//   moving wall:  the same plus 2 w_i rho0 (c_i . u_w) / c_s^2 (Ladd);
//   free-slip:    the mirrored population from the node upstream along the wall. On the staggered
//                 D2Q7 rows the mirrored population travels one whole node along the wall, which is
//                 exact for flow uniform along the wall.
//   velocity inlet: the moving wall's rule with the inflow velocity u (normal to the side): Ladd's
//                 bounce-back then adds exactly rho0 u per node and step (MODEL.md section 1).
//   pressure outlet: what enters is the equilibrium f_i = f^eq_i(rho_out, u), u the velocity one
//                 node upstream: scale 0 and the equilibrium as the correction. The rule here is
//                 its value at u = 0; FluidLattice sets u after every step (refresh_outlet_corrections).
//                 Tried first and dropped: anti-bounce-back, f_i = -f*_opp(i) + 2 w_i rho_out
//                 (to first order, and with the u^2 term from that velocity): it blew up within
//                 a few hundred steps in a 128 x 32 channel at u_max 0.02 and omega 1.6, where the
//                 equilibrium stayed bounded from rest up to u_max 0.2 (parabolic, BGK at omega 1
//                 and 1.6, 6000 steps; measured by hand at cc98eba). The fast-inlet hard case
//                 (tests/hard_cases/fast_inlet_test.cpp) runs it at 0.27.
// A population is read as scale * source + correction; scale is 0 only at a pressure outlet.
#include <array>

#include "fluid/fluid_config.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::fluid {

struct PullSourceRule {
  int dir;
  std::array<int, 3> node;
  double correction;
  double scale = 1.0;
};

template <class L>
PullSourceRule resolve_pull_source(const FluidConfig& cfg, int i, int x, int y, int z) {
  const int n[3] = {cfg.nx, cfg.ny, cfg.nz};
  const int here[3] = {x, y, z};
  const int parity = L::hexagonal ? (y & 1) : 0;
  const auto o = L::neighbour_offset(lattice::opposite<L>(i), parity);
  int s[3] = {x + o[0], y + o[1], z + o[2]};
  for (int axis : {1, 2, 0}) {
    if (s[axis] >= 0 && s[axis] < n[axis]) continue;
    const int side = 2 * axis + (s[axis] < 0 ? 0 : 1);
    const SideBoundary& wall = cfg.sides[side];
    if (wall.kind == WallKind::kPeriodic) {
      s[axis] = ((s[axis] % n[axis]) + n[axis]) % n[axis];
      continue;
    }
    const int back = lattice::opposite<L>(i);
    const PullSourceRule bounce{back, {x, y, z}, 0.0};
    if (wall.kind == WallKind::kBounceBack) return bounce;
    if (wall.kind == WallKind::kMovingWall) {
      double cu = 0;
      for (int a = 0; a < 3; ++a) cu += L::c[i][a] * wall.wall_velocity[a];
      return {back, {x, y, z}, 2.0 * L::w[i] * cfg.rho0 * cu / L::cs2};
    }
    if (wall.kind == WallKind::kVelocityInlet) {  // an x side: the inflow runs along +-x
      const double u = (side == kXLow ? 1.0 : -1.0) * inflow_speed_at(cfg, side, y, z);
      return {back, {x, y, z}, 2.0 * L::w[i] * cfg.rho0 * L::c[i][0] * u / L::cs2};
    }
    if (wall.kind == WallKind::kPressureOutlet) {
      const double rho_out = wall.outflow_density > 0 ? wall.outflow_density : cfg.rho0;
      return {back, {x, y, z}, L::w[i] * (rho_out - cfg.rho0), 0.0};  // the slot pairs as bounce-back's
    }
    // Free-slip: specular reflection off the wall normal to `axis`.
    int t[3] = {x, y, z};
    for (int b = 0; b < 3; ++b) {
      if (b == axis) continue;
      const double travel = L::hexagonal ? 2.0 * L::c[i][b] : L::c[i][b];
      t[b] = here[b] - static_cast<int>(travel < 0 ? travel - 0.5 : travel + 0.5);
      if (t[b] >= 0 && t[b] < n[b]) continue;
      const SideBoundary& across = cfg.sides[2 * b + (t[b] < 0 ? 0 : 1)];
      if (across.kind != WallKind::kPeriodic) return bounce;  // a corner: bounce back
      t[b] = ((t[b] % n[b]) + n[b]) % n[b];
    }
    return {lattice::mirrored<L>(i, axis), {t[0], t[1], t[2]}, 0.0};
  }
  return {i, {s[0], s[1], s[2]}, 0.0};
}

}  // namespace lbsolid::fluid
