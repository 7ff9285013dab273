// Hard case: a dense suspension. A sheet packed at eta = 1, 2, 4 and 8 particles per node (rest
// spacing 1/sqrt(eta)), covering about 6 x 6 nodes of a 16 x 16 periodic D2Q9 box (omega = 1) and
// moving at 0.05 through fluid at rest.
// Expectation with the common-velocity exchange (MODEL.md section 3: all particles at a node and
// the node reach one velocity): bounded for every eta; the monitor (every 10 steps) never stops it,
// total momentum is conserved to 1e-12 of the initial momentum and fluid mass to 1e-12 over 2000
// steps.
// Expectation with the pairwise rule (eq. 14 per particle, which over-corrects when several
// particles share a node): at eta = 8 each node is pulled 8 times toward each particle and the
// exchange overshoots by a growing factor each step (measured: bounded at eta = 2, diverging from
// eta = 3; scene_warnings warns once a node's sum Z / rho0 + Z / M reaches 2). The monitor, checking every
// step, stops the run cleanly at step 1 with "Mach number 0.52 (limit 0.5) at node ...", before any
// value is non-finite; checking every 5 steps it stops at step 5 on a negative density instead
// (the divergence is that fast), still before any NaN.
#include <cmath>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr double kSpeed = 0.05;

scene::Scene suspension(int eta, coupling::ExchangeRule rule) {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 16;
  s.exchange = rule;
  solid::BodySpec sheet;
  sheet.name = "suspension";
  sheet.spacing = 1 / std::sqrt(static_cast<double>(eta));
  const int side = static_cast<int>(std::lround(6 / sheet.spacing));
  sheet.size = {side, side, 1};
  sheet.centre = {8.25, 8.25, 0};  // off the node grid: no particle sits exactly between two nodes
  sheet.velocity = {kSpeed, 0, 0};
  s.bodies.push_back(sheet);
  s.monitor.interval = 10;
  return s;
}

class DenseSuspension : public ::testing::TestWithParam<int> {};

TEST_P(DenseSuspension, CommonVelocityStaysBoundedAndConserves) {
  const int eta = GetParam();
  auto sim = scene::build_simulation(suspension(eta, coupling::ExchangeRule::kCommonVelocity));
  const auto t0 = sim->totals();
  const double p0 = norm(t0.momentum());
  const auto stop = run_watched(*sim, 2000);
  ASSERT_FALSE(stop) << stop->what;
  ASSERT_EQ(non_finite_or_negative(*sim), "");
  const auto t = sim->totals();
  const double momentum_error = norm(difference(t.momentum(), t0.momentum())) / p0;
  const double mass_error = std::abs(t.fluid_mass - t0.fluid_mass) / t0.fluid_mass;
  const std::string name = "eta " + std::to_string(eta) + " (" + std::to_string(sim->solid()->particle_count()) +
                           " particles, mass ratio " +
                           std::to_string(scene::body_mass_ratio(sim->scene(), 0)).substr(0, 5) + ")";
  report(name + ": momentum drift (relative)", momentum_error, 1e-12);
  report(name + ": fluid mass drift (relative)", mass_error, 1e-12);
  EXPECT_LT(momentum_error, 1e-12);
  EXPECT_LT(mass_error, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(ParticlesPerNode, DenseSuspension, ::testing::Values(1, 2, 4, 8));

TEST(DenseSuspension, PairwiseAtEightPerNodeIsStoppedCleanly) {
  const auto warnings = scene::scene_warnings(suspension(8, coupling::ExchangeRule::kPairwise));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("exchange: pairwise with 9 particles at one node over-corrects", 0), 0u) << warnings[0];
  EXPECT_TRUE(scene::scene_warnings(suspension(8, coupling::ExchangeRule::kCommonVelocity)).empty());
  for (int interval : {1, 5}) {
    scene::Scene s = suspension(8, coupling::ExchangeRule::kPairwise);
    s.monitor.interval = interval;
    auto sim = scene::build_simulation(s);
    const auto stop = run_watched(*sim, 500);
    ASSERT_TRUE(stop) << "the pairwise exchange at 8 particles per node stayed bounded";
    std::printf("[ figure   ] pairwise, eta 8, checked every %d: %s\n", interval, stop->what.c_str());
    expect_clean_stop(*sim, *stop);
    EXPECT_EQ(stop->step, interval);
    if (interval == 1) {
      EXPECT_EQ(stop->message.rfind("Mach number 0.5", 0), 0u) << stop->what;
      EXPECT_NE(stop->message.find("(limit 0.5) at node ("), std::string::npos) << stop->what;
    } else {
      EXPECT_EQ(stop->message.rfind("density -", 0), 0u) << stop->what;
      EXPECT_NE(stop->message.find("(must stay positive) at node ("), std::string::npos) << stop->what;
    }
    EXPECT_EQ(non_finite_or_negative(*sim).rfind("non-finite", 0), std::string::npos);
  }
}

}  // namespace
}  // namespace lbsolid::hard_cases
