// The stability monitor: quiet on a healthy run, and names the quantity and the place when the
// fluid goes faster than the Mach limit or a value stops being finite.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "observe/stability.h"

namespace lbsolid::observe {
namespace {

scene::Scene driven_box(double force) {
  scene::Scene s;
  s.fluid.nx = 8;
  s.fluid.ny = 8;
  s.fluid.body_force = {force, 0, 0};
  return s;
}

// A closed box whose y_high wall moves: it compresses one corner.
scene::Scene pumped_box(int nx, int ny) {
  scene::Scene s = driven_box(0);
  s.fluid.nx = nx;
  s.fluid.ny = ny;
  for (int side = 0; side < 4; ++side) s.fluid.sides[side].kind = fluid::WallKind::kBounceBack;
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {0.1, 0, 0};
  return s;
}

TEST(StabilityMonitor, QuietWhileTheFlowIsSlow) {
  auto sim = scene::build_simulation(driven_box(1e-5));
  sim->run(100);
  EXPECT_EQ(find_instability(*sim, {}), "");
}

TEST(StabilityMonitor, NamesTheMachNumberAndTheNode) {
  // A periodic box under a uniform force accelerates uniformly. It starts at rest in the physical
  // velocity (sum f c + F/2) / rho (the initial populations carry -F/2) and gains exactly F per
  // step (Guo forcing), so after t steps Mach = t F / (rho c_s), the same at every node.
  const double force = 1e-3, cs = 1 / std::sqrt(3.0);
  auto sim = scene::build_simulation(driven_box(force));
  sim->run(200);  // Mach 0.346
  EXPECT_EQ(find_instability(*sim, {0.5}), "");
  sim->run(200);  // Mach 0.693
  const std::string problem = find_instability(*sim, {0.5});
  ASSERT_EQ(problem.rfind("Mach number ", 0), 0u) << problem;
  EXPECT_NE(problem.find(" (limit 0.5) at node (0, 0, 0)"), std::string::npos) << problem;
  // The figure the message shows is the monitor's own Mach number: it must be the analytic one.
  // It is printed to 6 significant digits, so it can differ from t F / c_s by half a unit of the
  // 6th digit (5e-7 at 0.69); the velocity itself is exact to round-off (about 1e-16 x 400 steps),
  // far below that. A monitor reading the bare sum f c / rho would show (t - 1/2) F / c_s, 8.7e-4
  // lower, and fail.
  const double shown = std::stod(problem.substr(std::string("Mach number ").size()));
  const double expected = 400 * force / cs;
  EXPECT_NEAR(shown, expected, 5e-7) << problem;
}

TEST(StabilityMonitor, NamesANonFiniteParticle) {
  scene::Scene s = driven_box(0);
  s.with_fluid = false;
  solid::BodySpec sheet;
  sheet.name = "sheet";
  sheet.size = {2, 2, 1};
  sheet.centre = {4, 4, 0};
  sheet.load = {1e308, 0, 0};  // finite (validation refuses infinite loads), but overflows in a few steps
  s.bodies.push_back(sheet);
  auto sim = scene::build_simulation(s);
  EXPECT_EQ(find_instability(*sim, {}), "");
  sim->run(5);
  EXPECT_EQ(find_instability(*sim, {}).rfind("non-finite", 0), 0u);
  EXPECT_NE(find_instability(*sim, {}).find("of body sheet"), std::string::npos);
}

// The density band is relative to rho0, shown as densities, and names the node furthest out. A
// moving wall pumping a closed box compresses one corner; a band tight enough catches it.
TEST(StabilityMonitor, NamesADensityOutsideTheBand) {
  scene::Scene s = pumped_box(8, 8);
  s.fluid.rho0 = 2.0;
  auto sim = scene::build_simulation(s);
  sim->run(50);
  EXPECT_EQ(find_instability(*sim, {}), "");  // default band [1, 4] at rho0 = 2
  StabilityLimits tight;
  tight.min_density = 0.999;
  tight.max_density = 1.001;
  const std::string problem = find_instability(*sim, tight);
  EXPECT_EQ(problem.rfind("density ", 0), 0u) << problem;
  EXPECT_NE(problem.find(" outside [1.998, 2.002] at node ("), std::string::npos) << problem;
}

// The monitor scans the fluid in parts on the session's threads; its answer must be the one scan
// in node order gives, ties included: a uniform Mach number (every node ties, the first is named),
// a density band (the node furthest out), two non-finite nodes in different parts (the first).
TEST(StabilityMonitor, ThePartsDoNotChangeTheAnswer) {
  parallel::ThreadPool pool(3);
  const auto same_in_parts = [&](const scene::Simulation& sim, const StabilityLimits& limits) {
    const std::string one = find_instability(sim, limits);
    EXPECT_FALSE(one.empty());  // each case below has a problem to find
    for (int parts : {2, 3, 7, 100}) EXPECT_EQ(find_instability(sim, limits, &pool, parts), one) << parts << " parts";
    return one;
  };
  auto driven = scene::build_simulation(driven_box(1e-3));
  driven->run(400);  // Mach 0.693 at every node
  EXPECT_NE(same_in_parts(*driven, {0.5}).find("at node (0, 0, 0)"), std::string::npos);

  auto pumped = scene::build_simulation(pumped_box(24, 16));
  pumped->run(50);
  StabilityLimits tight;
  tight.min_density = 0.999;
  tight.max_density = 1.001;
  EXPECT_EQ(same_in_parts(*pumped, tight).rfind("density ", 0), 0u);

  scene::SimulationState state = pumped->save_state();
  const long cells = 24 * 16;
  state.fluid.populations[cells + 300] = std::nan("");  // population 1 of node 300 = (12, 12, 0)
  state.fluid.populations[2 * cells + 100] = std::nan("");  // population 2 of node 100 = (4, 4, 0)
  pumped->load_state(state);
  EXPECT_EQ(same_in_parts(*pumped, {}).rfind("non-finite ", 0), 0u);
}

TEST(StabilityMonitor, DefaultsAndDisabledBand) {
  const StabilityLimits limits;
  EXPECT_EQ(limits.max_mach, 0.5);
  EXPECT_EQ(limits.min_density, 0.5);
  EXPECT_EQ(limits.max_density, 2.0);
  // The daemon's form of construction still sets the Mach limit first.
  const StabilityLimits mach_only{0.3};
  EXPECT_EQ(mach_only.max_mach, 0.3);
  EXPECT_EQ(mach_only.min_density, 0.5);
}

}  // namespace
}  // namespace lbsolid::observe
