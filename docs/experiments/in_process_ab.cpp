// A measurement, not part of the build: two trees' coupled steps in one process, so that the
// machine's drift between runs and the placement of one process's memory do not decide an A/B of
// a few nanoseconds a particle (issue 15; docs/performance.md, "Rows without nodes"). Copies of
// the bench's coupled scenes are built from each tree, alternately, and stepped in rounds of 10
// steps in turn, with a fluid-only box (arrays) before and after each round; it prints the median
// over rounds of each tree's coupled step over the fluid-only one, and of their difference.
// Its fluid-only box is at rest, which the D3Q19 kernel steps faster than a moving fluid (docs/
// performance.md, "A reference at rest"): the absolute figures carry that, the differences do not.
//
// The old tree's library is built with its namespace renamed, so that both link into one binary
// (the scenes, tests/bench/bench_scenes.h, are this tree's on both sides; run from its root):
//   git worktree add /tmp/old <rev>
//   cmake -S /tmp/old -B /tmp/old_build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLBSOLID_BUILD_SERVER=OFF \
//     -DLBSOLID_BUILD_TESTS=OFF -DLBSOLID_BUILD_BENCH=OFF -DLBSOLID_BUILD_EXAMPLES=OFF \
//     -DCMAKE_CXX_FLAGS=-Dlbsolid=lbsolid_old && cmake --build /tmp/old_build --target lbsolid_core
//   F="-std=c++20 -O3 -DNDEBUG -ffp-contract=off"
//   g++ $F -Dlbsolid=lbsolid_old '-DSIDE(x)=old_##x' -I/tmp/old/core -Itests -c docs/experiments/in_process_ab.cpp -o old.o
//   g++ $F '-DSIDE(x)=new_##x' -Icore -Itests -c docs/experiments/in_process_ab.cpp -o new.o
//   g++ $F -DAB_MAIN -c docs/experiments/in_process_ab.cpp -o main.o
//   g++ main.o old.o new.o /tmp/old_build/core/liblbsolid_core.a build/core/liblbsolid_core.a -lpthread -o ab
//   taskset -c 1 ./ab 3d 20 2        # scene (2d01, 2d1, 3d), rounds, copies of each, threads
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#ifndef AB_MAIN
#include "bench/bench_scenes.h"
#include "scene/simulation.h"

using namespace lbsolid;
using bench::Scene;
namespace {
struct Stepper { std::unique_ptr<scene::Simulation> sim; };
}
// scene: 2d01, 2d1, 3d; fluid_only: no bodies, arrays. Returns an opaque handle.
void* SIDE(make)(const char* which, bool fluid_only, int threads) {
  std::string w = which; Scene s;
  if (w == "3d") {
    s = bench::suspension_3d(96, 3, threads);
  } else {
    s = bench::paper_box(1024, threads);
    bench::add_sheets(s, w == "2d1" ? 1.0 : 0.1);
  }
  if (fluid_only) { s.bodies.clear(); s.fluid.layout = fluid::PopulationLayout::kArrays; }
  auto* st = new Stepper{scene::build_simulation(s)};
  return st;
}
double SIDE(run)(void* h, int steps) {
  auto* st = static_cast<Stepper*>(h);
  auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) st->sim->step();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps;
}
long SIDE(particles)(void* h) { auto* st = static_cast<Stepper*>(h); return st->sim->solid() ? st->sim->solid()->particle_count() : 0; }

#else  // AB_MAIN
void* old_make(const char*, bool, int); double old_run(void*, int); long old_particles(void*);
void* new_make(const char*, bool, int); double new_run(void*, int); long new_particles(void*);
int main(int argc, char** argv) {
  const char* which = argc > 1 ? argv[1] : "3d"; int rounds = argc > 2 ? atoi(argv[2]) : 20; int copies = argc > 3 ? atoi(argv[3]) : 2;
  int threads = argc > 4 ? atoi(argv[4]) : 1;
  std::vector<void*> o, n; void* ref = new_make(which, true, threads);
  for (int c = 0; c < copies; ++c) { o.push_back(old_make(which, false, threads)); n.push_back(new_make(which, false, threads)); }
  const long p = new_particles(n[0]);
  for (auto* h : o) old_run(h, 4); for (auto* h : n) new_run(h, 4); new_run(ref, 4);
  std::vector<double> dold, dnew, diff;
  for (int r = 0; r < rounds; ++r) {
    double f1 = new_run(ref, 10);
    double to = 0, tn = 0;
    for (int c = 0; c < copies; ++c) { if (r % 2) { tn += new_run(n[c], 10); to += old_run(o[c], 10); } else { to += old_run(o[c], 10); tn += new_run(n[c], 10); } }
    double f2 = new_run(ref, 10); double f = (f1 + f2) / 2; to /= copies; tn /= copies;
    dold.push_back(1e9 * (to - f) / p); dnew.push_back(1e9 * (tn - f) / p); diff.push_back(1e9 * (tn - to) / p);
  }
  auto med = [](std::vector<double> v) { std::sort(v.begin(), v.end()); return v[v.size() / 2]; };
  auto q = [](std::vector<double> v, double f) { std::sort(v.begin(), v.end()); return v[(size_t)(f * (v.size() - 1))]; };
  std::printf("%s t%d, %ld particles, %d copies each: over fluid-only ns/particle, medians: old %.1f new %.1f; new-old median %.1f (quartiles %.1f %.1f)\n", which, threads, p, copies,
              med(dold), med(dnew), med(diff), q(diff, 0.25), q(diff, 0.75));
}

#endif  // AB_MAIN
