// Hard case: light and heavy solids. A 4 x 4 sheet (mass 24 over 16 nodes) moving at 0.02 through
// a 16 x 16 periodic D2Q9 box at rest, omega = 1, with the solid-to-fluid mass ratio per node
// (scene::body_mass_ratio) set to 0.01, 0.1, 1, 10 and 100 through rho0 (MODEL.md section 2: the
// particle mass M = K/2 is fixed, the fluid's density is what varies; rho0 from 150 down to 0.015).
// Expectation, at every ratio (the common-velocity exchange is implicit in the mass ratio):
//   - bounded: the monitor (every 50 steps, default limits; the density band is relative to rho0)
//     never stops it;
//   - total momentum conserved to 1e-12 of the initial momentum, fluid mass to 1e-12;
//   - after 6000 steps (4 viscous times L^2 / nu of the box; the slowest mode has decayed by
//     e^-150) sheet and fluid share one velocity, P / (M_solid + M_fluid): the sheet's velocity
//     within 1e-9 of the initial 0.02 of it.
// No ratio in this range is unstable (nor with the pairwise rule, nor under a load), so a mass
// ratio gets no warning.
#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr double kSpeed = 0.02;
constexpr long kSteps = 6000;

scene::Scene sheet_in_box(double mass_ratio) {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 16;
  solid::BodySpec sheet;
  sheet.name = "sheet";
  sheet.size = {4, 4, 1};
  sheet.centre = {8, 8, 0};
  sheet.velocity = {kSpeed, 0, 0};
  s.bodies.push_back(sheet);
  s.fluid.rho0 = scene::body_mass_ratio(s, 0) / mass_ratio;  // the ratio is 1.5 / rho0
  s.monitor.interval = 50;
  return s;
}

class MassRatio : public ::testing::TestWithParam<double> {};

TEST_P(MassRatio, StaysBoundedConservesMomentumAndReachesTheCommonVelocity) {
  const double ratio = GetParam();
  const scene::Scene s = sheet_in_box(ratio);
  EXPECT_NEAR(scene::body_mass_ratio(s, 0), ratio, 1e-12 * ratio);
  EXPECT_TRUE(scene::scene_warnings(s).empty());
  auto sim = scene::build_simulation(s);
  const auto t0 = sim->totals();
  const double p0 = norm(t0.momentum());
  const auto stop = run_watched(*sim, kSteps);
  ASSERT_FALSE(stop) << stop->what;
  ASSERT_EQ(non_finite_or_negative(*sim), "");

  const auto t = sim->totals();
  const double momentum_error = norm(difference(t.momentum(), t0.momentum())) / p0;
  const double mass_error = std::abs(t.fluid_mass - t0.fluid_mass) / t0.fluid_mass;
  const double common = p0 / (sim->body_state(0).mass + t0.fluid_mass);
  const double velocity_error = std::abs(sim->body_state(0).velocity[0] - common) / kSpeed;
  const std::string name = "ratio " + std::to_string(ratio).substr(0, 6);
  report(name + ": momentum drift (relative)", momentum_error, 1e-12);
  report(name + ": fluid mass drift (relative)", mass_error, 1e-12);
  report(name + ": |u_sheet - P/M_total| / u0", velocity_error, 1e-9);
  EXPECT_LT(momentum_error, 1e-12);
  EXPECT_LT(mass_error, 1e-12);
  EXPECT_LT(velocity_error, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(LightToHeavy, MassRatio, ::testing::Values(0.01, 0.1, 1.0, 10.0, 100.0));

}  // namespace
}  // namespace lbsolid::hard_cases
