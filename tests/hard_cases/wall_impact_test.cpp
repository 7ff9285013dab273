// Hard case: a solid hitting a wall at speed 0.3 (Mach 0.52 on D2Q9). A 4 x 4 sheet in a 32 x 24
// D2Q9 channel (omega = 1, bounce-back walls at y = -1/2 and 23.5, periodic in x) starts with its
// lowest row 1 node above the y_low wall, moving straight at it at 0.3. The fluid is light
// (solid-to-fluid mass ratio per node 10, rho0 = 0.15) so the sheet still meets the wall at about
// 0.25; at ratio 1.5 (rho0 = 1) the fluid would have stopped it before the wall.
// Expectation: validation warns about the initial Mach number. The monitor runs every step with
// max Mach 0.6 (the sheet enters at Mach 0.52 and drags the nodes it covers along) and never stops
// the run over 400 steps; every value stays finite and the fluid mass is conserved to 1e-12.
//   - e = 1: no particle ever reaches the wall (the model stops an elastic particle exactly), and
//     the sheet rebounds (largest v_y afterwards above 0.05);
//   - e = 0: the sheet is stopped: its rebound (largest v_y, driven only by the fluid it
//     compressed) stays below 0.7 of the elastic one.
//   - A heavy sheet (mass ratio 100, rho0 = 0.015) compresses the light fluid it pins against
//     the wall beyond twice rho0 within a few steps: the monitor stops it cleanly with
//     "density <v> outside [0.0075, 0.03] at node (x, 0, 0)", every value still finite.
// Known limitation (reported, not asserted): with e < 1 the contact force (solid/wall_contact.cpp)
// halves a crossing particle's step instead of stopping it at the wall, so a particle can end past
// the wall; the e = 0 run prints how far.
#include <algorithm>

#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr double kSpeed = 0.3;
constexpr double kWall = -0.5;

scene::Scene falling_sheet(double restitution, double mass_ratio) {
  scene::Scene s;
  s.fluid.nx = 32;
  s.fluid.ny = 24;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  s.contact.restitution = restitution;
  solid::BodySpec sheet;
  sheet.name = "sheet";
  sheet.size = {4, 4, 1};
  sheet.centre = {16, 2.0, 0};  // rows at y = 0.5 ... 3.5: the lowest 1 node above the wall
  sheet.velocity = {0, -kSpeed, 0};
  s.bodies.push_back(sheet);
  s.fluid.rho0 = scene::body_mass_ratio(s, 0) / mass_ratio;
  s.monitor.interval = 1;
  s.monitor.limits.max_mach = 0.6;
  return s;
}

struct Impact {
  std::optional<Stop> stop;
  double lowest_y = INFINITY;  // lowest particle position over the run
  double impact_speed = 0;     // |v_y| of the sheet when its lowest row first comes within 1/2 of the wall
  double rebound = 0;          // largest v_y over the run
  double mass_error = 0;
  std::string left;            // non_finite_or_negative() at the end
};

Impact drop(double restitution, double mass_ratio) {
  auto sim = scene::build_simulation(falling_sheet(restitution, mass_ratio));
  const double mass0 = sim->totals().fluid_mass;
  Impact impact;
  for (long step = 0; step < 400 && !impact.stop; ++step) {
    impact.stop = run_watched(*sim, 1);
    const auto* solid = sim->solid();
    for (int p = 0; p < solid->particle_count(); ++p) impact.lowest_y = std::min(impact.lowest_y, solid->position(p)[1]);
    const double vy = sim->body_state(0).velocity[1];
    if (impact.impact_speed == 0 && impact.lowest_y < kWall + 0.5) impact.impact_speed = -vy;
    impact.rebound = std::max(impact.rebound, vy);
  }
  if (impact.stop) expect_clean_stop(*sim, *impact.stop);
  impact.left = non_finite_or_negative(*sim);
  impact.mass_error = std::abs(sim->totals().fluid_mass - mass0) / mass0;
  return impact;
}

TEST(WallImpact, WarnsAboutTheInitialMachNumber) {
  const auto warnings = scene::scene_warnings(falling_sheet(1, 10));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "bodies[0].velocity: initial Mach number 0.52 is above 0.1");
}

TEST(WallImpact, ElasticAndInelasticAtSpeedPointThree) {
  const Impact elastic = drop(1, 10), inelastic = drop(0, 10);
  for (const auto* run : {&elastic, &inelastic}) {
    const std::string name = run == &elastic ? "e = 1" : "e = 0";
    std::printf("[ figure   ] %s: impact speed %.3f, rebound %.4f, lowest particle y = %.4f (wall at -0.5)\n",
                name.c_str(), run->impact_speed, run->rebound, run->lowest_y);
    report(name + ": fluid mass drift (relative)", run->mass_error, 1e-12);
    EXPECT_FALSE(run->stop) << run->stop->what;
    EXPECT_EQ(run->left, "");
    EXPECT_LT(run->mass_error, 1e-12);
    EXPECT_GT(run->impact_speed, 0.2);
  }
  EXPECT_GT(elastic.lowest_y, kWall);
  EXPECT_GT(elastic.rebound, 0.05);
  EXPECT_LT(inelastic.rebound, 0.7 * elastic.rebound);
}

TEST(WallImpact, HeavySheetIsStoppedByTheDensityBand) {
  for (double e : {1.0, 0.0}) {
    const Impact heavy = drop(e, 100);
    ASSERT_TRUE(heavy.stop) << "e = " << e << ": the heavy sheet's impact stayed inside the density band";
    std::printf("[ figure   ] heavy sheet, e = %.0f: %s\n", e, heavy.stop->what.c_str());
    EXPECT_EQ(heavy.stop->message.rfind("density 0.0", 0), 0u) << heavy.stop->what;
    EXPECT_NE(heavy.stop->message.find(" outside [0.0075, 0.03] at node ("), std::string::npos) << heavy.stop->what;
    EXPECT_EQ(heavy.left, "");
  }
}

}  // namespace
}  // namespace lbsolid::hard_cases
