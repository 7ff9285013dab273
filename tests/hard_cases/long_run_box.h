#pragma once
// The long run's scene, shared by the CI test (10^5 steps) and tests/bench/long_run.cpp (10^6): a
// tiny coupled periodic box, so that many steps stay cheap and round-off, not physics, is what
// the run measures. A 2 x 2 sheet moving diagonally through an 8 x 8 D2Q9 box at rest (omega 1):
// no walls, no load, no body force, so total momentum (fluid + solid) is exactly conserved by
// the model (MODEL.md section 3) and whatever it drifts by is accumulated rounding.
#include <cmath>

#include "scene/simulation.h"

namespace lbsolid::hard_cases {

inline scene::Scene long_run_box() {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 8;
  solid::BodySpec sheet;
  sheet.name = "sheet";
  sheet.size = {2, 2, 1};
  sheet.centre = {4.3, 3.8, 0};
  sheet.velocity = {0.02, 0.01, 0};
  s.bodies.push_back(sheet);
  s.monitor.interval = 1000;
  return s;
}

// |P(t) - P(0)| / |P(0)|: the drift relative to the box's total momentum.
inline double momentum_drift(const scene::Totals& now, const scene::Totals& start) {
  const auto a = now.momentum(), b = start.momentum();
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) / std::hypot(b[0], b[1], b[2]);
}

}  // namespace lbsolid::hard_cases
