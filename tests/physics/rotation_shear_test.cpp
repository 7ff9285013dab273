// Rotating bodies in a fluid (issue 16). A torque-free disk in simple shear between walls moving
// at -U and +U turns at gamma_dot / 2, the Stokes result for any round body (the strain part of the
// flow exerts no torque on it), when its springs turn with it (solid_system.h); with the paper's
// fixed springs it cannot turn. A spinning disk in fluid at rest hands its spin to the fluid.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fluid/fluid_test_support.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

using testing::report;

constexpr int kSize = 48;        // H = 48 between the halfway bounce-back walls, periodic in x
constexpr double kRadius = 4;    // R / H = 1/12
constexpr double kWallSpeed = 0.01;
constexpr double kShearRate = 2 * kWallSpeed / kSize;  // 4.2e-4 per step

Scene disk_in_shear(bool rotation) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.fluid.nx = kSize;
  s.fluid.ny = kSize;
  s.fluid.omega = 1.0;  // nu = 1/6: Re = gamma_dot R^2 / nu = 0.04
  s.fluid.sides[fluid::kYLow].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYLow].wall_velocity = {-kWallSpeed, 0, 0};
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {kWallSpeed, 0, 0};
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = kRadius;
  disk.centre = {kSize / 2, kSize / 2, 0};  // on a node: no particle halfway between two
  disk.rotation = rotation;
  s.bodies.push_back(disk);
  return s;
}

// The angle the disk turns through over `steps` (the best fit, followed every 100 steps).
double turned(Simulation& sim, int steps) {
  double total = 0, last = sim.body_state(0).orientation;
  for (int t = 0; t < steps; t += 100) {
    sim.run(100);
    const double angle = sim.body_state(0).orientation;
    total += std::remainder(angle - last, 2 * std::numbers::pi);
    last = angle;
  }
  return total;
}

// 10,000 steps for the Couette flow to settle (its slowest mode decays as exp(-pi^2 nu t / H^2):
// e^-7 by then), then the rate over 10,000 more. The flow turns clockwise (u_x grows with y).
// Within 3% (issue 16); measured 1.001, and 0.99-1.02 at omega 0.6 and 1.6 (the rate does not
// depend on the viscosity); 0.964 for R = 8 in H = 96 at omega 1.6, where Re = 0.3.
TEST(RotationInShear, ATorqueFreeDiskTurnsAtHalfTheShearRate) {
  auto sim = build_simulation(disk_in_shear(true));
  EXPECT_EQ(sim->stages().back(), "rotation");
  sim->run(10000);
  const int steps = 10000;
  const double rate = -turned(*sim, steps) / steps;
  report("disk's rate / (gamma_dot / 2)", rate / (kShearRate / 2), 0.03);
  EXPECT_NEAR(rate / (kShearRate / 2), 1.0, 0.03);
  // Its angular velocity from L / I agrees with the turn (a rigid spin).
  EXPECT_NEAR(-sim->body_state(0).angular_velocity[2] / (kShearRate / 2), 1.0, 0.1);
}

// The paper's model: the springs hold the disk at its placed orientation (measured: 2e-11 rad, the
// disk symmetric about the line where the flow is at rest; the rotating disk turns 2.1 rad).
TEST(RotationInShear, WithFixedSpringsTheDiskCannotTurn) {
  auto sim = build_simulation(disk_in_shear(false));
  sim->run(10000);
  const double angle = turned(*sim, 10000);
  report("angle turned with fixed springs (rad)", std::abs(angle), 0.01);
  EXPECT_LT(std::abs(angle), 0.01);
}

// A disk spinning (and drifting) in a periodic 128^2 box of fluid at rest hands its spin to the
// fluid: after 1000 steps it keeps under 1% of its angular momentum, the momentum of fluid and
// solid together is kept to round-off (eqs. 12-14 unchanged by the rotation), and their angular
// momentum about the box's centre to 2% (measured at most 1.0%: the exchange takes momentum from a
// particle and gives it to its node, up to half a spacing away, so angular momentum is not exact
// the way momentum is; later the flow reaches the periodic images, which no box holds).
TEST(RotationInFluid, ASpinningDiskHandsItsSpinToTheFluid) {
  constexpr int n = 128;
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.fluid.nx = n;
  s.fluid.ny = n;
  s.fluid.omega = 1.0;
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 6;
  disk.centre = {n / 2, n / 2, 0};
  disk.velocity = {1e-4, -5e-5, 0};
  disk.angular_velocity = {0, 0, 0.005};  // rim speed 0.03
  disk.rotation = true;
  s.bodies.push_back(disk);
  auto sim = build_simulation(s);
  const auto angular_momenta = [&] {  // solid's own, and fluid + solid about the box centre
    const auto f = sim->fluid_fields();
    double fluid = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const long k = static_cast<long>(y) * n + x;
        fluid += f.density[k] * ((x - n / 2) * f.velocity[3 * k + 1] - (y - n / 2) * f.velocity[3 * k]);
      }
    const auto b = sim->body_state(0);
    const double orbit = b.mass * ((b.centre_of_mass[0] - n / 2) * b.velocity[1] - (b.centre_of_mass[1] - n / 2) * b.velocity[0]);
    return std::pair{b.angular_momentum[2], fluid + b.angular_momentum[2] + orbit};
  };
  const auto [spin0, total0] = angular_momenta();
  const Vec3 p0 = sim->totals().momentum();
  double worst_total = 0, worst_momentum = 0;
  for (int t = 0; t < 1000; t += 100) {
    sim->run(100);
    worst_total = std::max(worst_total, std::abs(angular_momenta().second - total0) / total0);
    const Vec3 p = sim->totals().momentum();
    for (int a = 0; a < 2; ++a) worst_momentum = std::max(worst_momentum, std::abs(p[a] - p0[a]));
  }
  const double spin_left = angular_momenta().first / spin0;
  report("disk's angular momentum left after 1000 steps", spin_left, 0.01);
  report("total angular momentum change (relative)", worst_total, 0.02);
  report("total momentum change", worst_momentum, 1e-12);
  EXPECT_LT(std::abs(spin_left), 0.01);
  EXPECT_LT(worst_total, 0.02);
  EXPECT_LT(worst_momentum, 1e-12);
}

