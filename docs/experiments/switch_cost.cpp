// A measurement, not part of the build: does a coupled 3D step pay for the simulation run just
// before it? The bench's paired rounds run 10 steps of the coupled scene after 20 of its box; here
// each of those 10 steps is timed alone, after 20 steps of the box given the scene's fluid or
// after 20 of the coupled scene's own (docs/performance.md, "A denser 3D suspension in the bench").
//   switch_cost [K [ROUNDS]]   K x K x K balls of radius 4 in the bench's 96^3 box (default 8)
// Build (from the tree's root, after building ./build):
//   g++ -std=c++20 -O3 -DNDEBUG -ffp-contract=off -Icore -Itests docs/experiments/switch_cost.cpp \
//     build/core/liblbsolid_core.a -lpthread -o switch_cost
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include "bench/bench_scenes.h"
#include "scene/simulation.h"
using namespace lbsolid;
int main(int argc, char** argv) {
  const int k = argc > 1 ? std::atoi(argv[1]) : 8;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 10;
  bench::Scene s = bench::suspension_3d(96, k, 1);
  bench::Scene box = s;
  box.bodies.clear();
  auto coupled = scene::build_simulation(s);
  auto ref = scene::build_simulation(box);
  coupled->run(30);
  auto st = coupled->save_state();
  st.has_solid = false;
  st.solid = {};
  ref->load_state(st);
  const long n = coupled->solid()->particle_count();
  auto timed = [&](int steps, std::vector<double>& per) {
    for (int i = 0; i < steps; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      coupled->step();
      per[i] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  };
  for (int after_ref : {1, 0, 1, 0}) {
    std::vector<double> per(10, 0.0);
    for (int r = 0; r < rounds; ++r) {
      if (after_ref) ref->run(20);
      else coupled->run(20);
      timed(10, per);
    }
    std::printf("%s: ms a step, steps 1..10 of a segment (mean of %d):", after_ref ? "after the box" : "after itself ", rounds);
    for (double t : per) std::printf(" %.2f", 1e3 * t / rounds);
    // Against steps 3, 5, 7, 9: the in-place steps alternate a local and a pulling step, whose
    // times differ by 5-10%.
    double same_kind = 0;
    for (int i = 2; i < 10; i += 2) same_kind += per[i];
    std::printf("  | step 1 over steps 3, 5, 7, 9: %.1f ns a particle\n", 1e9 * (per[0] - same_kind / 4) / rounds / n);
  }
}
