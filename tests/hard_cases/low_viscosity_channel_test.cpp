// Hard case: low viscosity. A D2Q9 channel at omega = 1.99 (nu = (1/1.99 - 1/2)/3 = 0.00084),
// 64 rows between two bounce-back walls, periodic in x, driven from rest by a uniform body force
// F = 3.75e-6 for 4000 steps: the bulk reaches u = F t / rho0 = 0.015, so Re = u H / nu = 1150
// (laminar: a 2D channel stays so up to Re 5772), with boundary layers only
// sqrt(nu t) = 1.8 nodes thick: the steepest gradients BGK sees at this omega.
// Expectation, for each collision operator (BGK, TRT, regularized):
//   - bounded: the monitor (every 100 steps, Mach 0.3, density in [0.5, 2] rho0) never stops it;
//   - mass conserved to 1e-12 (relative);
//   - the bulk (centre row) moves at F t / rho0 to 1e-3: nothing from the walls has reached it;
//   - the momentum the walls took, per wall, is Stokes's first problem for a uniformly forced
//     fluid next to a no-slip wall: (4 / (3 sqrt(pi))) F t^(3/2) nu^(1/2), to 20% (a boundary layer
//     under 2 nodes thick is not resolved better).
// An operator that is not implemented yet is reported as skipped (build_simulation refuses it).
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
  std::unique_ptr<scene::Simulation> sim;
  try {
    sim = scene::build_simulation(s);
  } catch (const std::invalid_argument& e) {
    GTEST_SKIP() << "collision operator not available: " << e.what();
  }
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
  report(name + " mass error (relative)", mass_error, 1e-12);
  report(name + " bulk velocity error (relative)", bulk_error, 1e-3);
  report(name + " wall momentum vs Stokes (relative)", stokes_error, 0.2);
  EXPECT_LT(mass_error, 1e-12);
  EXPECT_LT(bulk_error, 1e-3);
  EXPECT_LT(stokes_error, 0.2);
}

INSTANTIATE_TEST_SUITE_P(EachCollisionOperator, LowViscosityChannel,
                         ::testing::Values(fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt,
                                           fluid::CollisionModel::kRegularized),
                         [](const auto& info) { return std::string(fluid::collision_model_name(info.param)); });

}  // namespace
}  // namespace lbsolid::hard_cases
