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

}  // namespace lbsolid::fluid
