#pragma once
// A run's cost as the accuracy report records it: wall time from the build to the last
// measurement, steps, fluid cell updates per second, the simulation's memory and the process's
// peak resident set.
#include <sys/resource.h>

#include <chrono>

#include "accuracy/accuracy_problems.h"
#include "scene/simulation.h"

namespace lbsolid::accuracy {

inline long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024L;  // Linux reports kilobytes
}

class RunClock {
 public:
  RunClock() : start_(std::chrono::steady_clock::now()) {}
  void finish(const scene::Simulation& sim, RunResult& r) const {
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    r.steps = sim.step_count();
    const auto& c = sim.scene().fluid;
    const double cells = static_cast<double>(c.nx) * c.ny * c.nz;
    r.mlups = r.wall_s > 0 ? cells * static_cast<double>(r.steps) / r.wall_s / 1e6 : 0;
    r.memory_bytes = sim.fluid_bytes() + sim.solid_bytes();
    r.peak_rss_bytes = peak_rss_bytes();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lbsolid::accuracy
