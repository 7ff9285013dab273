#pragma once
// Shared by the hard cases: run a scene under its stability monitor and tell apart the two
// outcomes a hard case may have (bounded to the end, or stopped cleanly by the monitor), and the
// figures every case checks (mass, momentum, finiteness of what is left).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "fluid/fluid_test_support.h"
#include "observe/stability.h"
#include "scene/simulation.h"

namespace lbsolid::hard_cases {

using testing::report;

struct Stop {
  long step = 0;
  std::string message;  // the monitor's message, without "step N: "
  std::string what;     // the full what()
};

// Runs `steps` steps (the scene's monitor watching); the monitor's stop if it stopped the run.
inline std::optional<Stop> run_watched(scene::Simulation& sim, long steps) {
  try {
    for (long s = 0; s < steps; ++s) sim.step();
  } catch (const scene::InstabilityError& e) {
    return Stop{e.step(), e.message(), e.what()};
  }
  return std::nullopt;
}

// What a clean stop leaves: the step it names is the simulation's step count, and every value the
// monitor reads is still finite (no NaN was carried into the state) unless the message says which
// one was not.
inline void expect_clean_stop(const scene::Simulation& sim, const Stop& stop) {
  EXPECT_EQ(stop.step, sim.step_count());
  EXPECT_EQ(stop.what, "step " + std::to_string(stop.step) + ": " + stop.message);
  EXPECT_EQ(stop.message, observe::find_instability(sim, sim.scene().monitor.limits));
}

// Every value finite and every density positive: the monitor with limits that cannot trip otherwise.
inline std::string non_finite_or_negative(const scene::Simulation& sim) {
  observe::StabilityLimits loose;
  loose.max_mach = INFINITY;
  loose.min_density = 0;
  loose.max_density = INFINITY;
  return observe::find_instability(sim, loose);
}

inline double norm(const scene::Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

inline scene::Vec3 difference(const scene::Vec3& a, const scene::Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

// A run the monitor stopped: prints the stop (one outcome a hard case may have) and checks that it
// is clean. Returns whether it stopped.
inline bool report_stop(const scene::Simulation& sim, const std::optional<Stop>& stop, const std::string& name) {
  if (!stop) return false;
  std::printf("[ figure   ] %s: stopped: %s\n", name.c_str(), stop->what.c_str());
  expect_clean_stop(sim, *stop);
  return true;
}

// What a bounded run keeps: every value finite, and the total momentum (relative to its size) and
// the fluid's mass to 1e-12 of their start (round-off over thousands of steps).
inline void expect_bounded_and_conserved(const scene::Simulation& sim, const scene::Totals& start,
                                         const std::string& name) {
  EXPECT_EQ(non_finite_or_negative(sim), "");
  const auto now = sim.totals();
  const double momentum = norm(difference(now.momentum(), start.momentum())) / norm(start.momentum());
  const double mass = std::abs(now.fluid_mass - start.fluid_mass) / start.fluid_mass;
  report(name + ": momentum drift (relative)", momentum, 1e-12);
  report(name + ": fluid mass drift (relative)", mass, 1e-12);
  EXPECT_LT(momentum, 1e-12);
  EXPECT_LT(mass, 1e-12);
}

}  // namespace lbsolid::hard_cases
