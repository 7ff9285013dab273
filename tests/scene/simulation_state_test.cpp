// Checkpoint state: save_state() then load_state() into a simulation built from the same scene
// continues the run bit for bit (N + N steps equal 2N), on every lattice, precision and streaming
// scheme, with fluid, bodies, walls and contact; a state from another scene is refused by name.
#include <gtest/gtest.h>

#include "scene/restart_support.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

using testing::coupled_scene;
using testing::expect_same_state;

struct Case {
  LatticeKind lattice;
  Precision precision;
  fluid::StreamingScheme streaming;
};

class RestartTest : public ::testing::TestWithParam<Case> {};

TEST_P(RestartTest, SavedAndRestoredRunContinuesBitForBit) {
  const auto [lattice, precision, streaming] = GetParam();
  const Scene scene = coupled_scene(lattice, precision, streaming);
  constexpr long n = 25;  // odd, so the in-place scheme is restored mid-pair
  auto straight = build_simulation(scene);
  straight->run(2 * n);

  auto first = build_simulation(scene);
  first->run(n);
  const SimulationState saved = first->save_state();
  auto second = build_simulation(scene);
  second->load_state(saved);
  EXPECT_EQ(second->step_count(), n);
  second->run(n);
  expect_same_state(straight->save_state(), second->save_state());
  // Not trivially equal: the run moved the body and the fluid.
  EXPECT_NE(saved.solid.positions[0][0], second->save_state().solid.positions[0][0]);
}

INSTANTIATE_TEST_SUITE_P(
    AllLatticesAndSchemes, RestartTest,
    ::testing::Values(Case{LatticeKind::kD2Q9, Precision::kDouble, fluid::StreamingScheme::kInPlace},
                      Case{LatticeKind::kD2Q9, Precision::kFloat, fluid::StreamingScheme::kTwoBuffer},
                      Case{LatticeKind::kD2Q7, Precision::kDouble, fluid::StreamingScheme::kTwoBuffer},
                      Case{LatticeKind::kD2Q7, Precision::kFloat, fluid::StreamingScheme::kInPlace},
                      Case{LatticeKind::kD3Q19, Precision::kDouble, fluid::StreamingScheme::kInPlace},
                      Case{LatticeKind::kD3Q19, Precision::kFloat, fluid::StreamingScheme::kTwoBuffer}));

TEST(SimulationState, SolidOnlySceneRestartsBitForBit) {
  Scene s = coupled_scene(LatticeKind::kD2Q9, Precision::kDouble, fluid::StreamingScheme::kInPlace);
  s.with_fluid = false;
  s.fluid.body_force = {0, 0, 0};
  auto straight = build_simulation(s);
  straight->run(40);
  auto first = build_simulation(s);
  first->run(13);
  auto second = build_simulation(s);
  second->load_state(first->save_state());
  second->run(27);
  expect_same_state(straight->save_state(), second->save_state());
}

TEST(SimulationState, StateOfAnotherSceneIsRefusedByName) {
  const Scene scene = coupled_scene(LatticeKind::kD2Q9, Precision::kDouble, fluid::StreamingScheme::kInPlace);
  Scene bigger = scene;
  bigger.fluid.nx = 20;
  auto a = build_simulation(scene);
  auto b = build_simulation(bigger);
  try {
    b->load_state(a->save_state());
    FAIL() << "a state of another grid was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("fluid state:"), std::string::npos) << e.what();
  }
  Scene no_bodies = scene;
  no_bodies.bodies.clear();
  auto c = build_simulation(no_bodies);
  EXPECT_THROW(c->load_state(a->save_state()), std::invalid_argument);
}

}  // namespace
}  // namespace lbsolid::scene
