// lbsolid-accuracy-report: what accuracy costs. Problems with a known answer (decaying shear
// wave, Poiseuille, drag on a disk at Re = 1) swept over resolution for every lattice, precision
// and collision operator that runs; for each run the error, wall time, MLUPS, memory and steps.
// Prints the table, the observed order per method, the Pareto front of error against wall time
// and the cheapest run reaching 10%, 1% and 0.1%; writes the table as CSV.
//   lbsolid-accuracy-report [--quick] [--csv FILE] [--threads N] [--omega W] [--max-disk-diameter D]
// Plot: python3 tests/bench/plot_accuracy.py FILE [PNG]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/sweep_plan.h"

namespace {

using namespace lbsolid::accuracy;

constexpr Problem kProblems[] = {Problem::kShearWave, Problem::kPoiseuille, Problem::kDiskDrag};

void print_run(const RunResult& r, double order) {
  std::printf("  %-11s %-22s %5d  %-10.3e %9.3f %8.1f %10zu %9ld %7.2f%s\n", problem_name(r.problem),
              method_name(r.method).c_str(), r.resolution, r.error, r.wall_s, r.mlups, r.memory_bytes, r.steps, order,
              r.converged() ? "" : "  (hit safety cap)");
}

std::string csv_number(double v, const char* format = "%.6g") {
  if (!std::isfinite(v)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

bool write_csv(const std::string& path, const std::vector<MethodSweep>& sweeps) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f, "problem,lattice,precision,collision,resolution,error,wall_s,mlups,memory_bytes,steps,order,"
                  "measured,reynolds,peak_rss_bytes,stop\n");
  for (const auto& s : sweeps)
    for (std::size_t k = 0; k < s.runs.size(); ++k) {
      const RunResult& r = s.runs[k];
      std::fprintf(f, "%s,%s,%s,%s,%d,%s,%s,%s,%zu,%ld,%s,%s,%s,%ld,%s\n", problem_name(r.problem),
                   lbsolid::scene::lattice_kind_name(r.method.lattice), precision_name(r.method.precision),
                   lbsolid::fluid::collision_model_name(r.method.collision), r.resolution, csv_number(r.error).c_str(),
                   csv_number(r.wall_s).c_str(), csv_number(r.mlups, "%.2f").c_str(), r.memory_bytes, r.steps,
                   csv_number(s.pairwise_order[k], "%.3f").c_str(), csv_number(r.measured, "%.8g").c_str(),
                   r.problem == Problem::kDiskDrag ? csv_number(r.reynolds, "%.4f").c_str() : "", r.peak_rss_bytes,
                   r.stop.c_str());
    }
  return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string csv = "accuracy.csv";
  RunSettings settings;
  int max_disk_diameter = 37;
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--quick")) quick = true;
    else if (!std::strcmp(argv[k], "--csv") && k + 1 < argc) csv = argv[++k];
    else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc) settings.threads = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--omega") && k + 1 < argc) settings.omega = std::atof(argv[++k]);
    else if (!std::strcmp(argv[k], "--max-disk-diameter") && k + 1 < argc) max_disk_diameter = std::atoi(argv[++k]);
    else {
      std::fprintf(stderr,
                   "usage: lbsolid-accuracy-report [--quick] [--csv FILE] [--threads N] [--omega W]"
                   " [--max-disk-diameter D (9 to 65, default 37)]\n");
      return 2;
    }
  }
  if (max_disk_diameter < 25 || max_disk_diameter > 65) {
    std::fprintf(stderr, "--max-disk-diameter: must lie in [25, 65] (three disks for a Richardson reference), got %d\n",
                 max_disk_diameter);
    return 2;
  }
  const SweepPlan plan = quick ? quick_plan() : full_plan(max_disk_diameter);
  std::vector<std::string> skipped;
  const std::vector<Method> methods = available_methods(settings, &skipped);
  std::printf("What accuracy costs (%s sweep, omega %.3g, %d thread%s; diffusive scaling)\n", quick ? "quick" : "full",
              settings.omega, settings.threads, settings.threads == 1 ? "" : "s");
  for (const auto& name : skipped)
    std::printf("  not run: %s (the operator runs as BGK: not implemented yet)\n", name.c_str());
  std::printf("  %-11s %-22s %5s  %-10s %9s %8s %10s %9s %7s\n", "problem", "method", "N", "error", "wall_s", "MLUPS",
              "memory_B", "steps", "order");
  std::fflush(stdout);

  std::vector<MethodSweep> sweeps;
  for (Problem problem : kProblems)
    for (const Method& method : methods) {
      MethodSweep s = sweep_method(problem, method, plan.resolutions(problem), settings, [](const RunResult& r) {
        // Progress on stderr: a drag run's error is known only once the finest run is in.
        std::fprintf(stderr, "  ran %s %s N %d: %.2f s\n", problem_name(r.problem), method_name(r.method).c_str(),
                     r.resolution, r.wall_s);
      });
      for (std::size_t k = 0; k < s.runs.size(); ++k) print_run(s.runs[k], s.pairwise_order[k]);
      std::fflush(stdout);
      sweeps.push_back(std::move(s));
    }

  std::printf("\nObserved order of convergence per method (shear wave, Poiseuille: log-log fit of the error over all\n"
              "resolutions; drag: from the three finest c_d, no reference needed):\n");
  for (Problem problem : kProblems)
    for (const auto& s : sweeps)
      if (s.problem == problem) {
        std::printf("  %-11s %-22s order %6.2f", problem_name(problem), method_name(s.method).c_str(), s.order);
        if (problem == Problem::kDiskDrag)
          std::printf("   reference c_d(Re=1) %.5g (Richardson, order %.2f)", s.reference, s.richardson_order);
        std::printf("\n");
      }

  std::printf("\nPareto front (error against wall time; no other run is both faster and more accurate):\n");
  for (Problem problem : kProblems)
    for (const RunResult& r : pareto_runs(problem, sweeps))
      std::printf("  %-11s %-22s N %-4d error %.3e  %.3f s\n", problem_name(problem), method_name(r.method).c_str(),
                  r.resolution, r.error, r.wall_s);

  std::printf("\nCheapest run reaching each error:\n");
  for (Problem problem : kProblems)
    for (double target : {0.1, 0.01, 0.001}) {
      RunResult r;
      if (cheapest_within(problem, sweeps, target, r))
        std::printf("  %-11s %-6g %-22s N %-4d error %.3e  %.3f s\n", problem_name(problem), target,
                    method_name(r.method).c_str(), r.resolution, r.error, r.wall_s);
      else
        std::printf("  %-11s %-6g none in this sweep\n", problem_name(problem), target);
    }

  if (!write_csv(csv, sweeps)) {
    std::fprintf(stderr, "cannot write %s\n", csv.c_str());
    return 1;
  }
  std::printf("\nwrote %s\n", csv.c_str());
  return 0;
}
