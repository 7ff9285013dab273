// Hard case: chains in a strong shear. A D2Q9 channel of 32 x 8 nodes (omega = 1, nu = 1/6),
// periodic in x, between free-slip walls with traction +sigma on y_high and -sigma on y_low,
// sigma = 0.05 rho0 nu: the free fluid's steady gradient is du_x/dy = sigma / (rho0 nu) = 0.05,
// 25 times the paper's Fig. 6 and wall speeds near 0.175 (Mach 0.3). Eight chains of 4 particles
// stand across the flow (each spans 4 layers whose speeds differ by 0.15); contact keeps them
// between the walls.
// The chains either keep their orientation (the paper's model) or rotate with the flow (issue 16).
// Expectation: bounded over 3000 steps (about 8 viscous times H^2 / nu; the monitor every 50 steps
// with the default limits never stops it); the two tractions cancel, so total x momentum stays
// zero to 1e-12 of the momentum one wall puts in (sigma nx t); fluid mass to 1e-12; every particle
// stays between the walls; the free fluid's gradient is 0.05 to 1%, and the chains flatten it
// (apparent viscosity, free gradient over chain gradient, above 1).
#include <algorithm>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr int kLength = 32, kRows = 8;
constexpr double kGradient = 0.05, kNu = 1.0 / 6.0;
constexpr long kSteps = 3000;

scene::Scene sheared(bool with_chains, bool rotating = false) {
  scene::Scene s;
  s.fluid.nx = kLength;
  s.fluid.ny = kRows;
  const double sigma = kGradient * s.fluid.rho0 * kNu;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kFreeSlip;
  s.fluid.sides[fluid::kYLow].traction = {-sigma, 0, 0};
  s.fluid.sides[fluid::kYHigh].traction = {sigma, 0, 0};
  s.monitor.interval = 50;
  if (!with_chains) return s;
  for (int c = 0; c < 8; ++c) {
    solid::BodySpec chain;
    chain.name = "chain" + std::to_string(c);
    chain.shape = solid::BodyShape::kChain;
    chain.length = 4;
    chain.axis = 1;
    chain.centre = {2.0 + 4 * c, 3.5, 0};  // particles on rows 2..5
    chain.rotation = rotating;
    s.bodies.push_back(chain);
  }
  return s;
}

struct Sheared {
  double gradient = 0;        // slope of u_x(y) over the inner rows 1..6
  double momentum_error = 0;  // |total P_x| / (sigma nx t)
  double mass_error = 0;
  double lowest = INFINITY, highest = -INFINITY;  // extreme particle y over the run
};

Sheared run_sheared(bool with_chains, bool rotating = false) {
  const scene::Scene s = sheared(with_chains, rotating);
  auto sim = scene::build_simulation(s);
  const double mass0 = sim->totals().fluid_mass;
  Sheared r;
  for (long done = 0; done < kSteps; done += 50) {
    const auto stop = run_watched(*sim, 50);
    EXPECT_FALSE(stop) << stop->what;
    if (stop) break;
    if (const auto* solid = sim->solid())
      for (int p = 0; p < solid->particle_count(); ++p) {
        r.lowest = std::min(r.lowest, solid->position(p)[1]);
        r.highest = std::max(r.highest, solid->position(p)[1]);
      }
  }
  EXPECT_EQ(non_finite_or_negative(*sim), "");
  const auto profile = sim->velocity_profile();
  std::vector<double> y, u;
  for (int row = 1; row < kRows - 1; ++row) {
    y.push_back(row);
    u.push_back(profile[row]);
  }
  r.gradient = testing::fit_line(y, u).slope;
  const auto t = sim->totals();
  r.momentum_error = std::abs(t.momentum()[0]) / (s.fluid.sides[fluid::kYHigh].traction[0] * kLength * kSteps);
  r.mass_error = std::abs(t.fluid_mass - mass0) / mass0;
  return r;
}

TEST(StrongShear, ChainsAcrossAGradientOfPointZeroFiveStayBounded) {
  const Sheared free = run_sheared(false);
  const Sheared chains = run_sheared(true);
  const double free_error = std::abs(free.gradient - kGradient) / kGradient;
  std::printf("[ figure   ] gradient free %.5f, with chains %.5f (apparent viscosity %.3f); chain particles "
              "between y = %.3f and %.3f\n",
              free.gradient, chains.gradient, free.gradient / chains.gradient, chains.lowest, chains.highest);
  report("free gradient vs sigma / (rho nu) (relative)", free_error, 1e-2);
  report("x momentum, free (relative to sigma nx t)", free.momentum_error, 1e-12);
  report("x momentum, chains (relative to sigma nx t)", chains.momentum_error, 1e-12);
  report("fluid mass drift, chains (relative)", chains.mass_error, 1e-12);
  EXPECT_LT(free_error, 1e-2);
  EXPECT_LT(free.momentum_error, 1e-12);
  EXPECT_LT(chains.momentum_error, 1e-12);
  EXPECT_LT(free.mass_error, 1e-12);
  EXPECT_LT(chains.mass_error, 1e-12);
  EXPECT_GT(chains.lowest, -0.5);
  EXPECT_LT(chains.highest, kRows - 0.5);
  EXPECT_GT(free.gradient / chains.gradient, 1.0);
}

// The same chains free to rotate (issue 16's hard cases): they stay bounded with the momentum and
// mass as exact as before, and the monitor never stops them. They turn towards the flow (their
// particles no longer reach rows 2 and 5), and so raise the apparent viscosity less than chains
// held across it (measured 1.12 against 1.73): the shear thinning the paper expected of rotating
// polymers, here at one stress.
TEST(StrongShear, RotatingChainsInTheSameGradientStayBounded) {
  const Sheared free = run_sheared(false);
  const Sheared held = run_sheared(true);
  const Sheared chains = run_sheared(true, /*rotating=*/true);
  std::printf("[ figure   ] rotating chains: gradient %.5f (apparent viscosity %.3f, held chains %.3f); particles "
              "between y = %.3f and %.3f\n",
              chains.gradient, free.gradient / chains.gradient, free.gradient / held.gradient, chains.lowest,
              chains.highest);
  EXPECT_LT(free.gradient / chains.gradient, free.gradient / held.gradient);
  report("x momentum, rotating chains (relative to sigma nx t)", chains.momentum_error, 1e-12);
  report("fluid mass drift, rotating chains (relative)", chains.mass_error, 1e-12);
  EXPECT_LT(chains.momentum_error, 1e-12);
  EXPECT_LT(chains.mass_error, 1e-12);
  EXPECT_GT(chains.lowest, -0.5);
  EXPECT_LT(chains.highest, kRows - 0.5);
}

}  // namespace
}  // namespace lbsolid::hard_cases
