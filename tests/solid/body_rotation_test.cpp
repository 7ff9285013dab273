// Rotating bodies (issue 16, solid_system.h), no fluid. A disk (and a ball) set spinning keeps
// spinning with its shape when its springs turn with it, and cannot turn when they do not (the
// paper's model);
// without forces its angular momentum sum_p r_p x Psi_p is kept to round-off (the best fit's spring
// forces have no net torque), under loads the momentum changes by exactly the loads (eq. 8), and a
// restored state continues bit for bit (the frame is found from the state alone).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>

#include "fluid/fluid_test_support.h"
#include "solid/body_shape.h"
#include "solid/solid_system.h"

namespace lbsolid::solid {
namespace {

using testing::report;

constexpr double kSpin = 0.01;  // radians per step: a rim speed of 0.05 at radius 5

SolidSystem spinning_disk(bool rotates) {
  SolidSystem solid(2);
  BodySpec disk;
  disk.shape = BodyShape::kDisk;
  disk.radius = 5;
  solid.add_body("disk", body_labels(disk, 2), 1.0, {20, 20, 0}, {0.003, -0.001, 0}, {0, 0, 0}, {0, 0, kSpin},
                 rotates);
  return solid;
}

Vec3 centre_of_mass(const SolidSystem& s) {
  Vec3 c{0, 0, 0};
  double m = 0;
  for (int p = 0; p < s.particle_count(); ++p) {
    m += s.mass(p);
    for (int a = 0; a < 2; ++a) c[a] += s.mass(p) * s.position(p)[a];
  }
  return {c[0] / m, c[1] / m, 0};
}

// sum_p r_p x Psi_p (z), about the origin: what the scheme keeps.
double angular_momentum(const SolidSystem& s) {
  double l = 0;
  for (int p = 0; p < s.particle_count(); ++p)
    l += s.position(p)[0] * s.momentum(p)[1] - s.position(p)[1] * s.momentum(p)[0];
  return l;
}

// sum_p M_p |r_p - c|^2.
double moment_of_inertia(const SolidSystem& s) {
  const Vec3 c = centre_of_mass(s);
  double i = 0;
  for (int p = 0; p < s.particle_count(); ++p)
    i += s.mass(p) * (std::pow(s.position(p)[0] - c[0], 2) + std::pow(s.position(p)[1] - c[1], 2));
  return i;
}

// The largest |r_q - r_p - R Delta0| over the links, R the body's best-fit rotation, and the
// kinetic + spring energy sum_p |Psi_p|^2 / (2 M_p) + sum_links |r_q - r_p - R Delta0|^2 / 2.
std::pair<double, double> deformation_and_energy(const SolidSystem& s) {
  const double angle = s.best_fit_angle(0);
  double worst = 0, energy = 0;
  for (int p = 0; p < s.particle_count(); ++p) {
    const Vec3 psi = s.momentum(p);
    energy += (psi[0] * psi[0] + psi[1] * psi[1]) / (2 * s.mass(p));
    for (int k = 0; k < 2; ++k) {
      const int q = s.neighbour(p, k);
      if (q < 0) continue;
      const Vec3 rest = s.rest_separation(p, k);
      const double ex = s.position(q)[0] - s.position(p)[0] - (std::cos(angle) * rest[0] - std::sin(angle) * rest[1]);
      const double ey = s.position(q)[1] - s.position(p)[1] - (std::sin(angle) * rest[0] + std::cos(angle) * rest[1]);
      worst = std::max(worst, std::hypot(ex, ey));
      energy += 0.5 * (ex * ex + ey * ey);
    }
  }
  return {worst, energy};
}

// The angle turned over `steps` free steps (the best fit followed step by step), with the worst
// changes of the other quantities along the way.
struct FreeSpin {
  double turned = 0, largest_angle = 0;
  double angular_momentum_change = 0;  // relative
  double momentum_change = 0;          // absolute, per component
  double energy_change = 0;            // kinetic + spring, relative
  double deformation = 0;              // largest, in spacings
};

FreeSpin spin_freely(SolidSystem& s, int steps) {
  FreeSpin r;
  const double l0 = angular_momentum(s), e0 = deformation_and_energy(s).second;
  const Vec3 p0 = s.total_momentum();
  double last = s.best_fit_angle(0);
  const std::vector<Vec3> no_force(s.particle_count(), Vec3{0, 0, 0});
  for (int t = 0; t < steps; ++t) {
    s.step(no_force);
    const double angle = s.best_fit_angle(0);
    r.turned += std::remainder(angle - last, 2 * std::numbers::pi);
    last = angle;
    r.largest_angle = std::max(r.largest_angle, std::abs(r.turned));
    r.angular_momentum_change = std::max(r.angular_momentum_change, std::abs(angular_momentum(s) - l0) / std::abs(l0));
    const Vec3 p = s.total_momentum();
    for (int a = 0; a < 2; ++a) r.momentum_change = std::max(r.momentum_change, std::abs(p[a] - p0[a]));
    const auto [deformation, energy] = deformation_and_energy(s);
    r.deformation = std::max(r.deformation, deformation);
    r.energy_change = std::max(r.energy_change, std::abs(energy - e0) / e0);
  }
  return r;
}

// 2600 steps: about four turns. Bounds: the angular momentum and momentum to round-off (measured
// 6e-13 and 2e-14; the sum about the origin cancels terms about 100 times the spin's own share;
// with fixed springs the angular momentum changes by more than 100%); the rest measured (0.65% of a spacing, 0.93% of the
// energy, the same over 20 turns: a leapfrog's bounded energy error and the elastic ringing of a
// start that is not exactly rigid at the rim, whose particles have fewer links), with room of
// about half again.
TEST(BodyRotation, ASpinningDiskKeepsSpinningWithItsShape) {
  SolidSystem s = spinning_disk(true);
  const double omega = (angular_momentum(s) - [&] {
    const Vec3 c = centre_of_mass(s), p = s.total_momentum();
    return c[0] * p[1] - c[1] * p[0];  // the centre of mass's share
  }()) / moment_of_inertia(s);
  const int steps = 2600;
  const FreeSpin r = spin_freely(s, steps);
  report("turned / (L / I x steps) - 1", r.turned / (omega * steps) - 1, 0.01);
  report("angular momentum change (relative)", r.angular_momentum_change, 1e-11);
  report("momentum change", r.momentum_change, 1e-13);
  report("largest deformation in the body's frame (spacings)", r.deformation, 0.01);
  report("kinetic + spring energy change (relative)", r.energy_change, 0.015);
  EXPECT_GT(r.turned, 4 * 2 * std::numbers::pi * 0.95);
  EXPECT_NEAR(r.turned / (omega * steps), 1.0, 0.01);  // it turns as a rigid body with its L and I
  EXPECT_LT(r.angular_momentum_change, 1e-11);
  EXPECT_LT(r.momentum_change, 1e-13);
  EXPECT_LT(r.deformation, 0.01);
  EXPECT_LT(r.energy_change, 0.015);
}

// The same start with fixed springs (the paper's model): the disk is pulled back and rocks about
// its placed orientation (measured: at most 0.032 rad), its angular momentum swinging through zero.
TEST(BodyRotation, WithFixedSpringsTheSameDiskCannotTurn) {
  SolidSystem s = spinning_disk(false);
  const FreeSpin r = spin_freely(s, 2600);
  report("largest angle from the placed shape (rad)", r.largest_angle, 0.05);
  EXPECT_LT(r.largest_angle, 0.05);
  EXPECT_GT(r.angular_momentum_change, 1.0);  // the spin reverses
}

// Random loads on a spinning chain and a rotating sheet (2D) or box (3D): each step changes the
// total momentum by exactly the loads' sum (eq. 8), to round-off.
TEST(BodyRotation, UnderLoadsTheMomentumChangesByTheLoads) {
  for (int dimension : {2, 3}) {
    SolidSystem s(dimension);
    BodySpec chain;
    chain.shape = BodyShape::kChain;
    chain.length = 9;
    BodySpec sheet;
    sheet.size = {5, 4, dimension == 3 ? 3 : 1};
    const double z = dimension == 3 ? 10 : 0;
    s.add_body("chain", body_labels(chain, dimension), 0.8, {10, 10, z}, {0.01, 0, 0}, {0, 0, 0},
               {0, 0.01 * (dimension == 3), 0.02}, true);
    s.add_body("sheet", body_labels(sheet, dimension), 1.0, {30, 10, z}, {0, 0.01, 0}, {0, 0, 0},
               {0.005 * (dimension == 3), 0, -0.01}, true);
    std::mt19937_64 rng(16);
    std::uniform_real_distribution<double> load(-0.01, 0.01);
    std::vector<Vec3> force(s.particle_count());
    double worst = 0;
    for (int t = 0; t < 500; ++t) {
      Vec3 sum{0, 0, 0};
      for (auto& f : force) {
        f = {load(rng), load(rng), dimension == 3 ? load(rng) : 0.0};
        for (int a = 0; a < 3; ++a) sum[a] += f[a];
      }
      const Vec3 before = s.total_momentum();
      s.step(force);
      const Vec3 after = s.total_momentum();
      for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(after[a] - before[a] - sum[a]));
    }
    report(std::to_string(dimension) + "D: |momentum change - sum of loads|", worst, 1e-14);
    EXPECT_LT(worst, 1e-14);
  }
}

// The frame is the best fit of the positions, so a saved state needs nothing more: restored into
// a system built from the same bodies, the spin continues bit for bit.
TEST(BodyRotation, ARestoredSpinContinuesBitForBit) {
  SolidSystem a = spinning_disk(true);
  const std::vector<Vec3> no_force(a.particle_count(), Vec3{0, 0, 0});
  for (int t = 0; t < 333; ++t) a.step(no_force);
  SolidSystem b = spinning_disk(true);
  b.restore(a.state());
  for (int t = 0; t < 200; ++t) {
    a.step(no_force);
    b.step(no_force);
  }
  EXPECT_EQ(a.state().positions, b.state().positions);
  EXPECT_EQ(a.state().incoming, b.state().incoming);
  EXPECT_EQ(a.body(0).angle, b.body(0).angle);
}

// 3D: a ball spinning about a tilted axis. The turn is summed step by step from the best-fit
// rotations (the angle of R_t R_{t-1}^T), the deformation measured in the body's frame.
struct BallSpin {
  double turned = 0, largest_angle = 0, deformation = 0, angular_momentum_change = 0, momentum_change = 0;
  double spin = 0;  // |w| at the start, from L and I about the centre of mass
};

double angle_between(const Rotation& a, const Rotation& b) {  // of a b^T
  double trace = 0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) trace += a[i][k] * b[i][k];
  return std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0));
}

