// Hard case (issue 18): anchors in dense packing. A sheet packed at eta = 1, 4 and 8 particles per
// node (rest spacing 1/sqrt(eta)), covering about 6 x 6 nodes of a 16 x 16 periodic D2Q9 box
// (omega 1), every particle anchored, the fluid driven past it by a body force g per node; the
// monitor checks every 10 steps. Several anchored particles on one node share that node's
// exchange (MomentumExchange: the node and its particles reach u* = 0 together).
// Expectation with the common-velocity exchange: bounded for every eta; at every step the total
// momentum changes by exactly what the drive put in minus what the anchors took, to round-off;
// fluid mass conserved to 1e-12; and once steady, the anchors hold the whole drive.
#include <cmath>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr double kDrive = 1e-5;  // per node: a free flow of 1e-5 t, held by the sheet

scene::Scene anchored_packing(int eta) {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 16;
  s.fluid.body_force = {kDrive, 0, 0};
  solid::BodySpec sheet;
  sheet.name = "packing";
  sheet.spacing = 1 / std::sqrt(static_cast<double>(eta));
  const int side = static_cast<int>(std::lround(6 / sheet.spacing));
  sheet.size = {side, side, 1};
  sheet.centre = {8.25, 8.25, 0};  // off the node grid: no particle sits exactly between two nodes
  sheet.anchored = true;
  s.bodies.push_back(sheet);
  s.monitor.interval = 10;
  return s;
}

class DenseAnchors : public ::testing::TestWithParam<int> {};

TEST_P(DenseAnchors, StayBoundedAndBalanceTheDriveToRoundOff) {
  const int eta = GetParam();
  auto sim = scene::build_simulation(anchored_packing(eta));
  const double nodes = 16.0 * 16.0;
  const double mass0 = sim->totals().fluid_mass;
  auto before = sim->totals();
  double worst = 0, held = 0;
  constexpr int kSteps = 3000, kAveraged = 200;
  for (int t = 1; t <= kSteps; ++t) {
    const auto stop = run_watched(*sim, 1);
    ASSERT_FALSE(stop) << stop->what;
    const auto absorbed = sim->body_state(0).anchor_force;
    const auto now = sim->totals();
    for (int a = 0; a < 2; ++a) {
      const double entered = (a == 0 ? kDrive * nodes : 0.0) - absorbed[a];
      worst = std::max(worst, std::abs(now.momentum()[a] - before.momentum()[a] - entered));
    }
    before = now;
    if (t > kSteps - kAveraged) held += absorbed[0] / kAveraged;
  }
  ASSERT_EQ(non_finite_or_negative(*sim), "");
  const std::string name = "eta " + std::to_string(eta) + " (" + std::to_string(sim->solid()->particle_count()) + " anchored)";
  const double mass = std::abs(sim->totals().fluid_mass - mass0) / mass0;
  // Momenta of order nodes * 1e-5 t: round-off near 1e-16 of what each step adds up.
  report(name + ": worst per-step momentum balance", worst, 1e-13);
  report(name + ": fluid mass drift (relative)", mass, 1e-12);
  report(name + ": drive held by the anchors (fraction)", held / (kDrive * nodes), 1);
  EXPECT_LT(worst, 1e-13);
  EXPECT_LT(mass, 1e-12);
  // Steady: the flow through the gaps between the sheet's periodic images settles in a few viscous
  // times of the 10-node gap (10^2 / (nu pi^2) = 60 steps at nu 1/6); after 3000 steps the anchors
  // hold the whole drive, within 0.1%.
  EXPECT_NEAR(held, kDrive * nodes, 1e-3 * kDrive * nodes);
}

INSTANTIATE_TEST_SUITE_P(ParticlesPerNode, DenseAnchors, ::testing::Values(1, 4, 8));

}  // namespace
}  // namespace lbsolid::hard_cases
