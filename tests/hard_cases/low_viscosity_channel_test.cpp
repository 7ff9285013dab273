// Hard case: low viscosity. A D2Q9 channel at omega = 1.99 (nu = (1/1.99 - 1/2)/3 = 0.00084),
// 64 rows between two bounce-back walls, periodic in x, driven from rest by a uniform body force
// F = 3.75e-6 for 4000 steps: the bulk reaches u = F t / rho0 = 0.015, so Re = u H / nu = 1150
// (laminar: a 2D channel stays so up to Re 5772), with boundary layers only
// sqrt(nu t) = 1.8 nodes thick: the steepest gradients BGK sees at this omega.
// Expectation, for each collision operator (BGK, TRT, regularized):
//   - bounded: the monitor (every 100 steps, Mach 0.3, density in [0.5, 2] rho0) never stops it;
//   - mass conserved to 1e-12 (relative);
//   - the bulk (centre row) moves at F t / rho0 to round-off: nothing from the walls has reached
//     it (erfc(32 / (2 sqrt(nu t))) ~ 1e-34);
//   - the momentum the walls took, per wall, is Stokes's first problem for a uniformly forced
//     fluid next to a no-slip wall: (4 / (3 sqrt(pi))) F t^(3/2) nu^(1/2), to the discretisation
//     error of a boundary layer under 2 nodes thick (bounds below).
// All three operators are implemented (fluid_lattice.cpp): a simulation that cannot be built fails
// the test (the exception reaches gtest), it is not a skip.
#include <cmath>
#include <numbers>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr int kRows = 64;
constexpr double kOmega = 1.99;
constexpr double kForce = 3.75e-6;
constexpr long kSteps = 4000;

scene::Scene channel(fluid::CollisionModel model) {
  scene::Scene s;
  s.fluid.nx = 8;
  s.fluid.ny = kRows;
  s.fluid.omega = kOmega;
  s.fluid.collision = model;
  s.fluid.body_force = {kForce, 0, 0};
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  s.monitor.interval = 100;
  s.monitor.limits.max_mach = 0.3;
  return s;
}

class LowViscosityChannel : public ::testing::TestWithParam<fluid::CollisionModel> {};

TEST_P(LowViscosityChannel, StaysBoundedAndConservesMass) {
  const scene::Scene s = channel(GetParam());
  const auto warnings = scene::scene_warnings(s);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "omega: 1.99 is above 1.95; the fluid is close to its stability limit");
  const std::unique_ptr<scene::Simulation> sim = scene::build_simulation(s);
  const double nu = (1 / kOmega - 0.5) / 3, mass0 = sim->totals().fluid_mass;
  const auto stop = run_watched(*sim, kSteps);
  ASSERT_FALSE(stop) << stop->what;
  ASSERT_EQ(non_finite_or_negative(*sim), "");

  const auto t = sim->totals();
  const double mass_error = std::abs(t.fluid_mass - mass0) / mass0;
  const double plug = kForce * kSteps / s.fluid.rho0;
  const double bulk_error = std::abs(sim->velocity_profile()[kRows / 2] - plug) / plug;
  // Momentum the walls took: what the force put in minus what the fluid holds, half per wall.
  const double nodes = static_cast<double>(s.fluid.nx) * kRows;
  const double per_wall = (kForce * nodes * kSteps - t.fluid_momentum[0]) / (2 * s.fluid.nx);
  const double stokes = 4 / (3 * std::sqrt(std::numbers::pi)) * kForce * std::pow(kSteps, 1.5) * std::sqrt(nu);
  const double stokes_error = std::abs(per_wall - stokes) / stokes;
  const std::string name = fluid::collision_model_name(GetParam());
  std::printf("[ figure   ] %s: Re = %.0f, bulk u = %.5f\n", name.c_str(), plug * kRows / nu, plug);
  // Bulk: F t summed over 4000 steps, each rounding ~eps of 0.015, so at most ~4000 eps = 9e-13
  // relative; measured (Release) 1.6e-13 (BGK), 3.9e-15 (TRT), 1.4e-14 (regularized). Bound 1e-11,
  // 10x that worst case.
  // Stokes: a discretisation error, second order in the layer thickness delta = sqrt(nu t):
  // measured with BGK (D2Q9, Release) +9.7%, +2.15%, +0.50% at delta = 0.92, 1.83, 3.66 nodes
  // (t = 1000, 4000, 16000), falling 4.5x and 4.3x per doubling; regularized +2.13% and TRT -0.60%
  // here (TRT -0.63%, -0.19% at delta 0.92 and 3.66). Bound 1.5x the measured value, rounded up:
  // 3.5% for BGK and regularized, 1% for TRT.
  const double stokes_bound = GetParam() == fluid::CollisionModel::kTrt ? 0.01 : 0.035;
  report(name + " mass error (relative)", mass_error, 1e-12);
  report(name + " bulk velocity error (relative)", bulk_error, 1e-11);
  report(name + " wall momentum vs Stokes (relative)", stokes_error, stokes_bound);
  EXPECT_LT(mass_error, 1e-12);
  EXPECT_LT(bulk_error, 1e-11);
  EXPECT_LT(stokes_error, stokes_bound);
}

INSTANTIATE_TEST_SUITE_P(EachCollisionOperator, LowViscosityChannel,
                         ::testing::Values(fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt,
                                           fluid::CollisionModel::kRegularized),
                         [](const auto& info) { return std::string(fluid::collision_model_name(info.param)); });

}  // namespace
}  // namespace lbsolid::hard_cases
