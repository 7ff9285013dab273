// Hard case: a long run. 10^5 steps of a tiny coupled periodic box (hard_cases/long_run_box.h; the
// 10^6-step version is the lbsolid-long-run program, tests/bench/long_run.cpp).
// Expectation: bounded (the monitor every 1000 steps never stops it); total momentum drifts by
// less than 1e-10 of itself; fluid mass by less than 1e-12.
#include "hard_cases/hard_case_support.h"
#include "hard_cases/long_run_box.h"

namespace lbsolid::hard_cases {
namespace {

TEST(LongRun, HundredThousandStepsConserveMomentum) {
  auto sim = scene::build_simulation(long_run_box());
  const auto start = sim->totals();
  const auto stop = run_watched(*sim, 100000);
  ASSERT_FALSE(stop) << stop->what;
  ASSERT_EQ(non_finite_or_negative(*sim), "");
  const auto end = sim->totals();
  const double drift = momentum_drift(end, start);
  const double mass_drift = std::abs(end.fluid_mass - start.fluid_mass) / start.fluid_mass;
  report("momentum drift after 1e5 steps (relative)", drift, 1e-10);
  report("fluid mass drift after 1e5 steps (relative)", mass_drift, 1e-12);
  EXPECT_LT(drift, 1e-10);
  EXPECT_LT(mass_drift, 1e-12);
}

}  // namespace
}  // namespace lbsolid::hard_cases
