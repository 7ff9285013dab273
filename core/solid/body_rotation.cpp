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

namespace {

// The unit eigenvector of the largest eigenvalue of a symmetric 4 x 4 matrix, by cyclic Jacobi
// rotations (deterministic: the same matrix gives the same vector, bit for bit).
std::array<double, 4> top_eigenvector(std::array<std::array<double, 4>, 4> a) {
  std::array<std::array<double, 4>, 4> v{};
  for (int i = 0; i < 4; ++i) v[i][i] = 1;
  for (int sweep = 0; sweep < 50; ++sweep) {
    double off = 0, scale = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) (i == j ? scale : off) += a[i][j] * a[i][j];
    if (off <= 1e-30 * scale) break;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 4; ++q) {
        if (a[p][q] == 0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 4; ++k) {  // columns p and q of a, then rows
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 4; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 4; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  int top = 0;
  for (int i = 1; i < 4; ++i)
    if (a[i][i] > a[top][top]) top = i;
  return {v[0][top], v[1][top], v[2][top], v[3][top]};
}

Rotation rotation_of(double w, double x, double y, double z) {
  return {{{w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z}}};
}

}  // namespace

double SolidSystem::best_fit_angle(int b) const {
  const Body& body = bodies_[b];
  constexpr int kLinks = 4;
  // Rest links are spacing c_k, k = +x, +y: the cross and dot sums of the angle's atan2.
  double cross = 0, dot = 0;
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < 2; ++k) {
      const int q = neighbours_[static_cast<std::size_t>(p) * kLinks + k];
      if (q < 0) continue;
      const Vec3 rp = position(p), rq = position(q);
      const double dx = rq[0] - rp[0], dy = rq[1] - rp[1];
      cross += k == 0 ? dy : -dx;
      dot += k == 0 ? dx : dy;
    }
  return std::atan2(cross, dot);  // the spacing scales both sums alike
}

Rotation SolidSystem::best_fit_rotation(int b) const {
  if (dimension() == 2) {
    const double angle = best_fit_angle(b);
    const double c = std::cos(angle), s = std::sin(angle);
    return {{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
  }
  const Quaternion q = best_fit_quaternion(b);
  return rotation_of(q[0], q[1], q[2], q[3]);
}

Quaternion SolidSystem::best_fit_quaternion(int b) const {
  if (dimension() == 2) {
    const double half = 0.5 * best_fit_angle(b);  // in (-pi/2, pi/2]: w = cos(half) >= 0
    return {std::cos(half), 0, 0, std::sin(half)};
  }
  // Horn (1987): with S_ij = sum over links of (rest link)_i (current link)_j, the quaternion of
  // the best rotation is the top eigenvector of N(S). The rest links are the unit axes (the
  // spacing scales S as a whole), so S's row k sums the current links along +k.
  const Body& body = bodies_[b];
  constexpr int kLinks = 6;
  double m[3][3] = {};
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < 3; ++k) {
      const int q = neighbours_[static_cast<std::size_t>(p) * kLinks + k];
      if (q < 0) continue;
      const Vec3 rp = position(p), rq = position(q);
      for (int a = 0; a < 3; ++a) m[k][a] += rq[a] - rp[a];
    }
  const double xx = m[0][0], xy = m[0][1], xz = m[0][2], yx = m[1][0], yy = m[1][1], yz = m[1][2], zx = m[2][0],
               zy = m[2][1], zz = m[2][2];
  const auto q = top_eigenvector({{{xx + yy + zz, yz - zy, zx - xz, xy - yx},
                                   {yz - zy, xx - yy - zz, xy + yx, zx + xz},
                                   {zx - xz, xy + yx, -xx + yy - zz, yz + zy},
                                   {xy - yx, zx + xz, yz + zy, -xx - yy + zz}}});
  // q and -q are one rotation (rotation_of is even in q, bit for bit): report the one with w >= 0.
  if (q[0] >= 0) return q;
  return {-q[0], -q[1], -q[2], -q[3]};
}

void SolidSystem::co_rotate(int b) {
  Body& body = bodies_[b];
  body.frame = best_fit_rotation(b);
  if (dimension() == 2) body.angle = best_fit_angle(b);
  const int d = dimension();
  for (int p = body.first; p < body.first + body.count; ++p)
    for (int k = 0; k < d; ++k) {  // the links along +x, +y (, +z): each link once
      const int q = neighbours_[static_cast<std::size_t>(p) * links_ + k];
      if (q < 0) continue;
      double* at_q = incoming_at(q, k);                      // f_k(q), from p
      double* at_p = incoming_at(p, topology_.opposite(k));  // f_opp(k)(p), from q
      const double* rp = position_at(p);
      const double* rq = position_at(q);
      for (int a = 0; a < d; ++a) {
        // T = R spacing c_k (column k of R), less D as the step left it.
        const double shift = body.spacing * body.frame[a][k] - (rq[a] - rp[a] + at_q[a] - at_p[a]);
        at_q[a] += shift;
        at_p[a] -= shift;
      }
    }
  links_ == 6 ? update_momentum<6>(body.first, body.first + body.count)
              : update_momentum<4>(body.first, body.first + body.count);
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
      double* f = incoming_at(q, k);
      for (int a = 0; a < dim_; ++a) f[a] = 0.25 * (vp[a] + vq[a]);
    }
}

}  // namespace lbsolid::solid
