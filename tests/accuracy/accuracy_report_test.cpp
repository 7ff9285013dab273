// The accuracy report's quick sweep, in process: what must hold whatever the tuning.
//   - errors fall as the resolution grows (every problem, every method);
//   - BGK's observed order on the shear wave and on Poiseuille is 2 (double precision);
//   - float agrees with double wherever float's round-off is well below the discretisation error;
//   - the drag runs reach Re = 1 (within 10%) and their c_d converges (differences shrink);
//   - the Pareto front of error against wall time is non-empty and no run dominates a member.
// BGK only, on D2Q9 and D2Q7, double and float (the drag on D2Q9 double and float and D2Q7 double):
// about 7 s on one core. The full sweep is tests/bench/accuracy_report.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/convergence.h"
#include "accuracy/sweep_plan.h"

namespace lbsolid::accuracy {
namespace {

using scene::LatticeKind;
using scene::Precision;

constexpr Method kMethods[] = {{LatticeKind::kD2Q9, Precision::kDouble, fluid::CollisionModel::kBgk},
                               {LatticeKind::kD2Q9, Precision::kFloat, fluid::CollisionModel::kBgk},
                               {LatticeKind::kD2Q7, Precision::kDouble, fluid::CollisionModel::kBgk},
                               {LatticeKind::kD2Q7, Precision::kFloat, fluid::CollisionModel::kBgk}};

// The quick sweeps, run once per process and shared by the tests below.
const std::vector<MethodSweep>& sweeps() {
  static const std::vector<MethodSweep> all = [] {
    std::vector<MethodSweep> s;
    const SweepPlan plan = quick_plan();
    const RunSettings settings;
    for (Problem problem : {Problem::kShearWave, Problem::kPoiseuille, Problem::kDiskDrag})
      for (const Method& m : kMethods) {
        // Drag is the costly one: D2Q7 float adds no check the others do not make.
        if (problem == Problem::kDiskDrag && m.lattice == LatticeKind::kD2Q7 && m.precision == Precision::kFloat) continue;
        s.push_back(sweep_method(problem, m, plan.resolutions(problem), settings));
        for (const RunResult& r : s.back().runs)
          std::printf("  %-11s %-20s N %-3d error %.3e  %.3f s  %ld steps  stop %s\n", problem_name(problem),
                      method_name(m).c_str(), r.resolution, r.error, r.wall_s, r.steps, r.stop.c_str());
      }
    return s;
  }();
  return all;
}

const MethodSweep* find(Problem problem, LatticeKind lattice, Precision precision) {
  for (const auto& s : sweeps())
    if (s.problem == problem && s.method.lattice == lattice && s.method.precision == precision) return &s;
  return nullptr;
}

TEST(AccuracyReport, EveryRunStopsOnItsCriterion) {
  for (const auto& s : sweeps())
    for (const RunResult& r : s.runs) EXPECT_TRUE(r.converged()) << problem_name(s.problem) << " " << method_name(s.method) << " N " << r.resolution;
}

TEST(AccuracyReport, ErrorsFallWithResolution) {
  for (const auto& s : sweeps())
    for (std::size_t k = 1; k < s.runs.size(); ++k)
      EXPECT_LT(s.runs[k].error, s.runs[k - 1].error)
          << problem_name(s.problem) << " " << method_name(s.method) << " N " << s.runs[k].resolution;
}

// BGK is second order in space for smooth flows and with half-way bounce-back walls. From N = 16
// the next term (relative size ~ N^-2 <= 1/256) shifts a log-log slope by well under 0.1, so a
// band of +-0.15 around 2 separates second order from first or third with room for noise.
TEST(AccuracyReport, BgkIsSecondOrderOnShearWaveAndPoiseuille) {
  for (Problem problem : {Problem::kShearWave, Problem::kPoiseuille})
    for (LatticeKind lattice : {LatticeKind::kD2Q9, LatticeKind::kD2Q7}) {
      const MethodSweep* s = find(problem, lattice, Precision::kDouble);
      ASSERT_NE(s, nullptr);
      std::printf("[ figure   ] %s %s observed order = %.3f (band 2 +- 0.15)\n", problem_name(problem),
                  method_name(s->method).c_str(), s->order);
      EXPECT_NEAR(s->order, 2.0, 0.15) << problem_name(problem) << " " << method_name(s->method);
    }
}

// A run of n steps can accumulate a relative round-off of about n eps_float (each step rounds
// every population once, and a slow approach to steady state can stall when the per-step change
// falls below an ulp). Where that bound is under a fifth of the discretisation error, float must
// reproduce double's error to within a tenth of it: precision must not change the answer there.
TEST(AccuracyReport, FloatAgreesWithDoubleWhereRoundOffIsSmall) {
  const double eps_float = std::numeric_limits<float>::epsilon();
  int compared = 0;
  for (Problem problem : {Problem::kShearWave, Problem::kPoiseuille, Problem::kDiskDrag}) {
    const MethodSweep* d = find(problem, LatticeKind::kD2Q9, Precision::kDouble);
    const MethodSweep* f = find(problem, LatticeKind::kD2Q9, Precision::kFloat);
    ASSERT_TRUE(d && f);
    for (std::size_t k = 0; k < d->runs.size(); ++k) {
      const RunResult &rd = d->runs[k], &rf = f->runs[k];
      const double round_off = static_cast<double>(rf.steps) * eps_float;
      if (!(round_off < 0.2 * rd.error)) continue;
      // The change precision makes, in the units of the error (a relative error): Poiseuille's
      // measured value is its error; the others' errors are relative deviations of `measured`
      // (the drag's from per-method references, so those are compared directly).
      const double difference = problem == Problem::kPoiseuille
                                    ? std::abs(rf.error - rd.error)
                                    : std::abs(rf.measured - rd.measured) / std::abs(rd.measured);
      std::printf("[ figure   ] %s N %d: |float - double| = %.2e, discretisation error %.2e\n", problem_name(problem),
                  rd.resolution, difference, rd.error);
      EXPECT_LT(difference, 0.1 * rd.error) << problem_name(problem) << " N " << rd.resolution;
      ++compared;
    }
  }
  EXPECT_GE(compared, 5) << "too few runs where float's round-off is below the discretisation error";
}

TEST(AccuracyReport, DragRunsReachReOneAndConverge) {
  for (const auto& s : sweeps()) {
    if (s.problem != Problem::kDiskDrag) continue;
    // The coarsest run aims with a guess; the others with the coarser runs' c_d Re.
    for (std::size_t k = 1; k < s.runs.size(); ++k)
      EXPECT_NEAR(s.runs[k].reynolds, 1.0, 0.1) << method_name(s.method) << " D " << s.runs[k].resolution;
    for (std::size_t k = 2; k < s.runs.size(); ++k)
      EXPECT_LT(std::abs(s.runs[k].measured - s.runs[k - 1].measured),
                std::abs(s.runs[k - 1].measured - s.runs[k - 2].measured))
          << method_name(s.method) << ": c_d differences must shrink as D grows";
  }
}

TEST(AccuracyReport, ParetoFrontIsNonEmptyAndUndominated) {
  for (Problem problem : {Problem::kShearWave, Problem::kPoiseuille, Problem::kDiskDrag}) {
    std::vector<CostPoint> all;
    for (const auto& s : sweeps())
      if (s.problem == problem)
        for (const RunResult& r : s.runs) all.push_back({r.wall_s, r.error});
    const std::vector<RunResult> front = pareto_runs(problem, sweeps());
    ASSERT_FALSE(front.empty()) << problem_name(problem);
    for (const RunResult& r : front) EXPECT_FALSE(dominated({r.wall_s, r.error}, all)) << problem_name(problem);
    for (std::size_t k = 1; k < front.size(); ++k) {
      // Sorted by time, a front's error must fall: otherwise the slower member would be dominated.
      EXPECT_LE(front[k - 1].wall_s, front[k].wall_s);
      EXPECT_GT(front[k - 1].error, front[k].error);
    }
  }
}

TEST(Convergence, OrdersRichardsonAndFrontOnKnownData) {
  // q(N) = 3 + 5 N^-2: exact order 2 and exact extrapolation.
  auto q = [](double n) { return 3 + 5 / (n * n); };
  EXPECT_NEAR(pairwise_order(16, q(16) - 3, 32, q(32) - 3), 2.0, 1e-12);
  EXPECT_NEAR(fitted_order({16, 32, 64}, {q(16) - 3, q(32) - 3, q(64) - 3}), 2.0, 1e-12);
  const double n[3] = {9, 17, 33}, v[3] = {q(9), q(17), q(33)};
  EXPECT_NEAR(order_from_three(n, v), 2.0, 1e-9);
  EXPECT_NEAR(richardson(17, q(17), 33, q(33), 2.0), 3.0, 1e-12);
  const std::vector<CostPoint> points = {{1, 0.1}, {2, 0.2}, {3, 0.01}, {0.5, 0.5}, {3, 0.02}};
  const std::vector<std::size_t> front = pareto_front(points);
  ASSERT_EQ(front.size(), 3u);  // (0.5, 0.5), (1, 0.1), (3, 0.01); (2, 0.2) and (3, 0.02) are dominated
  EXPECT_EQ(front[0], 3u);
  EXPECT_EQ(front[1], 0u);
  EXPECT_EQ(front[2], 2u);
}

}  // namespace
}  // namespace lbsolid::accuracy
