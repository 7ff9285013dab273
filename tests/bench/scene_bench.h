#pragma once
// Scene-level benchmarks (issue: "simulate only the effects a scene calls for"): what the builder
// adds to a fluid-only scene, the memory of a solid-only scene, and the cost of coupled steps.
#include <array>
#include <string>
#include <vector>

#include "scene/stage_clock.h"

namespace lbsolid::bench {

struct SceneRow {
  std::string what;    // which measurement
  std::string lattice;
  int threads = 1;     // the fluid's threads (the solid and the coupling run on the stepping thread)
  long cells = 0;      // fluid cells (0 without fluid)
  long particles = 0;  // solid particles
  double step_seconds = 0;      // best seconds per step
  double reference_seconds = 0; // the step it is compared with (0 if none)
  double fluid_bytes = 0, solid_bytes = 0;
  // Seconds per step in each stage (scene::Stage), measured over separate steps with the stage
  // clock on; all zero where not measured.
  scene::StageClock::Seconds stage_seconds{};
  // With more than one thread, a coupled scene's step and its reference step with one thread,
  // measured in rounds alternating with this row's own (0 where not measured): the speed-up then
  // compares steps taken side by side, not minutes apart on a machine whose speed drifts.
  double one_thread_step_seconds = 0, one_thread_reference_seconds = 0;
  // A coupled scene's extra seconds per step by short alternating rounds (zero where not
  // measured): each round steps the scene against its reference and against its box at rest in
  // ABBA order (paired_rounds), and these are the quartiles of the rounds' differences. Steadier than the difference of two best
  // segments, which is a draw on this VM. Over the box at rest: the reference before the
  // reference got the scene's fluid, so that both can be read.
  struct Quartiles {
    double low = 0, median = 0, high = 0;
  };
  Quartiles over_reference, over_rest;
};

std::vector<SceneRow> run_scene_benchmarks(bool quick, int threads);
// The rows, then the coupled steps stage by stage, then for each scene measured with more than one
// thread its speed-up over one thread.
void print_scene_rows(const std::vector<SceneRow>& rows);
void print_scene_rows_json(const std::vector<SceneRow>& rows);

}  // namespace lbsolid::bench
