#pragma once
// What the restart tests share (in process, through checkpoint files): a small coupled scene with
// every stage (walls, a moving wall, a body force, a loaded disk) and a bitwise comparison of two
// saved states.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "scene/simulation.h"

namespace lbsolid::scene::testing {

inline Scene coupled_scene(LatticeKind lattice, Precision precision,
                           fluid::StreamingScheme streaming = fluid::StreamingScheme::kInPlace) {
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

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  // memcmp with the null data() of an empty vector is undefined (UBSan), even for zero bytes.
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Bitwise equality of everything a run changes.
inline void expect_same_state(const SimulationState& a, const SimulationState& b) {
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.has_fluid, b.has_fluid);
  EXPECT_EQ(a.fluid.steps, b.fluid.steps);
  EXPECT_EQ(a.fluid.current, b.fluid.current);
  EXPECT_EQ(a.fluid.pulled, b.fluid.pulled);
  EXPECT_EQ(a.fluid.stepped, b.fluid.stepped);
  EXPECT_EQ(a.fluid.buffers, b.fluid.buffers);
  EXPECT_EQ(a.fluid.cells, b.fluid.cells);
  EXPECT_TRUE(same_bytes(a.fluid.populations, b.fluid.populations));
  EXPECT_EQ(a.has_solid, b.has_solid);
  EXPECT_TRUE(same_bytes(a.solid.positions, b.solid.positions));
  EXPECT_TRUE(same_bytes(a.solid.incoming, b.solid.incoming));
  EXPECT_TRUE(same_bytes(a.solid.momentum, b.solid.momentum));
  EXPECT_EQ(a.solid.broken, b.solid.broken);  // BrokenLink's == compares every field exactly
  EXPECT_TRUE(same_bytes(a.solid.shed_momentum, b.solid.shed_momentum));
}

}  // namespace lbsolid::scene::testing
