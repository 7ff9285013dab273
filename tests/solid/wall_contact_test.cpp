// The paper's Fig. 1: a square sheet with an initial momentum bouncing in a closed box, no fluid.
// With restitution e = 1 the total energy (eq. 9) is constant to round-off through every bounce,
// and between contacts the centre of mass moves in a straight line at constant velocity.
#include <gtest/gtest.h>

#include <cmath>

#include "fluid/fluid_test_support.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

using testing::report;

Scene bouncing_sheet(double restitution, int dimension = 2) {
  Scene s;
  s.lattice = dimension == 3 ? LatticeKind::kD3Q19 : LatticeKind::kD2Q9;
  s.with_fluid = false;
  s.fluid.nx = 24;
  s.fluid.ny = 16;
  s.fluid.nz = dimension == 3 ? 12 : 1;
  for (int side = 0; side < 2 * dimension; ++side) s.fluid.sides[side].kind = fluid::WallKind::kBounceBack;
  solid::BodySpec sheet;
  sheet.size = {6, 6, dimension == 3 ? 4 : 1};
  sheet.centre = {8, 6, dimension == 3 ? 6.0 : 0.0};
  sheet.velocity = {0.31, 0.17, dimension == 3 ? 0.11 : 0.0};
  s.bodies.push_back(sheet);
  s.contact.restitution = restitution;
  return s;
}

TEST(WallContact, BouncingSheetConservesEnergyAndMovesStraightBetweenContacts) {
  for (int dimension : {2, 3}) {
    auto sim = build_simulation(bouncing_sheet(1.0, dimension));
    EXPECT_EQ(sim->stages(), (std::vector<std::string>{"contact", "solid"}));
    EXPECT_EQ(sim->fluid_bytes(), 0u);
    const double energy0 = sim->totals().solid_energy;
    double worst_energy = 0, worst_straight = 0;
    int bounces = 0, free_steps = 0;
    BodyState previous = sim->body_state(0), before_previous = previous;
    for (int step = 1; step <= 1500; ++step) {
      sim->step();
      const BodyState now = sim->body_state(0);
      worst_energy = std::max(worst_energy, std::abs(sim->totals().solid_energy - energy0) / energy0);
      for (int a = 0; a < dimension; ++a)
        if (now.velocity[a] * previous.velocity[a] < 0) ++bounces;
      // Momentum unchanged over two steps (up to the round-off of summing it): no contact, so the
      // path must be straight and uniform.
      bool free = step >= 2;
      for (int a = 0; a < 3; ++a)
        free = free && std::abs(now.velocity[a] - previous.velocity[a]) < 1e-14 &&
               std::abs(previous.velocity[a] - before_previous.velocity[a]) < 1e-14;
      if (free) {
        ++free_steps;
        for (int a = 0; a < 3; ++a)
          worst_straight = std::max(worst_straight, std::abs(now.centre_of_mass[a] - 2 * previous.centre_of_mass[a] +
                                                             before_previous.centre_of_mass[a]));
      }
      before_previous = previous;
      previous = now;
    }
    const std::string d = " (" + std::to_string(dimension) + "D)";
    report("relative energy drift over " + std::to_string(bounces) + " bounces" + d, worst_energy, 1e-10);
    report("centre-of-mass curvature between contacts" + d, worst_straight, 1e-12);
    EXPECT_GE(bounces, 5);
    std::printf("  %d of 1500 steps free of contact\n", free_steps);
    EXPECT_GT(free_steps, 300);
    EXPECT_LT(worst_energy, 1e-10);
    EXPECT_LT(worst_straight, 1e-12);
    // Every particle stayed inside the box.
    const auto* solid = sim->solid();
    for (int p = 0; p < solid->particle_count(); ++p)
      for (int a = 0; a < dimension; ++a) {
        EXPECT_GT(solid->position(p)[a], wall_position(sim->scene(), 2 * a));
        EXPECT_LT(solid->position(p)[a], wall_position(sim->scene(), 2 * a + 1));
      }
  }
}

// e = 0 takes the normal kinetic energy out at each contact: the energy only falls.
TEST(WallContact, InelasticContactDissipates) {
  auto sim = build_simulation(bouncing_sheet(0.0));
  double energy = sim->totals().solid_energy;
  const double energy0 = energy;
  for (int step = 0; step < 600; ++step) {
    sim->step();
    const double now = sim->totals().solid_energy;
    EXPECT_LE(now, energy * (1 + 1e-12)) << "step " << step;
    energy = now;
  }
  report("energy left after e = 0 contacts (fraction)", energy / energy0, 0.5);
  EXPECT_LT(energy, 0.5 * energy0);
}

}  // namespace
}  // namespace lbsolid::scene
