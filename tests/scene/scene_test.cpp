// Scenes: validation names the field and the reason; the builder assembles only the stages a
// scene declares, and a fluid-only scene is exactly the bare fluid.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "fluid/fluid_test_support.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

Scene channel() {
  Scene s;
  s.lattice = LatticeKind::kD2Q7;
  s.fluid.nx = 20;
  s.fluid.ny = 10;
  s.fluid.sides[fluid::kYLow].kind = s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  return s;
}

solid::BodySpec disk_at(double x, double y) {
  solid::BodySpec d;
  d.shape = solid::BodyShape::kDisk;
  d.radius = 2;
  d.centre = {x, y, 0};
  return d;
}

bool has_error(const std::vector<std::string>& errors, const std::string& start) {
  for (const auto& e : errors)
    if (e.rfind(start, 0) == 0) return true;
  return false;
}

TEST(SceneValidation, EveryErrorNamesItsField) {
  Scene s = channel();
  s.fluid.omega = 2.5;
  s.contact.restitution = 1.5;
  s.bodies.push_back(disk_at(10, 1.0));  // reaches below the y_low wall
  s.bodies.push_back(disk_at(10, 4));
  s.bodies.back().radius = 0.5;
  const auto errors = validate_scene(s);
  for (const auto& e : errors) std::printf("  %s\n", e.c_str());
  EXPECT_TRUE(has_error(errors, "omega: must lie in (0, 2)"));
  EXPECT_TRUE(has_error(errors, "contact.restitution: must lie in [0, 1]"));
  EXPECT_TRUE(has_error(errors, "bodies[0].centre: particle at (10, -1) lies on or beyond the y_low wall (at -0.433"));
  EXPECT_TRUE(has_error(errors, "bodies[1].radius: must be at least 1"));
  EXPECT_EQ(errors.size(), 4u);
  try {
    build_simulation(s);
    FAIL() << "an invalid scene was built";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("omega: must lie in (0, 2)"), std::string::npos);
  }
}

TEST(SceneValidation, BodyNamesAreUniqueDefaultsIncluded) {
  Scene s = channel();
  s.bodies.push_back(disk_at(5, 5));   // goes by "body0"
  s.bodies.push_back(disk_at(14, 5));
  s.bodies.back().name = "body0";      // clashes with the default name of bodies[0]
  const auto errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[1].name: \"body0\" is already the name of bodies[0]");
  s.bodies.back().name = "second";
  EXPECT_TRUE(validate_scene(s).empty());
}

// One error per shared name, with how many bodies share it, found in n log n: 10^5 bodies of one
// name (99,999 duplicates) give one error, not 99,999 (nor minutes of pairwise comparison).
TEST(SceneValidation, SharedNamesAreReportedOncePerNameWithACount) {
  Scene s = channel();
  s.with_fluid = false;
  for (const char* name : {"a", "b", "a", "c", "b", "a"}) {
    s.bodies.push_back(disk_at(10, 4.5));
    s.bodies.back().name = name;
  }
  EXPECT_EQ(validate_scene(s), (std::vector<std::string>{
                                   "bodies[2].name: \"a\" is already the name of bodies[0] (3 bodies share this "
                                   "name; the last is bodies[5])",
                                   "bodies[4].name: \"b\" is already the name of bodies[1]",
                               }));
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = 2;
  chain.centre = {10, 4.5, 0};
  chain.name = "same";
  s.bodies.assign(100000, chain);
  EXPECT_EQ(validate_scene(s), std::vector<std::string>{"bodies[1].name: \"same\" is already the name of bodies[0] "
                                                        "(100000 bodies share this name; the last is bodies[99999])"});
}

// A message echoes at most 64 bytes of a name, cut between characters, so 20 of them stay short.
TEST(SceneValidation, MessagesEchoAtMost64BytesOfAName) {
  Scene s = channel();
  s.bodies.push_back(disk_at(5, 4.5));
  s.bodies.push_back(disk_at(14, 4.5));
  // 63 ASCII bytes and a 2-byte character across byte 64: the cut falls before that character.
  const std::string name = std::string(63, 'n') + "\xc3\xa9" + std::string(200, 'x');
  s.bodies[0].name = s.bodies[1].name = name;
  EXPECT_EQ(validate_scene(s), std::vector<std::string>{"bodies[1].name: \"" + std::string(63, 'n') +
                                                        "...\" is already the name of bodies[0]"});
}