Vec3 angular_momentum_3d(const SolidSystem& s) {
  Vec3 l{0, 0, 0};
  for (int p = 0; p < s.particle_count(); ++p) {
    const Vec3& r = s.position(p);
    const Vec3 psi = s.momentum(p);
    l[0] += r[1] * psi[2] - r[2] * psi[1];
    l[1] += r[2] * psi[0] - r[0] * psi[2];
    l[2] += r[0] * psi[1] - r[1] * psi[0];
  }
  return l;
}

BallSpin spin_ball(bool rotates, int steps) {
  SolidSystem s(3);
  BodySpec ball;
  ball.shape = BodyShape::kDisk;
  ball.radius = 3;
  s.add_body("ball", body_labels(ball, 3), 1.0, {10, 10, 10}, {0.002, 0, -0.001}, {0, 0, 0},
             {0.0036, 0.0048, 0.008}, rotates);  // 0.01 rad a step about (0.36, 0.48, 0.8)
  const Vec3 l0 = angular_momentum_3d(s), p0 = s.total_momentum();
  const double l_size = std::sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]);
  BallSpin r;
  {
    // A lattice ball has a cube's symmetry, so its inertia tensor is (2/3) sum M |r - c|^2 times 1.
    Vec3 c{0, 0, 0};
    double mass = 0, inertia = 0;
    for (int p = 0; p < s.particle_count(); ++p) {
      mass += s.mass(p);
      for (int a = 0; a < 3; ++a) c[a] += s.mass(p) * s.position(p)[a];
    }
    for (int a = 0; a < 3; ++a) c[a] /= mass;
    for (int p = 0; p < s.particle_count(); ++p)
      for (int a = 0; a < 3; ++a) inertia += 2.0 / 3 * s.mass(p) * std::pow(s.position(p)[a] - c[a], 2);
    const Vec3 own{l0[0] - (c[1] * p0[2] - c[2] * p0[1]), l0[1] - (c[2] * p0[0] - c[0] * p0[2]),
                   l0[2] - (c[0] * p0[1] - c[1] * p0[0])};
    r.spin = std::sqrt(own[0] * own[0] + own[1] * own[1] + own[2] * own[2]) / inertia;
  }
  const Rotation start = s.best_fit_rotation(0);
  Rotation last = start;
  const std::vector<Vec3> no_force(s.particle_count(), Vec3{0, 0, 0});
  for (int t = 0; t < steps; ++t) {
    s.step(no_force);
    const Rotation now = s.best_fit_rotation(0);
    r.turned += angle_between(now, last);
    r.largest_angle = std::max(r.largest_angle, angle_between(now, start));
    last = now;
    const Vec3 l = s.total_momentum(), a = angular_momentum_3d(s);
    for (int c = 0; c < 3; ++c) {
      r.momentum_change = std::max(r.momentum_change, std::abs(l[c] - p0[c]));
      r.angular_momentum_change = std::max(r.angular_momentum_change, std::abs(a[c] - l0[c]) / l_size);
    }
    for (int p = 0; p < s.particle_count(); ++p)
      for (int k = 0; k < 3; ++k) {
        const int q = s.neighbour(p, k);
        if (q < 0) continue;
        double e2 = 0;
        for (int c = 0; c < 3; ++c) {
          const double e = s.position(q)[c] - s.position(p)[c] - now[c][k];
          e2 += e * e;
        }
        r.deformation = std::max(r.deformation, std::sqrt(e2));
      }
  }
  return r;
}

