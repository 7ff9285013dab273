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

// Work a step does on a range of rows (y + ny z) just before it updates them and just after,
// while their populations are in cache: the coupling gathers its nodes there before and gives
// them momentum after (add_momenta then writes into what the step has just produced). A step
// calls them from its parts, for disjoint ranges; a node's populations before and after the
// update lie in slots that no other node's update touches, so the ranges are independent.
class RowHooks {
 public:
  virtual ~RowHooks() = default;
  virtual void before_rows(long first_row, long end_row) = 0;
  virtual void after_rows(long first_row, long end_row) = 0;
};

}  // namespace lbsolid::fluid