// A finite spacing times a long extent overflows to infinite positions (which the nearest-node
// search and the solid cannot place); validation says so on the spacing.
TEST(SceneValidation, SpacingThatOverflowsPositionsIsRefused) {
  Scene s;
  s.fluid.nx = s.fluid.ny = 8;  // periodic: no wall to catch the particles first
  s.exchange = coupling::ExchangeRule::kPairwise;  // whose warning finds each particle's node
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = 1000;
  chain.spacing = 1e307;
  chain.centre = {4, 4, 0};
  s.bodies.push_back(chain);
  EXPECT_EQ(validate_scene(s), std::vector<std::string>{"bodies[0].spacing: 1e+307 times the body's extent puts "
                                                        "particles at non-finite positions"});
  s.bodies[0].spacing = 1e300;  // far away but finite: valid in a periodic box, and the warning is defined
  EXPECT_TRUE(validate_scene(s).empty());
  EXPECT_NO_THROW(scene_warnings(s));
}

TEST(SceneValidation, SceneWithoutFluidNeedsABodyAndNoBodyForce) {
  Scene s = channel();
  s.with_fluid = false;
  s.fluid.body_force = {1e-5, 0, 0};
  const auto errors = validate_scene(s);
  EXPECT_TRUE(has_error(errors, "body_force: is set but the scene has no fluid"));
  EXPECT_TRUE(has_error(errors, "bodies: a scene without fluid needs at least one body"));
}

TEST(SceneValidation, ThreeDimensionalBodies) {
  Scene s;
  s.lattice = LatticeKind::kD3Q19;
  s.fluid.nx = s.fluid.ny = s.fluid.nz = 8;
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = 4;
  chain.axis = 2;
  chain.centre = {4, 4, 4};
  s.bodies.push_back(chain);
  EXPECT_TRUE(validate_scene(s).empty());
  s.lattice = LatticeKind::kD2Q9;
  s.fluid.nz = 1;
  chain.centre[2] = 0;
  s.bodies[0] = chain;
  EXPECT_TRUE(has_error(validate_scene(s), "bodies[0].axis: must be 0 (x), 1 (y)"));
}

TEST(SimulationBuilder, HoldsOnlyTheStagesTheSceneNeeds) {
  Scene fluid_only = channel();
  auto a = build_simulation(fluid_only);
  EXPECT_EQ(a->stages(), std::vector<std::string>{"fluid"});
  EXPECT_EQ(a->solid_bytes(), 0u);
  EXPECT_EQ(a->solid(), nullptr);

  Scene coupled = channel();
  coupled.bodies.push_back(disk_at(10, 4.5));
  auto b = build_simulation(coupled);
  EXPECT_EQ(b->stages(), (std::vector<std::string>{"exchange", "fluid", "contact", "solid"}));
  coupled.bodies[0].load = {1e-4, 0, 0};
  coupled.contact.enabled = false;
  EXPECT_EQ(build_simulation(coupled)->stages(), (std::vector<std::string>{"exchange", "fluid", "loads", "solid"}));

  Scene periodic = coupled;  // no walls: no contact stage even when contact is enabled
  periodic.contact.enabled = true;
  periodic.fluid.sides[fluid::kYLow].kind = periodic.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kPeriodic;
  EXPECT_EQ(build_simulation(periodic)->stages(), (std::vector<std::string>{"exchange", "fluid", "loads", "solid"}));

  Scene solid_only = coupled;
  solid_only.with_fluid = false;
  auto c = build_simulation(solid_only);
  EXPECT_EQ(c->stages(), (std::vector<std::string>{"loads", "solid"}));
  EXPECT_EQ(c->fluid_bytes(), 0u);
  EXPECT_GT(c->solid_bytes(), 0u);
  EXPECT_THROW(c->velocity_profile(), std::logic_error);
}

// The builder adds nothing to a fluid-only scene: it steps exactly as the bare fluid does.
TEST(SimulationBuilder, FluidOnlySceneEqualsBareFluidBitForBit) {
  Scene s = channel();
  s.fluid.body_force = {1e-5, 0, 0};
  auto sim = build_simulation(s);
  fluid::FluidLattice<lattice::D2Q7, double> bare(s.fluid);
  sim->run(101);
  bare.run(101);
  const auto profile = sim->velocity_profile();
  for (int y = 0; y < s.fluid.ny; ++y) {
    double mean = 0;
    for (int x = 0; x < s.fluid.nx; ++x) mean += bare.velocity(x, y)[0];
    EXPECT_EQ(profile[y], mean / s.fluid.nx) << "row " << y;
    for (int x = 0; x < s.fluid.nx; ++x) {
      const auto m = sim->fluid_moments(x, y);
      EXPECT_EQ(m.rho, bare.density(x, y));
    }
  }
}