// About three turns (2000 steps at 0.0095). Bounds as for the disk: round-off for the momenta;
// the deformation measured (0.44% of a spacing) with room; the turn within 1% of the spin L / I
// gives (the spin asked for, 0.01, is 5% more: a ball has many surface particles, whose links
// start a little slower than a rigid rotation).
TEST(BodyRotation, ASpinningBallKeepsSpinningWithItsShape) {
  const BallSpin r = spin_ball(true, 2000);
  report("3D: turned / (|L| / I x steps)", r.turned / (r.spin * 2000), 0.01);
  report("3D: angular momentum change (relative, per component)", r.angular_momentum_change, 1e-11);
  report("3D: momentum change", r.momentum_change, 1e-13);
  report("3D: largest deformation in the body's frame (spacings)", r.deformation, 0.01);
  EXPECT_NEAR(r.turned / (r.spin * 2000), 1.0, 0.01);
  EXPECT_LT(r.angular_momentum_change, 1e-11);
  EXPECT_LT(r.momentum_change, 1e-13);
  EXPECT_LT(r.deformation, 0.01);
  // With fixed springs it rocks about its placed orientation instead.
  const BallSpin fixed = spin_ball(false, 2000);
  report("3D, fixed springs: largest angle from the start (rad)", fixed.largest_angle, 0.05);
  EXPECT_LT(fixed.largest_angle, 0.05);
}

