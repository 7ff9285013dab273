#include "scene/body_state.h"

#include <algorithm>
#include <cmath>

namespace lbsolid::scene {

namespace {

// x with m x = v by Cramer's rule; zero if m is singular (to round-off of its entries' size).
Vec3 solve_3x3(const double m[3][3], const Vec3& v) {
  const auto det = [](double a, double b, double c, double d, double e, double f, double g, double h, double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const double d = det(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  double scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max(scale, std::abs(m[i][i]));
  if (!(std::abs(d) > 1e-12 * scale * scale * scale)) return {0, 0, 0};
  return {det(v[0], m[0][1], m[0][2], v[1], m[1][1], m[1][2], v[2], m[2][1], m[2][2]) / d,
          det(m[0][0], v[0], m[0][2], m[1][0], v[1], m[1][2], m[2][0], v[2], m[2][2]) / d,
          det(m[0][0], m[0][1], v[0], m[1][0], m[1][1], v[1], m[2][0], m[2][1], v[2]) / d};
}

}  // namespace

BodyState measure_body(const solid::SolidSystem& solid, int body, bool with_orientation) {
  const solid::SolidSystem* s = &solid;
  BodyState state;
  const auto& b = s->body(body);
  Vec3 momentum{0, 0, 0};
  for (int p = b.first; p < b.first + b.count; ++p) {
    const double m = s->mass(p);
    const Vec3 psi = s->momentum(p);
    state.mass += m;
    for (int a = 0; a < 3; ++a) {
      state.centre_of_mass[a] += m * s->position(p)[a];
      momentum[a] += psi[a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    state.centre_of_mass[a] /= state.mass;
    state.velocity[a] = momentum[a] / state.mass;
  }
  double inertia[3][3] = {};
  for (int p = b.first; p < b.first + b.count; ++p) {
    const double m = s->mass(p);
    const Vec3 psi = s->momentum(p);
    Vec3 r;
    for (int a = 0; a < 3; ++a) r[a] = s->position(p)[a] - state.centre_of_mass[a];
    state.angular_momentum[0] += r[1] * psi[2] - r[2] * psi[1];
    state.angular_momentum[1] += r[2] * psi[0] - r[0] * psi[2];
    state.angular_momentum[2] += r[0] * psi[1] - r[1] * psi[0];
    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) inertia[i][j] += m * ((i == j ? r2 : 0.0) - r[i] * r[j]);
  }
  if (s->dimension() == 2) {
    if (inertia[2][2] > 0) state.angular_velocity[2] = state.angular_momentum[2] / inertia[2][2];
    if (with_orientation) state.orientation = s->best_fit_angle(body);
  } else {
    state.angular_velocity = solve_3x3(inertia, state.angular_momentum);
  }
  if (with_orientation) state.orientation_quaternion = s->best_fit_quaternion(body);
  return state;
}

}  // namespace lbsolid::scene
