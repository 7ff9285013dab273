#pragma once
// What the coupling and a fluid pass each other in their batched calls (FluidLattice::
// gather_momenta, add_momenta): nodes, and a node's density and momentum.
#include <array>

#include "fluid/fluid_config.h"

namespace lbsolid::fluid {

// A node of the grid, (x, y, z).
using NodeIndex = std::array<int, 3>;

// rho and rho u = sum_i f_i c_i + F/2 of a node (Moments without the division).
struct DensityMomentum {
  double rho;
  Vec3 momentum;
};

// What the fluid's step and an exchange inside it (in_step_exchange.h) pass each other for up to
// kNodesAtOnce nodes at once (a word of marks), component by component, node k at [k]: so that
// both sides read and write them across nodes in vectors. Given node by node (DensityMomentum and
// D-value gains), the step's blocks of nodes spent most of their time taking vectors apart and
// putting them together (docs/performance.md).
inline constexpr int kNodesAtOnce = 64;
struct NodesFluid {
  alignas(64) double rho[kNodesAtOnce];
  alignas(64) double momentum[3][kNodesAtOnce];
  DensityMomentum node(long k) const { return {rho[k], {momentum[0][k], momentum[1][k], momentum[2][k]}}; }
  void set(long k, const DensityMomentum& m) {
    rho[k] = m.rho;
    for (int a = 0; a < 3; ++a) momentum[a][k] = m.momentum[a];
  }
};
// The momentum each node's fluid gains, axis by axis (D of them used).
struct NodesGain {
  alignas(64) double momentum[3][kNodesAtOnce];
};

}  // namespace lbsolid::fluid