// The torque a body receives (BodyState::torque) is what changes its spin: summed over the steps,
// it equals the change of the body's angular momentum about its centre of mass (the co-rotational
// springs exert none on it). A disk set spinning in a periodic box at rest, as above, and a ball
// spinning about a tilted axis in D3Q19. Measured: 2D, the summed torque -15.88739 against the spin
// change -15.88736 over 1000 steps (1.8e-6 relative), each step's change off its torque by at most
// 2.2e-5 where the torque reaches 5.9; 3D, 2.6e-5 relative over 400 steps. Bound 1e-4 relative: the exchange's
// force on a particle reaches the body through its links, not at the particle itself, so the
// two agree to the force's spread over a spacing, not to round-off.
double spin_change_against_torque(const Scene& s, int steps) {
  auto sim = build_simulation(s);
  EXPECT_EQ(sim->body_state(0).torque, (Vec3{0, 0, 0}));  // no step yet
  const Vec3 l0 = sim->body_state(0).angular_momentum;
  Vec3 impulse{0, 0, 0};
  for (int t = 0; t < steps; ++t) {
    sim->step();
    const Vec3 torque = sim->body_state(0).torque;
    for (int a = 0; a < 3; ++a) impulse[a] += torque[a];
  }
  const Vec3 l = sim->body_state(0).angular_momentum;
  double change = 0, off = 0;
  for (int a = 0; a < 3; ++a) {
    change += (l[a] - l0[a]) * (l[a] - l0[a]);
    off += (impulse[a] - (l[a] - l0[a])) * (impulse[a] - (l[a] - l0[a]));
  }
  EXPECT_GT(std::sqrt(change), 0.1 * std::sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]));  // it spun down
  return std::sqrt(off / change);
}

TEST(RotationInFluid, TheTorqueIsWhatChangesTheSpin) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.fluid.nx = 128;
  s.fluid.ny = 128;
  s.fluid.omega = 1.0;
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 6;
  disk.centre = {64, 64, 0};
  disk.velocity = {1e-4, -5e-5, 0};
  disk.angular_velocity = {0, 0, 0.005};
  disk.rotation = true;
  s.bodies.push_back(disk);
  const double off_2d = spin_change_against_torque(s, 1000);
  report("2D: summed torque against the change of spin (relative)", off_2d, 1e-4);
  EXPECT_LT(off_2d, 1e-4);

  Scene ball = s;
  ball.lattice = LatticeKind::kD3Q19;
  ball.fluid.nx = ball.fluid.ny = ball.fluid.nz = 32;
  ball.bodies[0].radius = 3;
  ball.bodies[0].centre = {16, 16, 16};
  ball.bodies[0].velocity = {1e-4, 0, -5e-5};
  ball.bodies[0].angular_velocity = {0.0036, 0.0048, 0.008};
  const double off_3d = spin_change_against_torque(ball, 400);
  report("3D: summed torque against the change of spin (relative)", off_3d, 1e-4);
  EXPECT_LT(off_3d, 1e-4);
}

// The same in 3D: a ball of radius 3 in a D3Q19 32^3 box, periodic in x and z, between walls moving
// at -+0.01 (Re = gamma_dot R^2 / nu = 0.03, R / H = 0.09). Its turn about z (from its frame, the
// best-fit rotation) over 4000 steps after 2000 for the flow to settle (pi^2 nu t / H^2 = 3 by
// then). Within 3% (issue 16); measured 1.005 (rates over 500 steps scatter by 3%).
TEST(RotationInShear, ATorqueFreeBallTurnsAtHalfTheShearRate) {
  constexpr int n = 32;
  constexpr double u = 0.01, gamma = 2 * u / n;
  Scene s;
  s.lattice = LatticeKind::kD3Q19;
  s.fluid.nx = s.fluid.ny = s.fluid.nz = n;
  s.fluid.omega = 1.0;
  s.fluid.sides[fluid::kYLow].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYLow].wall_velocity = {-u, 0, 0};
  s.fluid.sides[fluid::kYHigh].kind = fluid::WallKind::kMovingWall;
  s.fluid.sides[fluid::kYHigh].wall_velocity = {u, 0, 0};
  solid::BodySpec ball;
  ball.shape = solid::BodyShape::kDisk;  // a ball in 3D
  ball.radius = 3;
  ball.centre = {n / 2, n / 2, n / 2};
  ball.rotation = true;
  s.bodies.push_back(ball);
  auto sim = build_simulation(s);
  const auto angle_about_z = [&] {
    const auto& frame = sim->solid()->body(0).frame;
    return std::atan2(frame[1][0], frame[0][0]);
  };
  sim->run(2000);
  double turned = 0, last = angle_about_z();
  const int steps = 4000;
  for (int t = 0; t < steps; t += 100) {
    sim->run(100);
    const double angle = angle_about_z();
    turned += std::remainder(angle - last, 2 * std::numbers::pi);
    last = angle;
  }
  const double rate = -turned / steps;
  report("3D: ball's rate / (gamma_dot / 2)", rate / (gamma / 2), 0.03);
  EXPECT_NEAR(rate / (gamma / 2), 1.0, 0.03);
}

}  // namespace
}  // namespace lbsolid::scene
