// Jeffery orbits (issue 16): a rotating elongated body in simple shear tumbles by Jeffery's law,
// tan(phi) = tan(2 pi t / T) / r with T = 2 pi (r + 1/r) / gamma_dot (accuracy/rotation_in_shear.h
// derives what is measured). A lattice body is not a continuum ellipse, so its aspect ratio r is
// not given: the test takes the effective one from the SHAPE of its turn (the time it spends within
// 45 degrees of the flow), states it, and checks against Jeffery's law what that r does not fix: the
// period, and the angle at every moment of a full turn.
//
// The body: the lattice ellipse of semi-axes 6 x 2 (37 particles at spacing 1; the continuum
// ellipse's r is 3) in the middle of a D2Q9 Couette flow, H = 64 (body length / H = 0.19), 128
// long, omega = 1, gamma_dot = 5e-4: Re = gamma_dot a^2 / nu = 0.11. Measured r = 3.98 (a Jeffery
// period 28% longer than r = 3 gives: the lattice body turns like a slimmer ellipse; 3.65 at twice
// the size and the same Re, converging slowly, see the accuracy report's jeffery rows). Doubling
// H moved the period by under 3%; halving Re by under 0.5%.
#include <gtest/gtest.h>

#include <numbers>

#include "accuracy/rotation_in_shear.h"
#include "fluid/fluid_test_support.h"

namespace lbsolid::accuracy {
namespace {

using testing::report;

constexpr double kShearRate = 5e-4;

JefferyFit ellipse_orbit(double spacing) {
  CouetteFlow flow;  // D2Q9 64 x 128, omega 1
  flow.shear_rate = kShearRate;
  scene::Scene s = couette_scene(flow);
  s.bodies.push_back(lattice_ellipse(6, 2, spacing, {flow.length / 2.0, (flow.height - 1) / 2.0, 0}));
  auto sim = scene::build_simulation(s);
  // It starts along the flow and turns a quarter in about 14,000 steps, a full turn (Jeffery's
  // period for r = 4) in 53,000 more: 100,000 steps is ample.
  const auto turn = follow_turn(*sim, 20, 2.6 * std::numbers::pi, 100000);
  return fit_jeffery(turn, kShearRate);
}

void expect_jeffery(const JefferyFit& fit, double aspect_ratio_measured) {
  ASSERT_TRUE(fit.complete) << "no full turn within the run";
  std::printf("  effective aspect ratio %.3f (measured %.2f when written); gamma_dot T = %.3f (half turns %.3f, %.3f);"
              " against Jeffery at r = 3: %+.3f\n",
              fit.aspect_ratio, aspect_ratio_measured, fit.shear_period, fit.half_periods[0], fit.half_periods[1],
              fit.shear_period / jeffery_shear_period(3) - 1);
  // Within 5% (issue 16). Measured +1.1% (spacing 1), +0.9% (1/2): inertia at Re 0.1 and the walls
  // lengthen the period a little (at Re 0.43 it is +2 to +3%).
  report("period against Jeffery's at the effective aspect ratio", fit.period_error, 0.05);
  EXPECT_LT(std::abs(fit.period_error), 0.05);
  // Measured 0.014 rad at both spacings. Sampling every 20 steps is good to 0.005 rad; at Re 0.43
  // the deviation reaches 0.04-0.05, which this bound would catch.
  report("largest angle off Jeffery's law over the turn (rad)", fit.law_deviation, 0.03);
  EXPECT_LT(fit.law_deviation, 0.03);
}

TEST(JefferyOrbit, ALatticeEllipseTumblesByJefferysLaw) { expect_jeffery(ellipse_orbit(1.0), 3.98); }

// The same ellipse of 145 particles at spacing 1/2 (four per node): measured r = 3.79.
TEST(JefferyOrbit, APackedEllipseTumblesByJefferysLaw) { expect_jeffery(ellipse_orbit(0.5), 3.79); }

// The law itself, against a rate integrated numerically: Jeffery's angle solves
// d(phi)/dt = gamma_dot (r^2 sin^2 phi + cos^2 phi) / (r^2 + 1) with psi = 2 pi t / T.
TEST(JefferyOrbit, TheAngleFormulaSolvesJefferysEquation) {
  for (double r : {1.0, 2.0, 3.98}) {
    const double t_period = jeffery_shear_period(r) / kShearRate;
    double phi = -std::numbers::pi / 2, worst = 0;
    const int n = 200000;
    const double dt = t_period / 2 / n;  // half a turn, from across the flow to across again
    for (int k = 0; k < n; ++k) {        // midpoint rule: error ~ dt^2
      const auto rate = [&](double p) {
        return kShearRate * (r * r * std::sin(p) * std::sin(p) + std::cos(p) * std::cos(p)) / (r * r + 1);
      };
      phi += dt * rate(phi + dt / 2 * rate(phi));
      const double psi = -std::numbers::pi / 2 + 2 * std::numbers::pi * (k + 1) * dt / t_period;
      worst = std::max(worst, std::abs(phi - jeffery_angle(psi, r)));
    }
    EXPECT_LT(worst, 1e-8) << "r = " << r;
  }
}

// The fit, on a turn made by Jeffery's law itself (r = 2.5, starting along the flow, sampled every
// 20 steps) and on one at a constant rate (a disk's: r = 1): it finds r and no deviation; for the
// constant rate with Jeffery's period of r = 2.5 instead, the law's check fails by far.
TEST(JefferyOrbit, TheFitFindsTheAspectRatioOfAKnownTurn) {
  const auto sampled = [](double r, double shear_period) {
    std::vector<TurnSample> turn;
    const double t_period = shear_period / kShearRate;
    for (long step = 0; step <= 2 * static_cast<long>(t_period); step += 20)
      turn.push_back({step, jeffery_angle(2 * std::numbers::pi * step / t_period, r)});
    return turn;
  };
  const JefferyFit jeffery = fit_jeffery(sampled(2.5, jeffery_shear_period(2.5)), kShearRate);
  ASSERT_TRUE(jeffery.complete);
  EXPECT_NEAR(jeffery.aspect_ratio, 2.5, 1e-3);  // linear interpolation between samples 20 steps apart
  EXPECT_LT(std::abs(jeffery.period_error), 1e-4);
  EXPECT_LT(jeffery.law_deviation, 1e-3);

  const JefferyFit uniform = fit_jeffery(sampled(1.0, jeffery_shear_period(1.0)), kShearRate);
  EXPECT_NEAR(uniform.aspect_ratio, 1.0, 1e-3);
  EXPECT_LT(std::abs(uniform.period_error), 1e-4);

  const JefferyFit wrong = fit_jeffery(sampled(1.0, jeffery_shear_period(2.5)), kShearRate);
  EXPECT_NEAR(wrong.aspect_ratio, 1.0, 1e-3);  // the shape says a disk
  EXPECT_GT(wrong.period_error, 0.1);          // 2 pi (2.5 + 0.4) against 4 pi: +45%
}

}  // namespace
}  // namespace lbsolid::accuracy
