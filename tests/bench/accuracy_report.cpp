// lbsolid-accuracy-report: what accuracy costs. Problems with a known answer (decaying shear
// wave, Poiseuille, drag on a disk at Re = 1, the coupled solid's drag in periodic arrays of
// disks and balls, and rotating bodies in shear: a disk's rate, an ellipse's Jeffery period) swept over resolution for every lattice, precision and collision operator that
// runs (and for the arrays the particle spacing 1 and 1/2); for each run the error, wall time,
// MLUPS, memory and steps. Prints the table, the observed order per method, the Pareto front of
// error against wall time and the cheapest run reaching 10%, 1% and 0.1% (arrays: 10%, 5%, 2%);
// writes the table as CSV.
//   lbsolid-accuracy-report [--quick] [--csv FILE] [--threads N] [--omega W] [--max-disk-diameter D]
//                           [--problems LIST]
// LIST: comma-separated problem names (shear_wave, poiseuille, disk_drag, array_drag_2d,
// array_drag_3d, shear_rotation, jeffery) or the groups "fluid" (the first three), "coupled" (the
// arrays) and "rotation" (the last two); default all.
// Plot: python3 tests/bench/plot_accuracy.py FILE [PNG]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include "accuracy/accuracy_sweep.h"
#include "accuracy/periodic_array.h"
#include "accuracy/rotation_in_shear.h"
#include "accuracy/rotation_problems.h"
#include "accuracy/sweep_plan.h"

namespace {

using namespace lbsolid::accuracy;

constexpr Problem kAllProblems[] = {Problem::kShearWave,   Problem::kPoiseuille,    Problem::kDiskDrag,
                                    Problem::kArrayDrag2d, Problem::kArrayDrag3d,   Problem::kShearRotation,
                                    Problem::kJeffery};

bool in_group(const std::string& group, Problem p) {
  if (group == "fluid") return !is_array_problem(p) && !is_rotation_problem(p);
  if (group == "coupled") return is_array_problem(p);
  if (group == "rotation") return is_rotation_problem(p);
  return false;
}

void print_run(const RunResult& r, double order) {
  std::printf("  %-13s %-30s %5d  %-10.3e %9.3f %8.1f %10zu %9ld %7.2f%s\n", problem_name(r.problem),
              method_label(r.problem, r.method).c_str(), r.resolution, r.error, r.wall_s, r.mlups, r.memory_bytes,
              r.steps, order, r.converged() ? "" : "  (hit safety cap)");
}

// "fluid", "coupled" or comma-separated names into the problems to run; false on an unknown name.
bool parse_problems(const std::string& list, std::vector<Problem>& out) {
  out.clear();
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, end - start);
    bool known = false;
    for (Problem p : kAllProblems) {
      if (in_group(name, p) || name == problem_name(p)) {
        if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
        known = true;
      }
    }
    if (!known) return false;
    start = end + 1;
  }
  std::sort(out.begin(), out.end());  // the report's order
  return !out.empty();
}

// The array runs' radii: where the body's drag says its surface is.
void print_array_radii(const std::vector<MethodSweep>& sweeps) {
  std::printf("\nArray drag: the body's radii (a_cells: as built, the error's reference; a_w: wet-node; a_h:\n"
              "hydrodynamic, the reference's radius for the measured drag), the signed errors against\n"
              "reference(a_cells) and reference(a_w), Re = 2 a_w U / nu, the body's displacement, the stop:\n");
  std::printf("  %-13s %-30s %5s %8s %8s %8s %8s %8s %9s %9s %8s %8s %s\n", "problem", "method", "R", "a_cells", "a_w",
              "a_h", "a_h-a_w", "a_h-a_c", "err_cell", "err_w", "Re", "|dx|", "stop");
  for (const auto& s : sweeps)
    if (is_array_problem(s.problem))
      for (const RunResult& r : s.runs)
        std::printf("  %-13s %-30s %5d %8.3f %8.3f %8.3f %+8.3f %+8.3f %+9.4f %+9.4f %8.1e %8.1e %s\n",
                    problem_name(r.problem), method_label(r.problem, r.method).c_str(), r.resolution, r.a_cells,
                    r.a_wet, r.a_hydro, r.a_hydro - r.a_wet, r.a_hydro - r.a_cells, r.error_signed, r.error_wet,
                    r.reynolds, std::abs(r.displacement), r.stop.c_str());
}

