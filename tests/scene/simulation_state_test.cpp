// Checkpoint state: save_state() then load_state() into a simulation built from the same scene
// continues the run bit for bit (N + N steps equal 2N), on every lattice, precision and streaming
// scheme, with fluid, bodies, walls and contact; a state from another scene is refused by name.
#include <gtest/gtest.h>

#include <cstring>

#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

Scene coupled_scene(LatticeKind lattice, Precision precision, fluid::StreamingScheme streaming) {
  Scene s;
  s.lattice = lattice;
  s.precision = precision;
  const bool three_d = lattice == LatticeKind::kD3Q19;
  s.fluid.nx = 16;
  s.fluid.ny = 12;
  s.fluid.nz = three_d ? 6 : 1;
  s.fluid.omega = 1.3;
  s.fluid.streaming = streaming;
  s.fluid.body_force = {2e-6, 0, 0};
  s.fluid.sides[fluid::kYLow].kind = fluid::WallKind::kBounceBack;
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {0.01, 0, 0};
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 2;
  disk.centre = {6, 5, three_d ? 3.0 : 0.0};
  disk.load = {1e-4, -2e-4, 0};
  s.bodies.push_back(disk);
  return s;
}

// Bitwise equality of everything a run changes, compared through the saved states.
void expect_identical(const SimulationState& a, const SimulationState& b) {
  ASSERT_EQ(a.step, b.step);
  ASSERT_EQ(a.fluid.populations.size(), b.fluid.populations.size());
  EXPECT_EQ(0, std::memcmp(a.fluid.populations.data(), b.fluid.populations.data(),
                           a.fluid.populations.size() * sizeof(double)));
  EXPECT_EQ(a.fluid.pulled, b.fluid.pulled);
  EXPECT_EQ(a.fluid.current, b.fluid.current);
  ASSERT_EQ(a.solid.positions.size(), b.solid.positions.size());
  ASSERT_EQ(a.solid.incoming.size(), b.solid.incoming.size());
  EXPECT_EQ(0, std::memcmp(a.solid.positions.data(), b.solid.positions.data(), a.solid.positions.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(a.solid.incoming.data(), b.solid.incoming.data(), a.solid.incoming.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(a.solid.momentum.data(), b.solid.momentum.data(), a.solid.momentum.size() * sizeof(Vec3)));
}

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
  expect_identical(straight->save_state(), second->save_state());
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
  expect_identical(straight->save_state(), second->save_state());
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
