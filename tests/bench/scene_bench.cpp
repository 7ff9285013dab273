#include "bench/scene_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>
#include <vector>

#include "bench/bench_scenes.h"
#include "scene/simulation.h"

namespace lbsolid::bench {
namespace {

using scene::Scene;

// Best seconds per step over several segments (the least disturbed on a shared machine).
template <class Stepper>
double seconds_per_step(Stepper&& step, double min_seconds) {
  constexpr int kSegments = 5;
  double best = INFINITY;
  for (int segment = 0; segment < kSegments; ++segment) {
    long steps = 0;
    double seconds = 0;
    const auto start = std::chrono::steady_clock::now();
    while (seconds < min_seconds / kSegments) {
      step();
      ++steps;
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    best = std::min(best, seconds / steps);
  }
  return best;
}

// Seconds per step in each stage, over steps taken with the stage clock on (apart from the steps
// timed as a whole, so that those carry no clock reads); the least of a few rounds per stage.
scene::StageClock::Seconds stage_seconds_per_step(scene::Simulation& sim, double min_seconds) {
  scene::StageClock::Seconds best;
  best.fill(INFINITY);
  for (int round = 0; round < 3; ++round) {
    sim.time_stages(true);
    long steps = 0;
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < min_seconds / 3) {
      sim.step();
      ++steps;
    }
    for (int k = 0; k < scene::kStageCount; ++k)
      best[k] = std::min(best[k], sim.stage_seconds()[k] / static_cast<double>(steps));
  }
  sim.time_stages(false);
  return best;
}

// Steps the coupled scene takes before the fluid-only one is given its fluid: enough for the
// disturbance from every ball to reach every cell of the 3D box (no cell is more than 16 cells
// along any axis from a ball's centre; D3Q19's velocities cross (12, 12, 12) in 18 steps).
constexpr int kStepsBeforeReference = 30;

// The quartiles of v (not empty).
SceneRow::Quartiles quartiles(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return {v[n / 4], v[n / 2], v[(3 * n) / 4]};
}

// The coupled step's extra seconds a step over the reference and over the box at rest, from
// `rounds` rounds of `steps` steps each, in the order coupled, reference, reference, coupled, then
// coupled, at rest, at rest, coupled: each difference is taken within a second, and in ABBA order,
// since what ran just before can move a segment (in one run a box at rest before the coupled
// segment read the 3D figure 4-10 ns a particle lower, before the reference 3-4 higher; in
// another, no such effect: docs/experiments/reference_at_rest.cpp, order).
std::pair<SceneRow::Quartiles, SceneRow::Quartiles> paired_rounds(scene::Simulation& coupled,
                                                                 scene::Simulation& reference,
                                                                 scene::Simulation& at_rest, int rounds, int steps) {
  auto seconds = [steps](scene::Simulation& sim) {
    const auto start = std::chrono::steady_clock::now();
    sim.run(steps);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  };
  auto abba = [&](scene::Simulation& other) {
    const double c1 = seconds(coupled);
    const double o1 = seconds(other);
    const double o2 = seconds(other);
    const double c2 = seconds(coupled);
    return ((c1 + c2) - (o1 + o2)) / 2;
  };
  std::vector<double> over_reference, over_rest;
  for (int round = 0; round < rounds; ++round) {
    over_reference.push_back(abba(reference));
    over_rest.push_back(abba(at_rest));
  }
  return {quartiles(over_reference), quartiles(over_rest)};
}

// A coupled scene against the same scene without its bodies, in alternating rounds, with the
// coupled step's stages. With more than one thread, the same two steps with one thread take
// their turns in the same rounds. The fluid-only scene starts from the coupled scene's fluid,
// not from rest: the D3Q19 kernel steps a fluid at rest (every stored deviation zero) 5-10%
// faster than a moving one, which put 30-45 ns a particle of fluid into the 3D coupling's figure
// (docs/performance.md, "A reference at rest").
SceneRow coupled_against_fluid(const std::string& what, const std::string& lattice, const Scene& coupled,
                               double min_seconds, int rounds) {
  Scene fluid_only = coupled;
  fluid_only.bodies.clear();
  const int threads = coupled.fluid.threads;
  auto with_one_thread = [](Scene s) {
    s.fluid.threads = 1;
    return s;
  };
  auto a = scene::build_simulation(fluid_only);
  auto at_rest = scene::build_simulation(fluid_only);
  auto b = scene::build_simulation(coupled);
  b->run(kStepsBeforeReference);
  scene::SimulationState fluid_of_b = b->save_state();
  fluid_of_b.has_solid = false;
  fluid_of_b.solid = {};
  a->load_state(fluid_of_b);
  std::unique_ptr<scene::Simulation> a1, b1;
  if (threads > 1) {
    a1 = scene::build_simulation(with_one_thread(fluid_only));
    b1 = scene::build_simulation(with_one_thread(coupled));
    b1->run(kStepsBeforeReference);
    a1->load_state(fluid_of_b);  // the threads' results are the same bit for bit
  }
  double plain = INFINITY, with_solid = INFINITY, plain_one = 0, with_solid_one = 0;
  if (threads > 1) plain_one = with_solid_one = INFINITY;
  for (int round = 0; round < (threads > 1 ? 3 : 2); ++round) {
    plain = std::min(plain, seconds_per_step([&] { a->step(); }, min_seconds));
    with_solid = std::min(with_solid, seconds_per_step([&] { b->step(); }, min_seconds));
    if (threads == 1) continue;
    plain_one = std::min(plain_one, seconds_per_step([&] { a1->step(); }, min_seconds));
    with_solid_one = std::min(with_solid_one, seconds_per_step([&] { b1->step(); }, min_seconds));
  }
  const auto& f = coupled.fluid;
  SceneRow row{what, lattice, threads, static_cast<long>(f.nx) * f.ny * f.nz, b->solid()->particle_count(), with_solid,
               plain, static_cast<double>(b->fluid_bytes()), static_cast<double>(b->solid_bytes()),
               stage_seconds_per_step(*b, min_seconds)};
  row.one_thread_step_seconds = with_solid_one;
  row.one_thread_reference_seconds = plain_one;
  std::tie(row.over_reference, row.over_rest) = paired_rounds(*b, *a, *at_rest, rounds, 10);
  return row;
}

}  // namespace

std::vector<SceneRow> run_scene_benchmarks(bool quick, int threads) {
  std::vector<SceneRow> rows;
  const double min_seconds = quick ? 0.5 : 2.0;
  const int rounds = quick ? 10 : 20;  // of the paired rounds (paired_rounds)
  const int n = quick ? 512 : 1024;

  // 1. A fluid-only scene through the builder against the bare kernel, interleaved A/B/A/B.
  {
    Scene s = paper_box(n, threads);
    auto sim = scene::build_simulation(s);
    fluid::FluidLattice<lattice::D2Q7, double> bare(s.fluid);
    // Many short alternating rounds, best of each: on a shared machine a single long round of
    // either side can be disturbed by several percent, more than the difference sought.
    double built = INFINITY, plain = INFINITY;
    for (int round = 0; round < 8; ++round) {
      built = std::min(built, seconds_per_step([&] { sim->step(); }, 0.5 * min_seconds));
      plain = std::min(plain, seconds_per_step([&] { bare.step(); }, 0.5 * min_seconds));
    }
    rows.push_back({"fluid-only scene vs bare kernel", "D2Q7", threads, bare.cells(), 0, built, plain,
                    static_cast<double>(sim->fluid_bytes()), static_cast<double>(sim->solid_bytes())});
  }
  // 2. A solid-only scene (the paper's Fig. 1 kind): no fluid storage at all.
  {
    Scene s = paper_box(n, threads);
    s.with_fluid = false;
    add_sheets(s, 0.1);
    auto sim = scene::build_simulation(s);
    const double t = seconds_per_step([&] { sim->step(); }, min_seconds);
    rows.push_back({"solid-only scene", "D2Q7", threads, 0, sim->solid()->particle_count(), t, 0,
                    static_cast<double>(sim->fluid_bytes()), static_cast<double>(sim->solid_bytes())});
  }
  // 3. Coupled steps at 0.1 and 1 particle per fluid cell, against the fluid-only step.
  for (double per_cell : {0.1, 1.0}) {
    Scene coupled = paper_box(n, threads);
    add_sheets(coupled, per_cell);
    char what[64];
    std::snprintf(what, sizeof what, "coupled, %.1f particles per cell", per_cell);
    rows.push_back(coupled_against_fluid(what, "D2Q7", coupled, min_seconds, rounds));
  }
  // 4. The 3D suspension against its fluid-only box: issue 15's dilute one (0.008 particle per
  // cell), then a denser one in the same box (0.15 per cell). The dilute one's coupling is about
  // 2% of its step, so that its ns a particle, a small difference of two large times, moved by
  // 30-60 ns between runs; the denser one's is about half of its step.
  const int side = quick ? 64 : 96;
  for (int k : {quick ? 2 : 3, quick ? 5 : 8}) {
    char what[64];
    std::snprintf(what, sizeof what, "3D, %d balls of radius 4", k * k * k);
    rows.push_back(coupled_against_fluid(what, "D3Q19", suspension_3d(side, k, threads), min_seconds, rounds));
  }
  return rows;
}

void print_scene_rows(const std::vector<SceneRow>& rows) {
  std::printf("\nscenes (D2Q7 double, and D3Q19 double in the last two): what the builder adds, and what solids cost\n"
              "(a coupled scene's ref: its box without bodies, given the scene's fluid after %d steps)\n",
              kStepsBeforeReference);
  std::printf("%-36s %7s %9s %10s %12s %12s %9s %12s %12s %13s\n", "scene", "threads", "cells", "particles", "ms/step",
              "ref ms/step", "ratio", "fluid MiB", "solid MiB", "ns/particle");
  for (const SceneRow& r : rows) {
    const bool compared = r.reference_seconds > 0;
    const double per_particle =
        r.particles ? 1e9 * (r.step_seconds - (compared && r.cells ? r.reference_seconds : 0)) / r.particles : 0;
    std::printf("%-36s %7d %9ld %10ld %12.3f %12s %9s %12.2f %12.2f %13s\n", r.what.c_str(), r.threads, r.cells,
                r.particles,
                1e3 * r.step_seconds, compared ? std::to_string(1e3 * r.reference_seconds).substr(0, 7).c_str() : "-",
                compared ? std::to_string(r.step_seconds / r.reference_seconds).substr(0, 5).c_str() : "-",
                r.fluid_bytes / 1048576.0, r.solid_bytes / 1048576.0,
                r.particles ? std::to_string(per_particle).substr(0, 6).c_str() : "-");
  }
  // The coupled steps' ns per particle again, by short alternating rounds (paired_rounds), over the
  // reference and over the box at rest (the reference until the reference got the scene's fluid:
  // the difference between the two is the fluid kernel's, not the coupling's).
  std::printf("\n%-36s %7s %30s %30s\n", "ns/particle by paired rounds", "threads", "over ref: median (quartiles)",
              "over box at rest: median (q.)");
  for (const SceneRow& r : rows) {
    if (r.over_reference.median == 0 && r.over_rest.median == 0) continue;
    const double ns = 1e9 / static_cast<double>(r.particles);
    std::printf("%-36s %7d %10.1f (%7.1f, %7.1f) %10.1f (%7.1f, %7.1f)\n", r.what.c_str(), r.threads,
                ns * r.over_reference.median, ns * r.over_reference.low, ns * r.over_reference.high,
                ns * r.over_rest.median, ns * r.over_rest.low, ns * r.over_rest.high);
  }
  // The coupled steps stage by stage, in ns per particle per step (the fluid's too, for scale).
  std::printf("\n%-36s %7s", "coupled step by stage (ns/particle)", "threads");
  for (int k = 0; k < scene::kStageCount; ++k) std::printf(" %8s", scene::stage_name(static_cast<scene::Stage>(k)));
  std::printf(" %9s\n", "coupling");
  for (const SceneRow& r : rows) {
    if (r.stage_seconds[static_cast<int>(scene::Stage::kExchange)] == 0) continue;
    std::printf("%-36s %7d", r.what.c_str(), r.threads);
    double coupling = 0;  // every stage but the fluid's
    for (int k = 0; k < scene::kStageCount; ++k) {
      const double ns = 1e9 * r.stage_seconds[k] / static_cast<double>(r.particles);
      if (static_cast<scene::Stage>(k) != scene::Stage::kFluid) coupling += ns;
      std::printf(" %8.2f", ns);
    }
    std::printf(" %9.2f\n", coupling);
  }
  // Speed-up of each scene (and of its reference step) with threads: against the one-thread steps
  // measured in the same rounds where there are any (coupled scenes), else its one-thread row.
  bool header = false;
  for (const SceneRow& r : rows) {
    if (r.threads == 1) continue;
    for (const SceneRow& one : rows) {
      if (one.threads != 1 || one.what != r.what) continue;
      if (!header)
        std::printf("\n%-36s %7s %12s %16s  %s\n", "speed-up over one thread", "threads", "step", "reference step",
                    "one thread measured");
      header = true;
      const bool side_by_side = r.one_thread_step_seconds > 0;
      const double step = side_by_side ? r.one_thread_step_seconds : one.step_seconds;
      const double reference = side_by_side ? r.one_thread_reference_seconds : one.reference_seconds;
      std::printf("%-36s %7d %11.2fx %15s  %s\n", r.what.c_str(), r.threads, step / r.step_seconds,
                  r.reference_seconds > 0 ? (std::to_string(reference / r.reference_seconds).substr(0, 4) + "x").c_str()
                                          : "-",
                  side_by_side ? "in the same rounds" : "in its own row");
    }
  }
}

void print_scene_rows_json(const std::vector<SceneRow>& rows) {
  std::printf("  \"scenes\": [\n");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const SceneRow& r = rows[k];
    std::printf("    {\"scene\": \"%s\", \"lattice\": \"%s\", \"threads\": %d, \"cells\": %ld, \"particles\": %ld, \"seconds_per_step\": %.6g, "
                "\"reference_seconds_per_step\": %.6g, \"one_thread_seconds_per_step\": %.6g, "
                "\"one_thread_reference_seconds_per_step\": %.6g, \"paired_rounds_over_reference_seconds\": [%.6g, %.6g, %.6g], "
                "\"paired_rounds_over_rest_seconds\": [%.6g, %.6g, %.6g], "
                "\"fluid_bytes\": %.0f, \"solid_bytes\": %.0f, \"stage_seconds_per_step\": {",
                r.what.c_str(), r.lattice.c_str(), r.threads, r.cells, r.particles, r.step_seconds, r.reference_seconds,
                r.one_thread_step_seconds, r.one_thread_reference_seconds, r.over_reference.low,
                r.over_reference.median, r.over_reference.high, r.over_rest.low, r.over_rest.median, r.over_rest.high,
                r.fluid_bytes, r.solid_bytes);
    for (int s = 0; s < scene::kStageCount; ++s)
      std::printf("%s\"%s\": %.6g", s ? ", " : "", scene::stage_name(static_cast<scene::Stage>(s)), r.stage_seconds[s]);
    std::printf("}}%s\n", k + 1 < rows.size() ? "," : "");
  }
  std::printf("  ]\n");
}

}  // namespace lbsolid::bench
