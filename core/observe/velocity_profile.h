#pragma once
// The velocity profile u_x(y): u_x averaged over each row, along x (and z in 3D), indexed by the
// row number y (on D2Q7, row y sits at height y sqrt(3)/2).
#include <vector>

namespace lbsolid::observe {

// `Fluid` is a FluidLattice (config() and add_row_velocity_x(y, z, sum)).
template <class Fluid>
std::vector<double> velocity_profile(const Fluid& fluid) {
  const auto& c = fluid.config();
  std::vector<double> profile(c.ny, 0.0);
  for (int y = 0; y < c.ny; ++y) {
    for (int z = 0; z < c.nz; ++z) fluid.add_row_velocity_x(y, z, profile[y]);
    profile[y] /= static_cast<double>(c.nx) * c.nz;
  }
  return profile;
}

}  // namespace lbsolid::observe
