// The accuracy report's quick sweep, in process: what must hold whatever the tuning.
//   - errors fall as the resolution grows (every problem, every method);
//   - BGK's observed order on the shear wave and on Poiseuille is 2 (double precision);
//   - float agrees with double wherever float's round-off is well below the discretisation error;
//   - the drag runs reach Re = 1 (within 10%) and their c_d converges (differences shrink);
//   - the Pareto front of error against wall time is non-empty and no run dominates a member.
// BGK only, on D2Q9 and D2Q7, double and float (the drag on D2Q9 double and float and D2Q7 double):
// about 7 s on one core. The full sweep is tests/bench/accuracy_report.cpp.
// The coupled problems (array drag, periodic_array.h) have their own quick sweep, run only by the
// tests that need it (each test is its own process under ctest; about 3 s each):
//   - the drag's error against reference(a_cells) falls with the radius, and R |error| (the
//     first-order law's constant) lies in the band the full sweep measured; Re is Stokes flow;
//   - float, at its own velocity, gives double's drag to a tenth of the error;
//   - the stopping rule has really reached the steady state (a 100x tighter tolerance agrees).
// The rotation problems (rotation_problems.h) likewise, BGK and TRT at spacing 1 (about 5 s):
//   - a torque-free disk turns at gamma_dot / 2 within issue 16's 3% at every size;
//   - the lattice ellipse's Jeffery period approaches the continuum ellipse's as it grows, and at
//     every size follows Jeffery's law at the aspect ratio its turn shows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/convergence.h"
#include "accuracy/periodic_array.h"
#include "accuracy/rotation_problems.h"
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

// The array drag's quick sweep: BGK on both spacings in 2D and 3D, plus float and TRT in 2D.
// About 3 s on one core (the 3D ball of radius 5 at spacing 1/2, 8000 particles, is half of it).
const std::vector<MethodSweep>& array_sweeps() {
  static const std::vector<MethodSweep> all = [] {
    using fluid::CollisionModel;
    std::vector<MethodSweep> s;
    const SweepPlan plan = quick_plan();
    const RunSettings settings;
    const std::pair<Problem, Method> runs[] = {
        {Problem::kArrayDrag2d, {LatticeKind::kD2Q9, Precision::kDouble, CollisionModel::kBgk, 1.0}},
        {Problem::kArrayDrag2d, {LatticeKind::kD2Q9, Precision::kDouble, CollisionModel::kBgk, 0.5}},
        {Problem::kArrayDrag2d, {LatticeKind::kD2Q9, Precision::kFloat, CollisionModel::kBgk, 1.0}},
        {Problem::kArrayDrag2d, {LatticeKind::kD2Q9, Precision::kDouble, CollisionModel::kTrt, 1.0}},
        {Problem::kArrayDrag3d, {LatticeKind::kD3Q19, Precision::kDouble, CollisionModel::kBgk, 1.0}},
        {Problem::kArrayDrag3d, {LatticeKind::kD3Q19, Precision::kDouble, CollisionModel::kBgk, 0.5}}};
    for (const auto& [problem, m] : runs) {
      s.push_back(sweep_method(problem, m, plan.resolutions(problem), settings));
      for (const RunResult& r : s.back().runs)
        std::printf("  %-13s %-26s R %-2d error %.4e (err_w %+.4f, a_h - a_w %+.3f)  %.3f s  %ld steps  stop %s\n",
                    problem_name(problem), method_label(problem, m).c_str(), r.resolution, r.error, r.error_wet,
                    r.a_hydro - r.a_wet, r.wall_s, r.steps, r.stop.c_str());
    }
    return s;
  }();
  return all;
}

const MethodSweep* find_array(Problem problem, Precision precision, fluid::CollisionModel collision, double spacing) {
  for (const auto& s : array_sweeps())
    if (s.problem == problem && s.method.precision == precision && s.method.collision == collision &&
        s.method.spacing == spacing)
      return &s;
  return nullptr;
}