// The orientation as a quaternion (what the frames report in 3D): a ball spun about
// n = (0.36, 0.48, 0.8) at about 0.0095 rad a step has turned about n by the angle its best-fit
// rotation matrix shows, to round-off; its axis is n to round-off too (measured: the cosine
// between them 1 + 2e-16; a cube-symmetric ball keeps its axis). Past a half turn (400 steps,
// about 3.8 rad) the quaternion keeps w >= 0: the same rotation, 2.48 rad about -n.
TEST(BodyRotation, TheQuaternionIsTheBallsTurnAboutItsSpinAxis) {
  SolidSystem s(3);
  BodySpec ball;
  ball.shape = BodyShape::kDisk;
  ball.radius = 3;
  const Vec3 axis{0.36, 0.48, 0.8};
  s.add_body("ball", body_labels(ball, 3), 1.0, {10, 10, 10}, {0, 0, 0}, {0, 0, 0},
             {0.01 * axis[0], 0.01 * axis[1], 0.01 * axis[2]}, true);
  const std::vector<Vec3> no_force(s.particle_count(), Vec3{0, 0, 0});
  const Rotation identity{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  int stepped = 0;
  for (const auto& [steps, direction] : {std::pair{100, 1.0}, std::pair{400, -1.0}}) {
    for (; stepped < steps; ++stepped) s.step(no_force);
    const Quaternion q = s.best_fit_quaternion(0);
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double angle = 2 * std::acos(std::min(1.0, q[0]));
    const double sin_half = std::sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double cos_axes = (q[1] * axis[0] + q[2] * axis[1] + q[3] * axis[2]) / sin_half;
    std::printf("[ figure   ] 3D quaternion at step %d: angle %.4f rad\n", steps, angle);
    report("3D quaternion: |angle - angle of the rotation matrix|",
           std::abs(angle - angle_between(s.best_fit_rotation(0), identity)), 1e-12);
    report("3D quaternion: 1 - cosine between its axis and the spin's (signed)", 1 - direction * cos_axes, 1e-12);
    EXPECT_GE(q[0], 0.0);
    EXPECT_NEAR(norm, 1.0, 1e-14);
    EXPECT_NEAR(angle, angle_between(s.best_fit_rotation(0), identity), 1e-12);
    EXPECT_NEAR(direction * cos_axes, 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace lbsolid::solid
