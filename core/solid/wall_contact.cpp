#include "solid/wall_contact.h"

namespace lbsolid::solid {

void add_wall_contact(const ContactWalls& walls, const SolidSystem& solid, std::vector<Vec3>& force, int first,
                      int end) {
  if (end < 0) end = solid.particle_count();
  for (int p = first; p < end; ++p) {
    const Vec3& psi = solid.momentum(p);
    const Vec3& r = solid.position(p);
    const double m = solid.mass(p);
    for (int axis = 0; axis < solid.dimension(); ++axis) {
      const double push = psi[axis] + 0.5 * force[p][axis];  // P.n, n along the axis
      const double arrival = r[axis] + push / m;
      const bool through_low = walls.present[2 * axis] && push < 0 && arrival < walls.position[2 * axis];
      const bool through_high = walls.present[2 * axis + 1] && push > 0 && arrival > walls.position[2 * axis + 1];
      if (through_low || through_high) force[p][axis] -= (1.0 + walls.restitution) * push;
    }
  }
}

}  // namespace lbsolid::solid
