// A measurement, not part of the build: steps one of the bench's scenes and prints the time a
// step (with `clock`, each stage's ns a particle), so that two builds can be compared in
// separate processes run alternately, and one build linked several ways (padded_links.sh).
//   scene_steps SCENE STEPS THREADS [clock]   SCENE: 2d01, 2d1 (D2Q7 sheets at 0.1 and 1 a
//   cell), 2dbox (their box without sheets), 3d (the D3Q19 suspension), 3dbox (its box without balls),
//   3d512 (the bench's denser suspension, 512 balls), 3d512z (the same with each ball's x and z
//   swapped: the particles' index order then follows the cells' order, z slowest)
//   (the boxes at rest, which step faster than a moving fluid: docs/performance.md, "A reference at rest")
// Build (from the tree's root, after building ./build):
//   g++ -std=c++20 -O3 -DNDEBUG -ffp-contract=off -Icore -Itests docs/experiments/scene_steps.cpp \
//     build/core/liblbsolid_core.a -lpthread -o scene_steps
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "bench/bench_scenes.h"
#include "scene/simulation.h"

using namespace lbsolid;

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "2d1";
  const int steps = argc > 2 ? std::atoi(argv[2]) : 100;
  const int threads = argc > 3 ? std::atoi(argv[3]) : 1;
  const bool clock = argc > 4 && std::string(argv[4]) == "clock";
  bench::Scene s;
  if (which == "3d" || which == "3dbox") {
    s = bench::suspension_3d(96, 3, threads);
    if (which == "3dbox") s.bodies.clear();
  } else if (which == "3d512" || which == "3d512z") {
    s = bench::suspension_3d(96, 8, threads);
    if (which == "3d512z")
      for (auto& ball : s.bodies) std::swap(ball.centre[0], ball.centre[2]);
  } else if (which == "2d1" || which == "2d01" || which == "2dbox") {
    s = bench::paper_box(1024, threads);
    if (which != "2dbox") bench::add_sheets(s, which == "2d1" ? 1.0 : 0.1);
  } else {
    std::fprintf(stderr, "scene: 2d01, 2d1, 2dbox, 3d, 3dbox, 3d512 or 3d512z, not '%s'\n", which.c_str());
    return 2;
  }
  auto sim = scene::build_simulation(s);
  for (int i = 0; i < 5; ++i) sim->step();  // past the first listings
  sim->time_stages(clock);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) sim->step();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  const long particles = sim->solid() ? sim->solid()->particle_count() : 0;
  std::printf("%s: %ld particles, %.3f ms/step", which.c_str(), particles, 1e3 * seconds);
  if (clock && particles > 0)
    for (int k = 0; k < scene::kStageCount; ++k)
      std::printf(" %s %.2f", scene::stage_name(static_cast<scene::Stage>(k)),
                  1e9 * sim->stage_seconds()[k] / steps / particles);
  std::printf("\n");
}
