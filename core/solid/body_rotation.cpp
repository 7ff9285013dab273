// Rotating bodies (solid_system.h, issue 16): the best-fit angle of a body's links, the turn of its
// springs after each step, and the start of a spinning body.
#include <cmath>

#include "solid/solid_system.h"

namespace lbsolid::solid {

Vec3 SolidSystem::rest_offset(int p) const {
  const Body& body = bodies_[body_index_[p]];
  Vec3 offset;
  for (int a = 0; a < 3; ++a) offset[a] = body.spacing * labels_[p][a] - body.rest_centroid[a];
  return offset;
}

double SolidSystem::best_fit_angle(int b) const {
  const Body& body = bodies_[b];
  constexpr int kLinks = 4;
  // Rest links are spacing c_k, k = +x, +y: the cross and dot sums of the angle's atan2.
  double cross = 0, dot = 0;
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < 2; ++k) {
      const int q = neighbours_[static_cast<std::size_t>(p) * kLinks + k];
      if (q < 0) continue;
      const double dx = positions_[q][0] - positions_[p][0], dy = positions_[q][1] - positions_[p][1];
      cross += k == 0 ? dy : -dx;
      dot += k == 0 ? dx : dy;
    }
  return std::atan2(cross, dot);  // the spacing scales both sums alike
}

void SolidSystem::co_rotate(int b) {
  Body& body = bodies_[b];
  body.angle = best_fit_angle(b);
  const double cos_a = std::cos(body.angle), sin_a = std::sin(body.angle);
  constexpr int kLinks = 4;
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < 2; ++k) {  // +x and +y: each link once
      const int q = neighbours_[static_cast<std::size_t>(p) * kLinks + k];
      if (q < 0) continue;
      Vec3& at_q = incoming_[static_cast<std::size_t>(q) * kLinks + k];                      // f_k(q), from p
      Vec3& at_p = incoming_[static_cast<std::size_t>(p) * kLinks + topology_.opposite(k)];  // f_opp(k)(p), from q
      // T = R spacing c_k, and D as the step left it.
      const double tx = k == 0 ? body.spacing * cos_a : -body.spacing * sin_a;
      const double ty = k == 0 ? body.spacing * sin_a : body.spacing * cos_a;
      const double shift[2] = {tx - (positions_[q][0] - positions_[p][0] + at_q[0] - at_p[0]),
                               ty - (positions_[q][1] - positions_[p][1] + at_q[1] - at_p[1])};
      for (int a = 0; a < 2; ++a) {
        at_q[a] += shift[a];
        at_p[a] -= shift[a];
      }
    }
  update_momentum<kLinks>(body.first, body.first + body.count);
}

void SolidSystem::set_spin(int b, const Vec3& velocity, const Vec3& w) {
  const Body& body = bodies_[b];
  const auto rigid_velocity = [&](int p) {
    const Vec3 r = rest_offset(p);
    return Vec3{velocity[0] + w[1] * r[2] - w[2] * r[1], velocity[1] + w[2] * r[0] - w[0] * r[2],
                velocity[2] + w[0] * r[1] - w[1] * r[0]};
  };
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < links_; ++k) {
      const int q = neighbours_[static_cast<std::size_t>(p) * links_ + k];
      if (q < 0) continue;
      // The vector that arrived at q from p along link k is this link's (v_p + v_q)/4.
      const Vec3 vp = rigid_velocity(p), vq = rigid_velocity(q);
      Vec3& f = incoming_[static_cast<std::size_t>(q) * links_ + k];
      for (int a = 0; a < 3; ++a) f[a] = 0.25 * (vp[a] + vq[a]);
    }
}

}  // namespace lbsolid::solid
