#pragma once
// One method swept over resolutions on one problem: the runs, their errors (for the drag, against
// the Richardson extrapolation of the two finest runs), and the observed order of convergence.
// Then across methods: the Pareto front of error against wall time, and the cheapest run that
// reaches a target error.
#include <functional>
#include <vector>

#include "accuracy/accuracy_problems.h"

namespace lbsolid::accuracy {

struct MethodSweep {
  Problem problem = Problem::kShearWave;
  Method method;
  std::vector<RunResult> runs;  // ascending resolution
  std::vector<double> pairwise_order;  // between run k-1 and run k; NaN for the first
  // Shear wave, Poiseuille, array drag: least-squares slope of log error against log N over all runs.
  // Drag: the order read off the three finest c_d values (no reference needed); NaN with fewer.
  double order = 0;
  double reference = 0;          // drag: Richardson-extrapolated c_d at Re = 1
  double richardson_order = 0;   // drag: the order the extrapolation assumed
};

// Drag: the Richardson order when the three finest runs do not give a usable one. The disk is
// coupled to its nearest nodes, a staircase whose error falls as 1/D: first order.
constexpr double kDragFallbackOrder = 1.0;
// The c_d Re the coarsest drag run aims its force with (later runs use the previous run's value);
// only Re's closeness to 1 depends on it.
constexpr double kDragStokesGuess = 7.0;
// How far from 1 a drag run's Re may land before it is re-aimed and run again.
constexpr double kDragReTolerance = 0.05;

// `resolutions`: wavelengths (shear wave), rows (Poiseuille) or disk radii (drag), ascending.
// `on_run` is called after each run (progress output).
MethodSweep sweep_method(Problem problem, const Method& method, const std::vector<int>& resolutions,
                         const RunSettings& settings, const std::function<void(const RunResult&)>& on_run = {});

// The runs of `problem` on the Pareto front of (wall time, error) across all sweeps, by time.
std::vector<RunResult> pareto_runs(Problem problem, const std::vector<MethodSweep>& sweeps);

// The error levels the report asks the cheapest run for: 10%, 1%, 0.1% for the fluid problems;
// 10%, 5%, 2% for the array drag (a body's drag converges at first order: 1% is out of reach);
// 10%, 3%, 1% for the shear rotation; 30%, 20%, 10% for the Jeffery period.
std::vector<double> error_targets(Problem problem);

// The fastest run of `problem` with error <= target; false when none reaches it.
bool cheapest_within(Problem problem, const std::vector<MethodSweep>& sweeps, double target, RunResult& out);

}  // namespace lbsolid::accuracy
