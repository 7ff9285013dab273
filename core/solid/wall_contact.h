#pragma once
// Wall contact (MODEL.md section 2, the paper's Fig. 1): a particle that would cross a wall this
// step receives F_wall = -(1 + e) (P.n) n, with P = Psi + F_other/2 the momentum that would move
// it (Psi alone when nothing else pushes it, MODEL.md's rule). With e = 1 its normal displacement
// this step is exactly zero and, by eq. 10, the energy is unchanged: an exactly elastic bounce.
#include <array>
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

// Adds the contact force to `force` (which holds every other force) for particles about to cross,
// among particles [first, end) (all by default). Each particle reads and writes only its own
// entries, so ranges may run at once.
void add_wall_contact(const ContactWalls& walls, const SolidSystem& solid, std::vector<Vec3>& force, int first = 0,
                      int end = -1);

}  // namespace lbsolid::solid