// The stopping rule's own check: the finest BGK run of each spacing and precision again at a
// tolerance 100 times tighter; the drag must not move by more than a small fraction of its error.
void print_array_convergence_check(const std::vector<MethodSweep>& sweeps, const RunSettings& settings) {
  std::printf("\nArray drag: the stopping rule checked (finest bgk run of each spacing and precision again at a\n"
              "tolerance %.0e instead of %.0e; drag change relative, against the run's error):\n",
              settings.array_tolerance / 100, settings.array_tolerance);
  RunSettings tight = settings;
  tight.array_tolerance = settings.array_tolerance / 100;
  for (const auto& s : sweeps) {
    if (!is_array_problem(s.problem) || s.method.collision != lbsolid::fluid::CollisionModel::kBgk || s.runs.empty())
      continue;
    const RunResult& r = s.runs.back();
    const RunResult t = run_array_drag(s.problem, s.method, r.resolution, tight);
    std::printf("  %-13s %-30s R %-3d drag %.7g (%ld steps, %s) -> %.7g (%ld steps, %s): change %.1e, error %.3e\n",
                problem_name(s.problem), method_label(s.problem, s.method).c_str(), r.resolution, r.measured, r.steps,
                r.stop.c_str(), t.measured, t.steps, t.stop.c_str(), std::abs(t.measured / r.measured - 1), r.error);
  }
}

// The Jeffery runs: the aspect ratio each turn shows, and how well it follows Jeffery's law there.
void print_jeffery_details(const std::vector<MethodSweep>& sweeps) {
  std::printf("\nJeffery: the lattice ellipse 3b x b (error: its period against Jeffery's at r = 3); r_e, the\n"
              "effective aspect ratio its turn's shape shows; the period against Jeffery's at r_e; the largest\n"
              "angle off Jeffery's law at r_e over the turn:\n");
  std::printf("  %-30s %3s %10s %9s %7s %12s %10s\n", "method", "b", "gamma T", "error", "r_e", "period(r_e)", "law (rad)");
  for (const auto& s : sweeps)
    if (s.problem == Problem::kJeffery)
      for (const RunResult& r : s.runs)
        std::printf("  %-30s %3d %10.3f %+9.4f %7.3f %+12.4f %10.4f%s\n", method_label(r.problem, r.method).c_str(),
                    r.resolution, r.measured, r.measured / jeffery_shear_period(3) - 1,
                    r.aspect_ratio, r.jeffery_period_error, r.law_deviation, r.converged() ? "" : "  (no full turn)");
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
  // spacing: the array drag's and rotation problems'; a_cells .. error_wet: the array drag's;
  // aspect_ratio .. law_deviation: Jeffery's (empty for the other problems).
  std::fprintf(f, "problem,lattice,precision,collision,resolution,error,wall_s,mlups,memory_bytes,steps,order,"
                  "measured,reynolds,peak_rss_bytes,stop,spacing,a_cells,a_wet,a_hydro,error_signed,error_wet,"
                  "aspect_ratio,jeffery_period_error,law_deviation\n");
  for (const auto& s : sweeps)
    for (std::size_t k = 0; k < s.runs.size(); ++k) {
      const RunResult& r = s.runs[k];
      const bool array = is_array_problem(r.problem);
      const std::string reynolds = r.problem == Problem::kDiskDrag                       ? csv_number(r.reynolds, "%.4f")
                                   : array || is_rotation_problem(r.problem) ? csv_number(r.reynolds, "%.3e")
                                                                             : "";
      std::fprintf(f, "%s,%s,%s,%s,%d,%s,%s,%s,%zu,%ld,%s,%s,%s,%ld,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n",
                   problem_name(r.problem),
                   lbsolid::scene::lattice_kind_name(r.method.lattice), precision_name(r.method.precision),
                   lbsolid::fluid::collision_model_name(r.method.collision), r.resolution, csv_number(r.error).c_str(),
                   csv_number(r.wall_s).c_str(), csv_number(r.mlups, "%.2f").c_str(), r.memory_bytes, r.steps,
                   csv_number(s.pairwise_order[k], "%.3f").c_str(), csv_number(r.measured, "%.8g").c_str(),
                   reynolds.c_str(), r.peak_rss_bytes, r.stop.c_str(),
                   has_spacing(r.problem) ? csv_number(r.method.spacing, "%g").c_str() : "",
                   csv_number(r.a_cells, "%.4f").c_str(), csv_number(r.a_wet, "%.4f").c_str(),
                   csv_number(r.a_hydro, "%.4f").c_str(), csv_number(r.error_signed).c_str(),
                   csv_number(r.error_wet).c_str(), csv_number(r.aspect_ratio, "%.4f").c_str(),
                   csv_number(r.jeffery_period_error).c_str(), csv_number(r.law_deviation).c_str());
    }
  return std::fclose(f) == 0;
}

