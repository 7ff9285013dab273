#pragma once
// Wall contact (MODEL.md section 2, the paper's Fig. 1): a particle that would cross a wall this
// step receives F_wall = -(1 + e) (P.n) n, with P = Psi + F_other/2 the momentum that would move
// it (Psi alone when nothing else pushes it, MODEL.md's rule). With e = 1 its normal displacement
// this step is exactly zero and, by eq. 10, the energy is unchanged: an exactly elastic bounce.
#include <array>
#include <cmath>
#include <vector>

#include "solid/solid_system.h"

namespace lbsolid::solid {

struct ContactWalls {
  // Per side (x_low, x_high, y_low, y_high, z_low, z_high): a wall, and where it stands.
  std::array<bool, 6> present{};
  std::array<double, 6> position{};
  double restitution = 1.0;

  bool any() const {
    for (bool p : present)
      if (p) return true;
    return false;
  }
};

// Adds the contact force on particle p to `force` (which holds every other force on it) if p is
// about to cross a wall. Reads only p's own state. D: the solid's dimension.
template <int D>
inline void add_wall_contact(const ContactWalls& walls, const SolidSystem& solid, int p, Vec3& force) {
  const Vec3 psi = solid.momenta().get<D>(p);
  const Vec3 r = solid.positions().get<D>(p);
  const double m = solid.mass(p);
  for (int axis = 0; axis < D; ++axis) {
    const double push = psi[axis] + 0.5 * force[axis];  // P.n, n along the axis
    // Most particles are far from every wall: seen without the division below. A particle the
    // step reaches has a link, so M = K/2 >= 1/2 and it moves |push / M| <= 2 |push| (rounded
    // up by at most one part in 2^53); with both walls more than 4 |push| away (their distances
    // rounded down by as little), its rounded arrival cannot pass either. NaN takes the full test.
    const double reach = 4 * std::abs(push);
    const double low = walls.present[2 * axis] ? r[axis] - walls.position[2 * axis] : INFINITY;
    const double high = walls.present[2 * axis + 1] ? walls.position[2 * axis + 1] - r[axis] : INFINITY;
    if (low > reach && high > reach) continue;
    const double arrival = r[axis] + push / m;
    const bool through_low = walls.present[2 * axis] && push < 0 && arrival < walls.position[2 * axis];
    const bool through_high = walls.present[2 * axis + 1] && push > 0 && arrival > walls.position[2 * axis + 1];
    if (through_low || through_high) force[axis] -= (1.0 + walls.restitution) * push;
  }
}

}  // namespace lbsolid::solid