// The band of R |error| (error against reference(a_cells), R the radius in lattice units) that the
// full sweep (docs/accuracy.csv, omega 0.8) measured over all its radii, per problem, spacing and
// operator, in double: the error is a radius offset a_cells - a_h that is nearly constant, so
// R |error| is the first-order law's constant, and its spread over R = 3..16 (2D) or 3..8 (3D) is
// how far the law is from exact (the offset shrinks slowly with R: observed orders 0.94-1.5). The
// quick runs are a subset of the full sweep's and must land in the band widened by 10%: a change of
// the coupling, the operators or the run that moves the drag by more than that is a change of the
// model, for which the report must be regenerated (and these bands with it).
struct FirstOrderBand {
  Problem problem;
  double spacing;
  fluid::CollisionModel collision;
  double low, high;  // R |error| over the full sweep's radii
};
constexpr FirstOrderBand kFullSweepBands[] = {
    {Problem::kArrayDrag2d, 1.0, fluid::CollisionModel::kBgk, 0.996, 1.117},
    {Problem::kArrayDrag2d, 1.0, fluid::CollisionModel::kTrt, 0.861, 1.029},
    {Problem::kArrayDrag2d, 0.5, fluid::CollisionModel::kBgk, 0.417, 0.561},
    {Problem::kArrayDrag3d, 1.0, fluid::CollisionModel::kBgk, 1.352, 1.444},
    {Problem::kArrayDrag3d, 0.5, fluid::CollisionModel::kBgk, 0.473, 0.573}};

TEST(AccuracyReport, ArrayDragConvergesAtFirstOrderWithinTheFullSweepsBand) {
  int checked = 0;
  for (const auto& s : array_sweeps()) {
    const std::string name = std::string(problem_name(s.problem)) + " " + method_label(s.problem, s.method);
    for (std::size_t k = 0; k < s.runs.size(); ++k) {
      const RunResult& r = s.runs[k];
      EXPECT_TRUE(r.converged()) << name << " R " << r.resolution;
      // Stokes flow: the references neglect inertia, an O(Re^2) correction in a periodic array.
      EXPECT_LT(r.reynolds, 0.02) << name << " R " << r.resolution;
      if (k > 0) {
        EXPECT_LT(r.error, s.runs[k - 1].error) << name << ": the error must fall with the radius";
      }
      if (s.method.precision != Precision::kDouble) continue;
      for (const FirstOrderBand& band : kFullSweepBands)
        if (band.problem == s.problem && band.spacing == s.method.spacing && band.collision == s.method.collision) {
          const double constant = r.resolution * r.error;
          std::printf("[ figure   ] %s R %d: R |error| = %.3f (full sweep %.3f..%.3f, +-10%%)\n", name.c_str(),
                      r.resolution, constant, band.low, band.high);
          EXPECT_GE(constant, 0.9 * band.low) << name << " R " << r.resolution;
          EXPECT_LE(constant, 1.1 * band.high) << name << " R " << r.resolution;
          ++checked;
        }
    }
  }
  EXPECT_EQ(checked, 10);  // two radii of each of the five double sweeps
  // The Pareto front of each array problem: non-empty, and no run dominates a member.
  for (Problem problem : {Problem::kArrayDrag2d, Problem::kArrayDrag3d}) {
    std::vector<CostPoint> all;
    for (const auto& s : array_sweeps())
      if (s.problem == problem)
        for (const RunResult& r : s.runs) all.push_back({r.wall_s, r.error});
    const std::vector<RunResult> front = pareto_runs(problem, array_sweeps());
    ASSERT_FALSE(front.empty()) << problem_name(problem);
    for (const RunResult& r : front) EXPECT_FALSE(dominated({r.wall_s, r.error}, all)) << problem_name(problem);
  }
}

// Float runs the array at its own velocity (RunSettings::array_velocity_float, 1e-4: at double's
// 2e-6 its round-off, an absolute velocity error of order eps_float, moves the drag by 3% at R = 8).
// There it must give double's drag to a tenth of the discretisation error, the rule
// FloatAgreesWithDoubleWhereRoundOffIsSmall applies to the fluid problems (the full sweep measures
// 0.07% at R = 8 against an error of 13%).
TEST(AccuracyReport, ArrayDragFloatAtItsVelocityAgreesWithDouble) {
  const MethodSweep* d = find_array(Problem::kArrayDrag2d, Precision::kDouble, fluid::CollisionModel::kBgk, 1.0);
  const MethodSweep* f = find_array(Problem::kArrayDrag2d, Precision::kFloat, fluid::CollisionModel::kBgk, 1.0);
  ASSERT_TRUE(d && f);
  ASSERT_EQ(d->runs.size(), f->runs.size());
  for (std::size_t k = 0; k < d->runs.size(); ++k) {
    const RunResult &rd = d->runs[k], &rf = f->runs[k];
    const double difference = std::abs(rf.measured / rd.measured - 1);
    std::printf("[ figure   ] array_drag_2d R %d: |float - double| / double = %.2e, error %.2e\n", rd.resolution,
                difference, rd.error);
    EXPECT_LT(difference, 0.1 * rd.error) << "R " << rd.resolution;
  }
}