// Observers on a state known exactly: a body moving rigidly through fluid at rest at t = 0.
TEST(SimulationObservers, ReadTheStateTheyDescribe) {
  Scene s = channel();
  s.fluid.rho0 = 1.3;
  s.bodies.push_back(disk_at(10, 4.5));
  s.bodies[0].velocity = {0.02, -0.01, 0};
  s.bodies.push_back(disk_at(4, 4.5));  // at rest: it has no slip to normalise, so only body 0 is read
  auto sim = build_simulation(s);
  const BodyState state = sim->body_state(0);
  EXPECT_NEAR(state.centre_of_mass[0], 10, 1e-14);
  EXPECT_NEAR(state.centre_of_mass[1], 4.5, 1e-14);
  EXPECT_NEAR(state.velocity[0], 0.02, 1e-16);
  EXPECT_NEAR(state.velocity[1], -0.01, 1e-16);
  // Sum of K/2 over the 13 particles with |l| <= 2: 4 tips (1 link), 4 diagonals (2), 5 others (4).
  EXPECT_EQ(state.mass, 0.5 * (4 * 1 + 4 * 2 + 5 * 4));
  EXPECT_NEAR(sim->body_slip(0), 1.0, 1e-15);               // the fluid is at rest: |u_s - 0| / |u_s|
  const Totals t = sim->totals();
  EXPECT_NEAR(t.fluid_mass, 1.3 * 20 * 10, 1e-11);
  EXPECT_NEAR(t.fluid_kinetic_energy, 0.0, 1e-30);
  EXPECT_NEAR(t.solid_momentum[0], state.mass * 0.02, 1e-16);
  // E = sum |f|^2 with f = v/2 on each incoming link: M |v|^2 / 2 for a rigid motion.
  EXPECT_NEAR(t.solid_energy, 0.5 * state.mass * (0.02 * 0.02 + 0.01 * 0.01), 1e-17);
  EXPECT_THROW(sim->body_state(2), std::out_of_range);
  for (double u : sim->velocity_profile()) EXPECT_EQ(u, 0.0);
}

// The fluid's footprint is fixed when it is built: a session reports it while a worker steps the
// simulation, so a coupled step (whose exchange counts the nodes of each row) must not grow it.
TEST(SimulationObservers, FluidBytesDoNotChangeWhenTheSimulationSteps) {
  Scene s = channel();
  s.bodies.push_back(disk_at(10, 4.5));
  auto sim = build_simulation(s);
  const std::size_t built = sim->fluid_bytes();
  for (int k = 0; k < 3; ++k) {
    sim->step();
    EXPECT_EQ(sim->fluid_bytes(), built) << "after step " << k + 1;
  }
}

// particle_velocity reads the solid: without one, or for a particle it does not hold, it throws
// rather than reading through a null pointer or past the end of the arrays.
TEST(SimulationObservers, ParticleVelocityChecksItsArgument) {
  const auto fluid_only = build_simulation(channel());
  try {
    fluid_only->particle_velocity(0);
    FAIL() << "no exception without bodies";
  } catch (const std::logic_error& e) {
    EXPECT_EQ(std::string(e.what()), "particle_velocity: the scene has no bodies");
  }
  Scene s = channel();
  s.bodies.push_back(disk_at(10, 4.5));  // 13 particles
  s.bodies[0].velocity = {0.02, 0, 0};
  const auto sim = build_simulation(s);
  EXPECT_NEAR(sim->particle_velocity(12)[0], 0.02, 1e-16);
  for (int p : {-1, 13, std::numeric_limits<int>::max(), std::numeric_limits<int>::min()}) {
    try {
      sim->particle_velocity(p);
      FAIL() << "no exception for particle " << p;
    } catch (const std::out_of_range& e) {
      EXPECT_EQ(std::string(e.what()),
                "particle_velocity: no particle " + std::to_string(p) + " (the scene has 13)");
    }
  }
}

TEST(SceneValidation, MonitorLimitsAndSpeedsThatCannotBeStable) {
  Scene s = channel();
  s.monitor.interval = -1;
  s.monitor.limits.max_mach = 0;
  s.monitor.limits.min_density = 1.2;
  s.monitor.limits.max_density = 0.9;
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {0.6, 0, 0};  // Mach 1.2 on D2Q7 (c_s = 1/2)
  s.bodies.push_back(disk_at(10, 4));
  s.bodies.back().velocity = {0, 0.5, 0};  // Mach 1
  const auto errors = validate_scene(s);
  for (const auto& e : errors) std::printf("  %s\n", e.c_str());
  EXPECT_TRUE(has_error(errors, "monitor.interval: must be 0 (off) or a number of steps, got -1"));
  EXPECT_TRUE(has_error(errors, "monitor.max_mach: must be positive, got 0"));
  EXPECT_TRUE(has_error(errors, "monitor.min_density: must lie in [0, 1) (a fraction of rho0), got 1.2"));
  EXPECT_TRUE(has_error(errors, "monitor.max_density: must be above 1"));
  EXPECT_TRUE(has_error(errors, "sides.y_high.wall_velocity: Mach number 1.2 must stay below 1"));
  EXPECT_TRUE(has_error(errors, "bodies[0].velocity: initial Mach number 1 must stay below 1"));
  EXPECT_EQ(errors.size(), 6u);
  s.monitor.limits.max_mach = NAN;
  EXPECT_TRUE(has_error(validate_scene(s), "monitor.max_mach: must be positive, got nan"));
}

