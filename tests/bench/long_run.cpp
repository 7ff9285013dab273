// lbsolid-long-run: the long-run hard case at full length. Runs the tiny coupled periodic box of
// tests/hard_cases/long_run_box.h for 10^6 steps (or the count given as the first argument) and
// prints the relative drift of total momentum every tenth of the run; exits 1 if the final drift
// reaches 1e-10 or the stability monitor stops the run. CI runs the same box for 10^5 steps
// (tests/hard_cases/long_run_test.cpp).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "hard_cases/long_run_box.h"

int main(int argc, char** argv) {
  using namespace lbsolid;
  const long steps = argc > 1 ? std::atol(argv[1]) : 1000000;
  if (steps < 10) {
    std::fprintf(stderr, "usage: lbsolid-long-run [steps >= 10]\n");
    return 2;
  }
  try {
    auto sim = scene::build_simulation(hard_cases::long_run_box());
    const auto start = sim->totals();
    const auto t0 = std::chrono::steady_clock::now();
    double drift = 0;
    for (int part = 1; part <= 10; ++part) {
      sim->run(steps * part / 10 - sim->step_count());
      const auto now = sim->totals();
      drift = hard_cases::momentum_drift(now, start);
      std::printf("step %8ld  momentum drift %.3e  fluid mass drift %.3e\n", sim->step_count(), drift,
                  std::abs(now.fluid_mass - start.fluid_mass) / start.fluid_mass);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%ld steps in %.1f s: total momentum drift %.3e (bound 1e-10)\n", steps, seconds, drift);
    return drift < 1e-10 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lbsolid-long-run: %s\n", e.what());
    return 1;
  }
}