// Float's velocity checked: at a middle radius, bgk/float/s1 at the double's U (where float's
// round-off shows) and at its own, against bgk/double/s1 at both (the velocity's own effect: Re).
void print_array_float_check(const std::vector<MethodSweep>& sweeps, const RunSettings& settings) {
  std::printf("\nArray drag: float's velocity checked (bgk, spacing 1; drag relative to double at U = %.0e):\n",
              settings.array_velocity);
  for (const auto& s : sweeps) {
    if (!is_array_problem(s.problem) || s.method.collision != lbsolid::fluid::CollisionModel::kBgk ||
        s.method.precision != lbsolid::scene::Precision::kDouble || s.method.spacing != 1.0 || s.runs.empty())
      continue;
    const int radius = s.problem == Problem::kArrayDrag2d ? 8 : 5;
    const RunResult* base = nullptr;
    for (const RunResult& r : s.runs)
      if (r.resolution == radius) base = &r;
    if (!base) continue;
    Method single = s.method;
    single.precision = lbsolid::scene::Precision::kFloat;
    for (double u : {settings.array_velocity, settings.array_velocity_float})
      for (const Method& m : {s.method, single}) {
        RunSettings at = settings;
        at.array_velocity = at.array_velocity_float = u;
        const RunResult r = run_array_drag(s.problem, m, radius, at);
        std::printf("  %-13s %-30s R %-3d U %.0e: drag %.7g, %+.2e relative, Re %.1e, |dx| %.1e, %ld steps\n",
                    problem_name(s.problem), method_label(s.problem, m).c_str(), radius, u, r.measured,
                    r.measured / base->measured - 1, r.reynolds, std::abs(r.displacement), r.steps);
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string csv = "accuracy.csv";
  RunSettings settings;
  int max_disk_diameter = 37;
  std::vector<Problem> problems(std::begin(kAllProblems), std::end(kAllProblems));
  for (int k = 1; k < argc; ++k) {
    if (!std::strcmp(argv[k], "--quick")) quick = true;
    else if (!std::strcmp(argv[k], "--csv") && k + 1 < argc) csv = argv[++k];
    else if (!std::strcmp(argv[k], "--threads") && k + 1 < argc) settings.threads = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--omega") && k + 1 < argc) settings.omega = std::atof(argv[++k]);
    else if (!std::strcmp(argv[k], "--max-disk-diameter") && k + 1 < argc) max_disk_diameter = std::atoi(argv[++k]);
    else if (!std::strcmp(argv[k], "--problems") && k + 1 < argc && parse_problems(argv[k + 1], problems)) ++k;
    else {
      std::fprintf(stderr,
                   "usage: lbsolid-accuracy-report [--quick] [--csv FILE] [--threads N] [--omega W]"
                   " [--max-disk-diameter D (9 to 65, default 37)]\n"
                   "       [--problems LIST (comma-separated: shear_wave, poiseuille, disk_drag, array_drag_2d,"
                   " array_drag_3d, shear_rotation, jeffery, or fluid, coupled, rotation; default all)]\n");
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
  const std::vector<Method> fluid_methods = available_methods(settings, &skipped);
  std::vector<Method> methods_2d, methods_3d, methods_rotation;
  for (Problem p : problems) {
    if (p == Problem::kArrayDrag2d) methods_2d = array_methods(p, settings, &skipped);
    if (p == Problem::kArrayDrag3d) methods_3d = array_methods(p, settings, &skipped);
    if (is_rotation_problem(p) && methods_rotation.empty()) methods_rotation = rotation_methods(settings, &skipped);
  }
  auto methods_of = [&](Problem p) -> const std::vector<Method>& {
    if (is_rotation_problem(p)) return methods_rotation;
    return p == Problem::kArrayDrag2d ? methods_2d : p == Problem::kArrayDrag3d ? methods_3d : fluid_methods;
  };
  std::printf("What accuracy costs (%s sweep, omega %.3g, %d thread%s; diffusive scaling; array drag in Stokes flow"
              " at U ~ %.0e (double), %.0e (float))\n",
              quick ? "quick" : "full", settings.omega, settings.threads, settings.threads == 1 ? "" : "s",
              settings.array_velocity, settings.array_velocity_float);
  std::printf("  problems:");
  for (Problem p : problems) std::printf(" %s", problem_name(p));
  std::printf("\n");
  for (const auto& name : skipped)
    std::printf("  not run: %s (the operator runs as BGK: not implemented yet)\n", name.c_str());
  std::printf("  %-13s %-30s %5s  %-10s %9s %8s %10s %9s %7s\n", "problem", "method", "N", "error", "wall_s", "MLUPS",
              "memory_B", "steps", "order");
  std::fflush(stdout);

  std::vector<MethodSweep> sweeps;
  for (Problem problem : problems)
    for (const Method& method : methods_of(problem)) {
      MethodSweep s = sweep_method(problem, method, plan.resolutions(problem), settings, [](const RunResult& r) {
        // Progress on stderr: a drag run's error is known only once the finest run is in.
        std::fprintf(stderr, "  ran %s %s N %d: %.2f s\n", problem_name(r.problem),
                     method_label(r.problem, r.method).c_str(), r.resolution, r.wall_s);
      });
      for (std::size_t k = 0; k < s.runs.size(); ++k) print_run(s.runs[k], s.pairwise_order[k]);
      std::fflush(stdout);
      sweeps.push_back(std::move(s));
    }

  std::printf("\nObserved order of convergence per method (shear wave, Poiseuille: log-log fit of the error over all\n"
              "resolutions; drag: from the three finest c_d, no reference needed; array drag: log-log fit of the\n"
              "error against reference(a_cells) over all radii):\n");
  for (Problem problem : problems)
    for (const auto& s : sweeps)
      if (s.problem == problem) {
        std::printf("  %-13s %-30s order %6.2f", problem_name(problem), method_label(problem, s.method).c_str(),
                    s.order);
        if (problem == Problem::kDiskDrag)
          std::printf("   reference c_d(Re=1) %.5g (Richardson, order %.2f)", s.reference, s.richardson_order);
        if (is_array_problem(problem) && !s.runs.empty() && std::isfinite(s.order) && s.order > 0) {
          // The radius each target would need on this method's fitted line through its finest run.
          const RunResult& last = s.runs.back();
          std::printf("   R for 10%% / 5%% / 2%% (fit):");
          for (double target : error_targets(problem)) {
            if (last.error <= target)
              std::printf(" reached");
            else
              std::printf(" ~%.0f", last.resolution * std::pow(last.error / target, 1 / s.order));
          }
        }
        std::printf("\n");
      }

  const bool any_array = !methods_2d.empty() || !methods_3d.empty();
  if (any_array) print_array_radii(sweeps);
  if (std::find(problems.begin(), problems.end(), Problem::kJeffery) != problems.end()) print_jeffery_details(sweeps);

  std::printf("\nPareto front (error against wall time; no other run is both faster and more accurate):\n");
  for (Problem problem : problems)
    for (const RunResult& r : pareto_runs(problem, sweeps))
      std::printf("  %-13s %-30s N %-4d error %.3e  %.3f s\n", problem_name(problem),
                  method_label(problem, r.method).c_str(), r.resolution, r.error, r.wall_s);

  std::printf("\nCheapest run reaching each error:\n");
  for (Problem problem : problems)
    for (double target : error_targets(problem)) {
      RunResult r;
      if (cheapest_within(problem, sweeps, target, r))
        std::printf("  %-13s %-6g %-30s N %-4d error %.3e  %.3f s\n", problem_name(problem), target,
                    method_label(problem, r.method).c_str(), r.resolution, r.error, r.wall_s);
      else
        std::printf("  %-13s %-6g none in this sweep\n", problem_name(problem), target);
    }
  if (any_array) {
    // The same against reference(a_w): what a user who takes the wet-node radius as the body's gets.
    std::printf("\nArray drag, cheapest run whose drag is within each error of reference(a_w) (the wet-node radius):\n");
    for (Problem problem : problems) {
      if (!is_array_problem(problem)) continue;
      for (double target : error_targets(problem)) {
        const RunResult* best = nullptr;
        for (const auto& s : sweeps)
          if (s.problem == problem)
            for (const RunResult& r : s.runs)
              if (std::abs(r.error_wet) <= target && (!best || r.wall_s < best->wall_s)) best = &r;
        if (best)
          std::printf("  %-13s %-6g %-30s N %-4d error_w %+.3e  %.3f s\n", problem_name(problem), target,
                      method_label(problem, best->method).c_str(), best->resolution, best->error_wet, best->wall_s);
        else
          std::printf("  %-13s %-6g none in this sweep\n", problem_name(problem), target);
      }
    }
    if (!quick) {
      print_array_convergence_check(sweeps, settings);
      print_array_float_check(sweeps, settings);
    }
  }

  if (!write_csv(csv, sweeps)) {
    std::fprintf(stderr, "cannot write %s\n", csv.c_str());
    return 1;
  }
  std::printf("\nwrote %s\n", csv.c_str());
  return 0;
}
