// Hard cases for rotating bodies (issue 16), each either bounded with its figures or stopped
// cleanly by the monitor, and measured:
// - Dense rotating chains: 12 chains of 8 particles at spacing 1/2 and 1/3 (2 and 3 particles a
//   node along each chain), all with rotation: true, spinning at 0.02 rad a step and drifting at
//   0.01 through a 24 x 24 periodic D2Q9 box at rest, omega 1, monitor every 10 steps, 3000 steps.
//   Expectation: bounded; total momentum to 1e-12 of its size, fluid mass to 1e-12; the chains'
//   spin handed to the fluid (each keeps under 1% of its angular momentum). Measured: bounded at
//   both spacings, momentum 1.5e-13, mass 0, at most 3.2e-6 of a chain's spin left.
// - A rotating disk (radius 4) spinning at 0.01 rad a step in a 24 x 24 box at solid-to-fluid
//   mass ratios per node 0.01 to 100 (through rho0, as in mass_ratio_test.cpp), 3000 steps.
//   Expectation: bounded, momentum and mass to 1e-12, and the torque the fluid exerts accounts for
//   the disk's loss of spin (scene/stages/torque_record.h). Measured: to 4e-8 of what it lost at
//   ratio 0.01, 1.8e-7 at 0.1, 9.4e-6 at 1, 4.6e-5 at 10 and 2.1e-4 at 100. The torque is taken
//   at each step's start while the spin changes across the step; the difference grows with how
//   long the disk keeps spinning (at ratio 100 it still has 6% of its spin after 3000 steps, at
//   0.01 none after a few steps), which points at the step's second-order terms; not isolated
//   further. Bound 1e-3.
#include <cmath>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

scene::Scene dense_rotating_chains(double spacing) {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 24;
  s.monitor.interval = 10;
  for (int k = 0; k < 12; ++k) {
    solid::BodySpec chain;
    chain.name = "chain" + std::to_string(k);
    chain.shape = solid::BodyShape::kChain;
    chain.length = 8;
    chain.spacing = spacing;
    chain.axis = k % 2;
    chain.centre = {3.1 + 6 * (k % 4), 4.1 + 8 * (k / 4), 0};
    chain.velocity = {0.01, 0.005 * (k % 3 - 1), 0};
    chain.angular_velocity = {0, 0, k % 2 ? 0.02 : -0.02};
    chain.rotation = true;
    s.bodies.push_back(chain);
  }
  return s;
}

class DenseRotatingChains : public ::testing::TestWithParam<double> {};

TEST_P(DenseRotatingChains, StayBoundedAndHandTheirSpinToTheFluid) {
  const double spacing = GetParam();
  const scene::Scene s = dense_rotating_chains(spacing);
  ASSERT_TRUE(scene::validate_scene(s).empty());
  auto sim = scene::build_simulation(s);
  const auto t0 = sim->totals();
  std::vector<double> spin0;
  for (int b = 0; b < sim->solid()->body_count(); ++b) spin0.push_back(sim->body_state(b).angular_momentum[2]);
  const auto stop = run_watched(*sim, 3000);
  const std::string name = "chains at spacing " + std::to_string(spacing).substr(0, 4);
  if (report_stop(*sim, stop, name)) return;
  expect_bounded_and_conserved(*sim, t0, name);
  double spin_left = 0;
  for (int b = 0; b < sim->solid()->body_count(); ++b)
    spin_left = std::max(spin_left, std::abs(sim->body_state(b).angular_momentum[2] / spin0[b]));
  report(name + ": largest spin left in a chain (of its start)", spin_left, 0.01);
  EXPECT_LT(spin_left, 0.01);
}

INSTANTIATE_TEST_SUITE_P(ParticlesPerNode, DenseRotatingChains, ::testing::Values(0.5, 1.0 / 3));

scene::Scene spinning_disk(double mass_ratio) {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 24;
  s.monitor.interval = 50;
  solid::BodySpec disk;
  disk.name = "disk";
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 4;
  disk.centre = {12, 12, 0};
  disk.velocity = {0.005, 0, 0};
  disk.angular_velocity = {0, 0, 0.01};
  disk.rotation = true;
  s.bodies.push_back(disk);
  s.fluid.rho0 = scene::body_mass_ratio(s, 0) / mass_ratio;
  return s;
}

class RotatingMassRatio : public ::testing::TestWithParam<double> {};

TEST_P(RotatingMassRatio, StaysBoundedAndTheTorqueAccountsForTheSpin) {
  const double ratio = GetParam();
  auto sim = scene::build_simulation(spinning_disk(ratio));
  const auto t0 = sim->totals();
  const double spin0 = sim->body_state(0).angular_momentum[2];
  double impulse = 0;
  std::optional<Stop> stop;
  for (int step = 0; step < 3000 && !stop; ++step) {
    stop = run_watched(*sim, 1);
    if (!stop) impulse += sim->body_state(0).torque[2];
  }
  const std::string name = "rotating disk, mass ratio " + std::to_string(ratio).substr(0, 5);
  if (report_stop(*sim, stop, name)) return;
  expect_bounded_and_conserved(*sim, t0, name);
  const double lost = sim->body_state(0).angular_momentum[2] - spin0;
  const double torque_off = std::abs(impulse - lost) / std::abs(lost);
  std::printf("[ figure   ] %s: spin left %.3g of its start\n", name.c_str(), 1 + lost / spin0);
  report(name + ": summed torque against the spin lost (relative)", torque_off, 1e-3);
  EXPECT_LT(torque_off, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Ratios, RotatingMassRatio, ::testing::Values(0.01, 0.1, 1.0, 10.0, 100.0));

}  // namespace
}  // namespace lbsolid::hard_cases
