// A measurement, not part of the build: what the exchange inside the fluid's step costs in the
// 3D suspension, and the coupled step over its box given the scene's fluid with that work on and
// off (docs/performance.md, "A reference at rest"). It needs a patched copy of the tree, where
// StepNodes returns at once while skip_nodes_mode == 1 (skip_nodes.patch), built as in
// in_process_ab.cpp's header:
//   git worktree add /tmp/hack HEAD && git -C /tmp/hack apply docs/experiments/skip_nodes.patch
//   cmake -S /tmp/hack -B /tmp/hack_build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLBSOLID_BUILD_SERVER=OFF \
//     -DLBSOLID_BUILD_TESTS=OFF -DLBSOLID_BUILD_BENCH=OFF -DLBSOLID_BUILD_EXAMPLES=OFF
//   ninja -C /tmp/hack_build lbsolid_core
//   cd /tmp/hack && g++ -std=c++20 -O3 -DNDEBUG -ffp-contract=off -Icore -Itests \
//     /work/main/docs/experiments/nodes_on_off.cpp /tmp/hack_build/core/liblbsolid_core.a -lpthread -o nodes_on_off
// With the nodes' work off the fluid gets no momentum from the bodies: only the timings mean
// anything.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>
#include "bench/bench_scenes.h"
#include "fluid/fluid_lattice.h"
#include "fluid/fluid_lattice_methods.h"
#include "scene/simulation.h"
using namespace lbsolid;
double ms(scene::Simulation& sim, int steps) {
  auto t = std::chrono::steady_clock::now();
  sim.run(steps);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count() / steps * 1e3;
}
int main() {
  auto sc = bench::suspension_3d(96, 3, 1);
  auto boxs = sc; boxs.bodies.clear();
  auto coupled = scene::build_simulation(sc), box = scene::build_simulation(boxs);
  coupled->run(30);
  { auto st = coupled->save_state(); st.has_solid = false; st.solid = {}; box->load_state(st); }
  const double n = coupled->solid()->particle_count();
  for (int rep = 0; rep < 3; ++rep) {
    std::vector<double> d;
    for (int r = 0; r < 20; ++r) {
      fluid::skip_nodes_mode = 0; const double a1 = ms(*coupled, 10);
      fluid::skip_nodes_mode = 1; const double b1 = ms(*coupled, 10);
      const double b2 = ms(*coupled, 10);
      fluid::skip_nodes_mode = 0; const double a2 = ms(*coupled, 10);
      d.push_back(1e6 * ((a1 + a2) - (b1 + b2)) / 2 / n);
    }
    std::sort(d.begin(), d.end());
    std::printf("the nodes' work inside the step: median %.1f ns a particle (quartiles %.1f, %.1f)\n", d[10], d[5], d[15]);
    std::vector<double> e, f;
    for (int r = 0; r < 20; ++r) {
      fluid::skip_nodes_mode = 1;
      const double a1 = ms(*coupled, 10), b1 = ms(*box, 10), b2 = ms(*box, 10), a2 = ms(*coupled, 10);
      e.push_back(1e6 * ((a1 + a2) - (b1 + b2)) / 2 / n);
      fluid::skip_nodes_mode = 0;
      const double c1 = ms(*coupled, 10), d1 = ms(*box, 10), d2 = ms(*box, 10), c2 = ms(*coupled, 10);
      f.push_back(1e6 * ((c1 + c2) - (d1 + d2)) / 2 / n);
    }
    std::sort(e.begin(), e.end()); std::sort(f.begin(), f.end());
    std::printf("  over the box with its fluid: nodes off %.1f (%.1f, %.1f), nodes on %.1f (%.1f, %.1f)\n", e[10], e[5], e[15], f[10], f[5], f[15]);
  }
}
