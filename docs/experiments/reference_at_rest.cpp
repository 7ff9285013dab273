// A measurement, not part of the build: what the coupled scenes' fluid-only reference costs at
// rest and moving (docs/performance.md, "A reference at rest"). The fluid kernel stores each
// population as its deviation from rest (bgk_collision.h), so a fluid at rest is all zeros.
//   1. the bare kernel (D3Q19 96^3, D2Q7 1024^2, double) at rest, in a uniform flow, and at rest
//      with density 1.001 (nothing zero but the velocity);
//   2. a bench scene (3d: the suspension; 2d: the sheets at 0.1 a cell) against its box at rest
//      and against its box given the scene's fluid after 50 steps, in 40 alternating rounds of 10
//      steps: the medians and quartiles of the rounds' differences in ns a particle.
//   3. order: the suspension over its box with the scene's fluid in ABBA rounds of 10 steps, and
//      in rounds where its box at rest steps just before the coupled segment, or just before the
//      reference segment (what ran just before moves a segment on this VM).
// Build (from the tree's root, after building ./build):
//   g++ -std=c++20 -O3 -DNDEBUG -ffp-contract=off -Icore -Itests docs/experiments/reference_at_rest.cpp \
//     build/core/liblbsolid_core.a -lpthread -o reference_at_rest
//   taskset -c 1 ./reference_at_rest kernel | 3d | 2d | order
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_scenes.h"
#include "fluid/fluid_lattice.h"
#include "lattice/d2q7.h"
#include "lattice/d3q19.h"
#include "scene/simulation.h"

using namespace lbsolid;

template <class Steppable>
double ms_per_step(Steppable& s, int steps) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) s.step();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / steps;
}

template <class L>
void kernel_at_rest(int n, int nz, const char* what) {
  fluid::FluidConfig c;
  c.nx = c.ny = n;
  c.nz = nz;
  fluid::FluidLattice<L, double> rest(c), moving(c), dense(c);
  moving.initialize_uniform(1.0, {1e-3, 2e-4, nz > 1 ? 3e-4 : 0.0});
  dense.initialize_uniform(1.001, {0, 0, 0});
  for (int round = 0; round < 3; ++round)
    std::printf("%s: at rest %.3f, moving %.3f, at rest with density 1.001 %.3f ms a step\n", what,
                ms_per_step(rest, 100), ms_per_step(moving, 100), ms_per_step(dense, 100));
}

// A scene, its box at rest, and its box given the scene's fluid after `steps` coupled steps.
struct SceneAndBoxes {
  std::unique_ptr<scene::Simulation> coupled, rest, moved;
  double particles;
  SceneAndBoxes(const scene::Scene& s, int steps) {
    scene::Scene box = s;
    box.bodies.clear();
    coupled = scene::build_simulation(s);
    rest = scene::build_simulation(box);
    moved = scene::build_simulation(box);
    coupled->run(steps);
    scene::SimulationState state = coupled->save_state();
    state.has_solid = false;
    state.solid = {};
    moved->load_state(state);
    particles = static_cast<double>(coupled->solid()->particle_count());
  }
};

void scene_against_box(bool two_d) {
  scene::Scene s = two_d ? bench::paper_box(1024, 1) : bench::suspension_3d(96, 3, 1);
  if (two_d) bench::add_sheets(s, 0.1);
  SceneAndBoxes sims(s, 50);
  auto &coupled = sims.coupled, &rest = sims.rest, &moved = sims.moved;
  const double particles = sims.particles;
  // 40 rounds of 10 steps each in turn; the medians (and quartiles) of the rounds' differences.
  std::vector<double> over_rest, over_moved;
  for (int round = 0; round < 40; ++round) {
    const double c = ms_per_step(*coupled, 10), a = ms_per_step(*rest, 10), m = ms_per_step(*moved, 10);
    over_rest.push_back(1e6 * (c - a) / particles);
    over_moved.push_back(1e6 * (c - m) / particles);
  }
  auto quartiles = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return std::array<double, 3>{v[v.size() / 4], v[v.size() / 2], v[3 * v.size() / 4]};
  };
  const auto r = quartiles(over_rest), m = quartiles(over_moved);
  std::printf("ns a particle over the box at rest: median %.1f (quartiles %.1f, %.1f); over the box with the scene's "
              "fluid: median %.1f (quartiles %.1f, %.1f)\n", r[1], r[0], r[2], m[1], m[0], m[2]);
}

void order_of_rounds() {
  SceneAndBoxes sims(bench::suspension_3d(96, 3, 1), 30);
  auto &coupled = sims.coupled, &rest = sims.rest, &moved = sims.moved;
  const double particles = sims.particles;
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  for (int repeat = 0; repeat < 2; ++repeat) {
    std::vector<double> abba, rest_before_coupled, rest_before_reference;
    for (int round = 0; round < 20; ++round) {
      const double c1 = ms_per_step(*coupled, 10), m1 = ms_per_step(*moved, 10);
      const double m2 = ms_per_step(*moved, 10), c2 = ms_per_step(*coupled, 10);
      abba.push_back(1e6 * ((c1 + c2) - (m1 + m2)) / 2 / particles);
    }
    for (int round = 0; round < 20; ++round) {
      ms_per_step(*rest, 10);
      const double c = ms_per_step(*coupled, 10), m = ms_per_step(*moved, 10);
      rest_before_coupled.push_back(1e6 * (c - m) / particles);
    }
    for (int round = 0; round < 20; ++round) {
      const double c = ms_per_step(*coupled, 10);
      ms_per_step(*rest, 10);
      const double m = ms_per_step(*moved, 10);
      rest_before_reference.push_back(1e6 * (c - m) / particles);
    }
    std::printf("medians, ns a particle over the box with the scene's fluid: ABBA %.1f; the box at rest just before "
                "the coupled segment %.1f, just before the reference %.1f\n",
                median(abba), median(rest_before_coupled), median(rest_before_reference));
  }
}

int main(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "kernel";
  if (what == "kernel") {
    kernel_at_rest<lattice::D3Q19>(96, 96, "D3Q19 96^3");
    kernel_at_rest<lattice::D2Q7>(1024, 1, "D2Q7 1024^2");
  } else if (what == "order") {
    order_of_rounds();
  } else {
    scene_against_box(what == "2d");
  }
}
