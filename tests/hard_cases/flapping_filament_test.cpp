// Hard case: a filament flapping in a fast current (issue 18), at the highest drive the flapping
// figure uses (client-examples/python/figures/seaweed_flapping.py). A chain of 20 anchored at its
// bottom particle on the floor of a 256 x 64 D2Q9 channel (TRT, omega 1.8: nu = 0.0185), periodic
// in x, driven by g = 2e-5 per node: the mean flow reaches about 0.09 (Mach 0.3 at the fastest
// row), Re = <u> (L - 1) / nu about 95, and the filament flaps: its tip sweeps back and forth by
// about 5 nodes (more than twice its mean deflection) with a period near 1800 steps.
// Expectation over 20000 steps: bounded (the monitor every 500 steps never stops it; every value
// finite; the fluid's mass to 1e-12), the anchor held where it was placed, no particle through a
// wall, and the tip's range over the second half above 2 nodes (it does flap: measured 5.3).
#include <algorithm>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr int kLength = 20;

scene::Scene flapping_filament() {
  scene::Scene s;
  s.fluid.nx = 256;
  s.fluid.ny = 64;
  s.fluid.omega = 1.8;
  s.fluid.collision = fluid::CollisionModel::kTrt;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  s.fluid.body_force = {2e-5, 0, 0};
  s.monitor.interval = 500;
  solid::BodySpec weed;
  weed.name = "weed";
  weed.shape = solid::BodyShape::kChain;
  weed.length = kLength;
  weed.axis = 1;
  weed.centre = {64, 1.5 + (kLength - 1) / 2.0, 0};  // its bottom particle two nodes above the floor
  weed.anchor_labels = {{0, 0, 0}};
  s.bodies.push_back(weed);
  return s;
}

TEST(HardCases, AFilamentFlappingInAFastCurrentStaysBounded) {
  const scene::Scene scene = flapping_filament();
  auto sim = scene::build_simulation(scene);
  const auto& solid = *sim->solid();
  const scene::Totals start = sim->totals();
  const solid::Vec3 anchor = solid.position(0);
  constexpr long kSteps = 20000;
  double lowest = INFINITY, highest = -INFINITY, tip_min = INFINITY, tip_max = -INFINITY, moved = 0;
  std::optional<Stop> stop;
  for (long t = 1; t <= kSteps && !stop; ++t) {
    stop = run_watched(*sim, 1);
    for (int p = 0; p < kLength; ++p) {
      lowest = std::min(lowest, solid.position(p)[1]);
      highest = std::max(highest, solid.position(p)[1]);
    }
    moved = std::max(moved, norm(difference(solid.position(0), anchor)));
    if (t > kSteps / 2) {
      tip_min = std::min(tip_min, solid.position(kLength - 1)[0]);
      tip_max = std::max(tip_max, solid.position(kLength - 1)[0]);
    }
  }
  EXPECT_FALSE(report_stop(*sim, stop, "flapping filament")) << "the monitor stopped it";
  report("flapping filament: tip range over the second half (nodes)", tip_max - tip_min, 2);
  EXPECT_GT(tip_max - tip_min, 2) << "it does not flap";
  EXPECT_EQ(moved, 0) << "the anchor moved";
  // Nodes 0 .. ny - 1, half-way walls at -1/2 and ny - 1/2.
  EXPECT_GT(lowest, 0);
  EXPECT_LT(highest, scene.fluid.ny - 1);
  EXPECT_EQ(non_finite_or_negative(*sim), "");
  const double mass = std::abs(sim->totals().fluid_mass - start.fluid_mass) / start.fluid_mass;
  report("flapping filament: fluid mass drift (relative)", mass, 1e-12);
  EXPECT_LT(mass, 1e-12);
}

}  // namespace
}  // namespace lbsolid::hard_cases
