// Stage timing (what the benchmark reads to show a coupled step stage by stage): it changes
// nothing in the run, times exactly the stages the scene runs, and starts from zero when switched.
#include <gtest/gtest.h>

#include "scene/restart_support.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

using testing::coupled_scene;
using testing::expect_same_state;

double seconds_of(const Simulation& sim, Stage stage) { return sim.stage_seconds()[static_cast<int>(stage)]; }

TEST(StageTiming, ChangesNothingAndTimesTheStagesThatRun) {
  Scene scene = coupled_scene(LatticeKind::kD2Q9, Precision::kDouble);  // walls, loads, contact
  scene.monitor.interval = 4;
  auto timed = build_simulation(scene);
  auto plain = build_simulation(scene);
  timed->time_stages(true);
  timed->run(9);
  plain->run(9);
  expect_same_state(timed->save_state(), plain->save_state());
  // Every stage ran (the monitor at steps 4 and 8), and a clock read apart by real work moves.
  for (int k = 0; k < kStageCount; ++k)
    EXPECT_GT(timed->stage_seconds()[k], 0) << stage_name(static_cast<Stage>(k));
  for (int k = 0; k < kStageCount; ++k) EXPECT_EQ(plain->stage_seconds()[k], 0) << "timing is off by default";
  timed->time_stages(false);
  for (int k = 0; k < kStageCount; ++k) EXPECT_EQ(timed->stage_seconds()[k], 0) << "switching clears the sums";

  // Without fluid nothing is located, exchanged or injected.
  Scene solid_only = scene;
  solid_only.with_fluid = false;
  solid_only.fluid.body_force = {0, 0, 0};
  for (int side : {fluid::kYLow, fluid::kYHigh}) solid_only.fluid.sides[side] = fluid::SideBoundary{};  // periodic
  auto solid = build_simulation(solid_only);
  solid->time_stages(true);
  solid->run(3);
  for (Stage stage : {Stage::kLocate, Stage::kExchange, Stage::kFluid, Stage::kInject})
    EXPECT_EQ(seconds_of(*solid, stage), 0) << stage_name(stage);
  EXPECT_GT(seconds_of(*solid, Stage::kSolid), 0);
}

}  // namespace
}  // namespace lbsolid::scene
