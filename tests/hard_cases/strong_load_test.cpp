// Hard case: a strong load. A disk of 21 particles (radius 2.5) in a 24 x 24 periodic D2Q9 box
// (omega = 1), each particle pulled by 1e-2: the disk alone would gain 5e-3 per step, the box as a
// whole (nothing holds it back) 21e-2 / 616 = 3.4e-4, so the disk runs well ahead of the fluid and
// drags its nodes past Mach 0.3 (|u| = 0.173) in about 250 steps.
// Expectation: the monitor (every 10 steps, max Mach 0.3) stops the run cleanly, at the first
// check after the fastest fluid node passes Mach 0.3, with "step N: Mach number <v> (limit 0.3) at
// node (x, y, 0)", v in (0.3, 0.4): the flow is caught on its way up, not after it blew up. Up to
// the stop, total momentum equals the impulse of the load (N_p F t) to 1e-12 (relative), and
// every value left in the state is finite.
#include "hard_cases/hard_case_support.h"

namespace lbsolid::hard_cases {
namespace {

constexpr double kLoad = 1e-2;

scene::Scene pulled_disk() {
  scene::Scene s;
  s.fluid.nx = s.fluid.ny = 24;
  solid::BodySpec disk;
  disk.name = "disk";
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 2.5;
  disk.centre = {12, 12, 0};
  disk.load = {kLoad, 0, 0};
  s.bodies.push_back(disk);
  s.monitor.interval = 10;
  s.monitor.limits.max_mach = 0.3;
  return s;
}

TEST(StrongLoad, DiskDrivenTowardMachPointThreeIsStoppedByTheMonitor) {
  auto sim = scene::build_simulation(pulled_disk());
  const int particles = sim->solid()->particle_count();
  const auto stop = run_watched(*sim, 1000);
  ASSERT_TRUE(stop) << "the disk never passed Mach 0.3";
  expect_clean_stop(*sim, *stop);
  EXPECT_EQ(stop->message.rfind("Mach number 0.3", 0), 0u) << stop->what;
  EXPECT_NE(stop->message.find("(limit 0.3) at node ("), std::string::npos) << stop->what;
  EXPECT_EQ(non_finite_or_negative(*sim), "");

  const double impulse = particles * kLoad * static_cast<double>(sim->step_count());
  const auto p = sim->totals().momentum();
  const double momentum_error = norm(difference(p, {impulse, 0, 0})) / impulse;
  const double disk_mach = sim->body_state(0).velocity[0] * std::sqrt(3.0);
  std::printf("[ figure   ] stopped: %s (disk at Mach %.3f, %d particles)\n", stop->what.c_str(), disk_mach,
              particles);
  report("momentum vs impulse of the load (relative)", momentum_error, 1e-12);
  EXPECT_LT(momentum_error, 1e-12);
  // The disk drags its nearest nodes almost at its own speed: at the stop it is near Mach 0.3 too.
  EXPECT_GT(disk_mach, 0.3);
  EXPECT_LT(disk_mach, 0.4);
}

}  // namespace
}  // namespace lbsolid::hard_cases