TEST(SceneWarnings, NameTheQuantityNearTheEdge) {
  Scene s = channel();
  s.bodies.push_back(disk_at(10, 4));
  EXPECT_TRUE(scene_warnings(s).empty());
  s.fluid.omega = 1.97;
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {0.06, 0, 0};  // Mach 0.12 on D2Q7
  s.bodies[0].velocity = {0.06, 0, 0};
  ASSERT_TRUE(validate_scene(s).empty());
  const auto warnings = scene_warnings(s);
  ASSERT_EQ(warnings.size(), 3u);
  EXPECT_EQ(warnings[0], "omega: 1.97 is above 1.95; the fluid is close to its stability limit");
  EXPECT_EQ(warnings[1], "sides.y_high.wall_velocity: Mach number 0.12 is above 0.1");
  EXPECT_EQ(warnings[2], "bodies[0].velocity: initial Mach number 0.12 is above 0.1");
  s.with_fluid = false;  // without a fluid there is no speed of sound to compare with
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {0, 0, 0};
  EXPECT_TRUE(scene_warnings(s).empty());
}

// A spin is a speed too: the disk of radius 2 has particles 2 spacings from its centre, so a spin
// of 0.5 moves them at 1, Mach 2 on D2Q7 (c_s = 1/2), and 0.03 at Mach 0.12.
TEST(SceneValidation, ASpinWhoseRimPassesTheSpeedOfSoundIsRefused) {
  Scene s = channel();
  s.bodies.push_back(disk_at(10, 5));
  s.bodies.back().angular_velocity = {0, 0, 0.5};
  s.bodies.back().rotation = true;
  const auto errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].angular_velocity: the fastest particle's initial Mach number 2 must stay below 1");
  s.bodies.back().angular_velocity = {0, 0, -0.03};
  ASSERT_TRUE(validate_scene(s).empty());
  const auto warnings = scene_warnings(s);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "bodies[0].angular_velocity: the fastest particle's initial Mach number 0.12 is above 0.1");
}

TEST(SceneWarnings, MassRatioPerNode) {
  Scene s;
  s.fluid.nx = s.fluid.ny = 16;
  solid::BodySpec sheet;
  sheet.size = {4, 4, 1};
  sheet.centre = {8, 8, 0};
  s.bodies.push_back(sheet);
  EXPECT_DOUBLE_EQ(body_mass_ratio(s, 0), 24.0 / 16.0);  // sum K/2 = 24 over 16 nodes
  s.fluid.rho0 = 0.015;
  EXPECT_DOUBLE_EQ(body_mass_ratio(s, 0), 100.0);
  s.bodies[0].spacing = 0.5;  // four particles per node: x, y = 7.5, 8, 8.5, 9 -> nodes 8, 9
  s.bodies[0].centre = {8.25, 8.25, 0};
  s.fluid.rho0 = 1;
  EXPECT_DOUBLE_EQ(body_mass_ratio(s, 0), 24.0 / 4.0);
}

TEST(SimulationMonitor, StopsAtTheCheckWithStepAndMessageAndLeavesTheStateReadable) {
  // A periodic box under a uniform force: u = F t, Mach 0.5 after 289 steps at F = 1e-3.
  Scene s;
  s.fluid.nx = s.fluid.ny = 8;
  s.fluid.body_force = {1e-3, 0, 0};
  s.monitor.interval = 25;
  auto sim = build_simulation(s);
  try {
    sim->run(1000);
    FAIL() << "the monitor did not stop the run";
  } catch (const InstabilityError& e) {
    EXPECT_EQ(e.step(), 300);
    EXPECT_EQ(sim->step_count(), 300);
    EXPECT_EQ(e.message().rfind("Mach number 0.519", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()), "step 300: " + e.message());
    const std::runtime_error& base = e;  // what callers that know only std::runtime_error see
    EXPECT_EQ(std::string(base.what()).rfind("step 300: Mach number", 0), 0u);
  }
  EXPECT_NEAR(sim->fluid_moments(3, 3).u[0], 300e-3, 1e-9);
  EXPECT_EQ(sim->save_state().step, 300);
  // Off (interval 0), the same run goes on.
  s.monitor.interval = 0;
  auto unwatched = build_simulation(s);
  unwatched->run(400);
  EXPECT_EQ(unwatched->step_count(), 400);
}

}  // namespace
}  // namespace lbsolid::scene
