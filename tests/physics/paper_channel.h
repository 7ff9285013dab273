#pragma once
// The paper's set-up for its experiments (section 4): a D2Q7 fluid with omega = 1 in a channel
// periodic in x between two walls of one kind at y_low and y_high.
#include "scene/scene.h"

namespace lbsolid::testing {

inline scene::Scene paper_channel(int nx, int ny, fluid::WallKind walls, double omega = 1.0, double rho0 = 1.0) {
  scene::Scene s;
  s.lattice = scene::LatticeKind::kD2Q7;
  s.fluid.nx = nx;
  s.fluid.ny = ny;
  s.fluid.omega = omega;
  s.fluid.rho0 = rho0;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = walls;
  return s;
}

}  // namespace lbsolid::testing