// The SteadyMonitor stops where the change between samples, decaying geometrically, says the rest
// is below the tolerance; sampled too often, a slow decay looks like a plateau and the run stops
// early. Sampled as run_to_steady does (0.2 of the viscous time, and of the body's own relaxation
// time, which dominates for the heavy spacing-1/2 bodies), a run at 1e-5 must agree with the same
// run at 1e-7 far inside its error: to 1e-4 of the drag (the errors here are 10% and more).
TEST(AccuracyReport, ArrayDragStopsAtItsSteadyState) {
  RunSettings loose, tight;
  tight.array_tolerance = loose.array_tolerance / 100;
  for (double spacing : {1.0, 0.5}) {
    const Method m{LatticeKind::kD2Q9, Precision::kDouble, fluid::CollisionModel::kBgk, spacing};
    const RunResult a = run_array_drag(Problem::kArrayDrag2d, m, 4, loose);
    const RunResult b = run_array_drag(Problem::kArrayDrag2d, m, 4, tight);
    const double change = std::abs(b.measured / a.measured - 1);
    std::printf("[ figure   ] array_drag_2d %s R 4: drag %.7g (%ld steps) -> %.7g (%ld steps) at 1/100 the tolerance:"
                " change %.1e (bound 1e-4)\n",
                method_label(Problem::kArrayDrag2d, m).c_str(), a.measured, a.steps, b.measured, b.steps, change);
    EXPECT_EQ(a.stop, "tolerance");
    EXPECT_GT(b.steps, a.steps);
    EXPECT_LT(change, 1e-4);
  }
}

// The rotation problems' quick sweep: BGK and TRT at spacing 1 on both problems.
const std::vector<MethodSweep>& rotation_sweeps() {
  static const std::vector<MethodSweep> all = [] {
    std::vector<MethodSweep> s;
    const SweepPlan plan = quick_plan();
    const RunSettings settings;
    for (Problem problem : {Problem::kShearRotation, Problem::kJeffery})
      for (auto collision : {fluid::CollisionModel::kBgk, fluid::CollisionModel::kTrt}) {
        const Method m{LatticeKind::kD2Q9, Precision::kDouble, collision, 1.0};
        s.push_back(sweep_method(problem, m, plan.resolutions(problem), settings));
        for (const RunResult& r : s.back().runs)
          std::printf("  %-14s %-26s N %-2d measured %.5g error %.4e (r_e %.3f, period(r_e) %+.4f, law %.4f)  %.3f s\n",
                      problem_name(problem), method_label(problem, m).c_str(), r.resolution, r.measured, r.error,
                      r.aspect_ratio, r.jeffery_period_error, r.law_deviation, r.wall_s);
      }
    return s;
  }();
  return all;
}

// Measured at omega 0.8: 0.34% to 0.87% (R = 4, 8). The rate is taken once the Couette flow has
// settled to e^-7 of its start, so the figures are near the measurement's own floor (TRT's does not
// fall from R = 4 to 8: 0.38%, 0.42%); 3% is issue 16's bound.
TEST(AccuracyReport, ATorqueFreeDiskTurnsAtHalfTheShearRateAtEverySize) {
  int checked = 0;
  for (const auto& s : rotation_sweeps()) {
    if (s.problem != Problem::kShearRotation) continue;
    for (const RunResult& r : s.runs) {
      EXPECT_EQ(r.stop, "time") << method_label(s.problem, s.method) << " R " << r.resolution;
      EXPECT_LT(r.error, 0.03) << method_label(s.problem, s.method) << " R " << r.resolution;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 4);
}

// Measured at omega 0.8, b = 1 -> 2: the period's error against r = 3 falls 109% -> 36% (BGK) and
// 69% -> 24% (TRT); against Jeffery's at the turn's own r_e it is 0.8-1.1% and the angle stays
// within 0.013 rad of the law at b = 2 (0.075-0.080 at b = 1, a 9-particle cross). The bounds are
// jeffery_orbit_test's: 5% (issue 16) and 0.03 rad, held at b = 2.
TEST(AccuracyReport, TheJefferyPeriodConvergesAndFollowsTheLaw) {
  int checked = 0;
  for (const auto& s : rotation_sweeps()) {
    if (s.problem != Problem::kJeffery) continue;
    const std::string name = method_label(s.problem, s.method);
    ASSERT_EQ(s.runs.size(), 2u) << name;
    for (const RunResult& r : s.runs) ASSERT_TRUE(r.converged()) << name << " b " << r.resolution << ": no full turn";
    EXPECT_LT(s.runs[1].error, s.runs[0].error) << name << ": the error must fall with the size";
    EXPECT_LT(std::abs(s.runs[1].jeffery_period_error), 0.05) << name;
    EXPECT_LT(s.runs[1].law_deviation, 0.03) << name;
    ++checked;
  }
  EXPECT_EQ(checked, 2);
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
