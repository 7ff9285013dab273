// Where the D2Q7 bounce-back walls on the x sides stand, measured with a Poiseuille flow along y,
// against what scene::wall_position says (the position wall contact and body placement use).
//
// Along x the D2Q7 rows alternate (core/lattice/d2q7.h): even rows have nodes at x = 0 .. nx - 1,
// odd rows at 1/2 .. nx - 1/2. A bounce-back x wall is therefore a zig-zag. At x_low it cuts the
// horizontal links half-way at x = -1/2 (even rows) and 0 (odd rows), and the slanted links of the
// even rows' first nodes (from 0 towards -1/2) at -1/4; at x_high the horizontal links at nx - 1/2
// and nx, and the slanted links of the odd rows' last nodes (from nx - 1/2 towards nx) at nx - 1/4.
// Only the slanted links carry momentum along the wall, and the cut points average to the same
// place: the walls stand at -1/4 and nx - 1/4, not at -1/2 and nx - 1/2 as on a square lattice.
//
// Measured (Release, -O3 -march=native; ny = 4, periodic in y, converged to a change below 1e-16
// per 1000 steps; the rows of one parity agree exactly and the two parities lie on one curve):
// the steady u_y at each node's true x = x + (y mod 2)/2 is
//     u_y(x) = k [(x + 1/4)(nx - 1/4 - x) - 1/16],   k = g / (2 nu),
// to 4e-4 k or better (BGK at omega 0.7, 1, 1.5, 1.8; TRT at Lambda 3/16 and 1/4; regularized;
// nx 8 to 64). That is the parabola through -1/4 and nx - 1/4 lowered by k/16 = g/(32 nu): the
// zig-zag wall is not flat, and the constant k/16 is its price whatever the operator and omega
// (TRT at Lambda 3/16, exact on a flat wall, does not remove it). A parabola fitted to the profile
// therefore has its roots (nx - sqrt(nx^2 - 1/4))/2 ~ 1/(16 nx) inside -1/4 and nx - 1/4:
//     nx                    8            16           32           64
//     x_low  measured   -0.242179    -0.246092    -0.248047    -0.249023
//            formula    -0.242180    -0.246093    -0.248047    -0.249023
//     x_high measured   nx - 0.257821  nx - 0.253908  nx - 0.251953  nx - 0.250977
// (BGK omega 1, both parities, curvature held at k; every operator and omega above, and each
// parity alone, within 3.5e-5 of these). The issue's -0.247 and nx - 0.253 are these. As the
// channel widens the walls tend to -1/4 and nx - 1/4, which is what wall_position must say and
// what this test checks it says; the bounds below allow twice what the zig-zag's k/16 costs
// (1/(8 nx) on a wall, 1/(2 nx^2) of u_max on the profile), and a wall_position at -1/2 and
// nx - 1/2 misses them by 32x (nx 16) and 64x (nx 32).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fluid/fluid_test_support.h"
#include "scene/scene.h"
#include "scene/simulation.h"

namespace lbsolid::testing {
namespace {

using fluid::CollisionModel;

struct Sample {
  double x, u;  // the node's true x, x + (y mod 2)/2, and its u_y
};

struct WallFit {
  double low = 0, high = 0;    // the parabola's roots: the effective walls
  double curvature_ratio = 1;  // fitted curvature / k (1 when the curvature is held at k)
};

// u = k (x - a)(b - x) with the bulk curvature k = g/(2 nu) held: u/k + x^2 = (a + b) x - a b is a
// straight line in x, so a least-squares line gives a + b and a b, and a, b are its roots.
WallFit fit_walls_at_curvature(const std::vector<Sample>& samples, double k) {
  std::vector<double> xs, ys;
  for (const auto& s : samples) {
    xs.push_back(s.x);
    ys.push_back(s.u / k + s.x * s.x);
  }
  const auto line = fit_line(xs, ys);
  const double sum = line.slope, product = -line.intercept;
  const double root = std::sqrt(sum * sum - 4 * product);
  return {0.5 * (sum - root), 0.5 * (sum + root), 1.0};
}

// u = c0 + c1 t + c2 t^2 (t = x - mean x) by least squares: curvature and walls all free.
WallFit fit_walls_free(const std::vector<Sample>& samples, double k) {
  double mean = 0;
  for (const auto& s : samples) mean += s.x / static_cast<double>(samples.size());
  double m[5] = {0, 0, 0, 0, 0}, r[3] = {0, 0, 0};  // sums of t^n and of t^n u
  for (const auto& s : samples) {
    const double t = s.x - mean;
    double tn = 1;
    for (int n = 0; n < 5; ++n, tn *= t) {
      m[n] += tn;
      if (n < 3) r[n] += tn * s.u;
    }
  }
  auto det = [](double a, double b, double c, double d, double e, double f, double g, double h, double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const double d = det(m[0], m[1], m[2], m[1], m[2], m[3], m[2], m[3], m[4]);
  const double c0 = det(r[0], m[1], m[2], r[1], m[2], m[3], r[2], m[3], m[4]) / d;
  const double c1 = det(m[0], r[0], m[2], m[1], r[1], m[3], m[2], r[2], m[4]) / d;
  const double c2 = det(m[0], m[1], r[0], m[1], m[2], r[1], m[2], m[3], r[2]) / d;
  const double root = std::sqrt(c1 * c1 - 4 * c2 * c0);
  const double t1 = (-c1 + root) / (2 * c2), t2 = (-c1 - root) / (2 * c2);
  return {mean + std::min(t1, t2), mean + std::max(t1, t2), -c2 / k};
}

struct Channel {
  FluidConfig config;
  std::vector<Sample> even, odd, both;  // one row of each parity, and the two together
  double k = 0;                         // g / (2 nu)
  double u_max = 0.01;                  // the centre velocity with walls nx apart
  double row_spread = 0;                // largest u_y difference between rows of one parity
};

// Poiseuille flow along y between bounce-back x walls: periodic y with ny = 4 (even, so the
// staggering survives the wrap, and two rows of each parity).
Channel poiseuille_along_y(int nx, CollisionModel model, double omega) {
  Channel ch;
  FluidConfig& c = ch.config;
  c.nx = nx;
  c.ny = 4;
  c.omega = omega;
  c.collision = model;  // TRT keeps its default Lambda = 3/16
  c.sides[fluid::kXLow].kind = c.sides[fluid::kXHigh].kind = WallKind::kBounceBack;
  const double nu = bgk_viscosity<D2Q7>(omega);
  const double g = 8 * nu * ch.u_max / (nx * nx);
  ch.k = g / (2 * nu);
  c.body_force = {0, g * c.rho0, 0};
  FluidLattice<D2Q7, double> fluid(c);
  auto u_y = [&] {
    std::vector<double> u;
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < nx; ++x) u.push_back(fluid.velocity(x, y)[1]);
    return u;
  };
  // Until u_y changes by less than 1e-16 (1e-14 of u_max) in 1000 steps. The slowest mode decays
  // by exp(-nu pi^2 1000 / nx^2) per 1000 steps, at least 0.67 here (nx = 32, omega = 1.5), so what
  // is left of the start is below 3e-16: far below the figures read off below (>= 1e-8 of u_max).
  std::vector<double> before = u_y();
  for (long done = 0; done < 400000; done += 1000) {
    fluid.run(1000);
    const std::vector<double> now = u_y();
    double change = 0;
    for (std::size_t i = 0; i < now.size(); ++i) change = std::max(change, std::abs(now[i] - before[i]));
    before = now;
    if (change < 1e-16) break;
  }
  for (int y = 0; y < c.ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const Sample s{FluidLattice<D2Q7, double>::position(x, y)[0], fluid.velocity(x, y)[1]};
      ch.row_spread = std::max(ch.row_spread, std::abs(s.u - fluid.velocity(x, y % 2)[1]));
      if (y >= 2) continue;
      (y == 0 ? ch.even : ch.odd).push_back(s);
      ch.both.push_back(s);
    }
  return ch;
}

scene::Scene d2q7_scene(const FluidConfig& fluid) {
  scene::Scene s;
  s.lattice = scene::LatticeKind::kD2Q7;
  s.fluid = fluid;
  return s;
}

struct Case {
  CollisionModel model;
  double omega;
};
constexpr Case kCases[] = {{CollisionModel::kBgk, 0.7}, {CollisionModel::kBgk, 1.0}, {CollisionModel::kBgk, 1.5},
                           {CollisionModel::kTrt, 0.7}, {CollisionModel::kTrt, 1.0}, {CollisionModel::kTrt, 1.5}};

// The walls a Poiseuille flow along y sees, fitted to each row parity and to both, lie where
// wall_position says, within 1/(8 nx): twice the 1/(16 nx) by which the zig-zag's constant k/16
// pulls the fitted roots inside (header). wall_position at -1/2 and nx - 1/2 is 0.25 off.
TEST(D2Q7XWalls, PoiseuilleAlongYSeesTheWallsWhereWallPositionSays) {
  for (int nx : {16, 32}) {
    const double wall_bound = 1.0 / (8 * nx), curvature_bound = 1e-4;
    double worst_wall = 0, worst_curvature = 0;
    for (const Case& cs : kCases) {
      const Channel ch = poiseuille_along_y(nx, cs.model, cs.omega);
      const scene::Scene scene = d2q7_scene(ch.config);
      const double low = scene::wall_position(scene, fluid::kXLow);
      const double high = scene::wall_position(scene, fluid::kXHigh);
      const std::string label = std::string(fluid::collision_model_name(cs.model)) + " omega " +
                                std::to_string(cs.omega) + ", nx " + std::to_string(nx);
      // y-uniform per parity, so one row stands for its parity: measured exactly 0; bound 1e-12 of
      // u_max, round-off for builds that compute the rows' cells in other orders.
      EXPECT_LT(ch.row_spread, 1e-12 * ch.u_max) << label;
      const char* names[3] = {"even rows", "odd rows", "both parities"};
      const std::vector<Sample>* sets[3] = {&ch.even, &ch.odd, &ch.both};
      double wall = 0, curvature = 0;  // this case's largest misses
      for (int s = 0; s < 3; ++s) {
        const WallFit held = fit_walls_at_curvature(*sets[s], ch.k);
        const WallFit free = fit_walls_free(*sets[s], ch.k);
        std::printf("[ figure   ] %s, %s: walls at %.6f and nx %+.6f (curvature held), %.6f and nx %+.6f "
                    "(free, curvature / k - 1 = %+.1e); wall_position: %.4f and nx %+.4f\n",
                    label.c_str(), names[s], held.low, held.high - nx, free.low, free.high - nx,
                    free.curvature_ratio - 1, low, high - nx);
        for (const WallFit& f : {held, free})
          wall = std::max({wall, std::abs(f.low - low), std::abs(f.high - high)});
        curvature = std::max(curvature, std::abs(free.curvature_ratio - 1));
      }
      EXPECT_LT(wall, wall_bound) << label << ": a fitted wall is this far from wall_position (" << low << ", "
                                  << high << ")";
      // The bulk curvature is g/nu: the free fit reads the same parabola, in each parity and in
      // both (not a compromise between them). Measured at most 6e-6 (nx 16), 2e-6 (nx 32); bound 1e-4.
      EXPECT_LT(curvature, curvature_bound) << label;
      worst_wall = std::max(worst_wall, wall);
      worst_curvature = std::max(worst_curvature, curvature);
    }
    // Measured: 4.0e-3 (nx 16), 2.0e-3 (nx 32), the 1/(16 nx) of the header.
    report("D2Q7 nx " + std::to_string(nx) + ": largest |fitted wall - wall_position|", worst_wall, wall_bound);
    report("D2Q7 nx " + std::to_string(nx) + ": largest |fitted curvature / k - 1|", worst_curvature,
           curvature_bound);
  }
}

// The profile against the parabola through wall_position's walls, k (x - a)(b - x): it differs by
// the zig-zag's k/16 (1/(4 nx^2) of u_max: 9.8e-4 at nx 16, 2.4e-4 at nx 32), and beyond that
// by little: against k [(x - a)(b - x) - 1/16] what is left is a constant fraction of k (it does
// not shrink with nx in units of k, only in units of u_max = k nx^2 / 4) that depends on the
// operator and omega, largest for BGK at omega 0.7 and TRT at omega 1.5.
// Measured (Release): at most 9.81e-4 and 2.45e-4 of u_max for the parabola; 2.9e-4 k (4.6e-6
// and 1.15e-6 of u_max at nx 16 and 32) for the parabola lowered by k/16, 1.9e-5 k to 2.9e-4 k
// over the six cases. Bounds: 1/(2 nx^2) of u_max for the parabola (twice the k/16; walls at -1/2
// and nx - 1/2 would miss by 1/nx = 6.3e-2 at nx 16) and 1e-3 k for the lowered one (3.4x the
// largest; a steady figure, converged far below it, and 1/62 of the k/16 it refines).
TEST(D2Q7XWalls, ProfileIsTheParabolaThroughWallPositionLessTheZigZagOffset) {
  for (int nx : {16, 32}) {
    const double parabola_bound = 1.0 / (2.0 * nx * nx);
    double worst_parabola = 0, worst_lowered = 0;
    for (const Case& cs : kCases) {
      const Channel ch = poiseuille_along_y(nx, cs.model, cs.omega);
      const scene::Scene scene = d2q7_scene(ch.config);
      const double a = scene::wall_position(scene, fluid::kXLow), b = scene::wall_position(scene, fluid::kXHigh);
      const double lowered_bound = 1e-3 * ch.k / ch.u_max;  // 1e-3 k, in units of u_max
      double parabola = 0, lowered = 0;
      for (const Sample& s : ch.both) {
        const double p = ch.k * (s.x - a) * (b - s.x);
        parabola = std::max(parabola, std::abs(s.u - p) / ch.u_max);
        lowered = std::max(lowered, std::abs(s.u - (p - ch.k / 16)) / ch.u_max);
      }
      const std::string label = std::string(fluid::collision_model_name(cs.model)) + " omega " +
                                std::to_string(cs.omega) + ", nx " + std::to_string(nx);
      std::printf("[ figure   ] %s: max |u - parabola| / u_max = %.3e, less k/16: %.3e\n", label.c_str(), parabola,
                  lowered);
      EXPECT_LT(parabola, parabola_bound) << label;
      EXPECT_LT(lowered, lowered_bound) << label;
      worst_parabola = std::max(worst_parabola, parabola);
      worst_lowered = std::max(worst_lowered, lowered * ch.u_max / ch.k);
    }
    report("D2Q7 nx " + std::to_string(nx) + ": max |u - parabola through wall_position| / u_max", worst_parabola,
           parabola_bound);
    report("D2Q7 nx " + std::to_string(nx) + ": max |u - (parabola - k/16)| / k", worst_lowered, 1e-3);
  }
}

// wall_position moves only the D2Q7 x sides: the D2Q7 y sides stay half a row beyond the first and
// last rows, and the square lattices' sides at -1/2 and n - 1/2.
TEST(D2Q7XWalls, OtherSidesAndLatticesKeepTheirHalfWayWalls) {
  scene::Scene s;
  s.fluid.nx = 10;
  s.fluid.ny = 6;
  s.fluid.nz = 4;
  for (auto lattice : {scene::LatticeKind::kD2Q9, scene::LatticeKind::kD3Q19, scene::LatticeKind::kD2Q7}) {
    s.lattice = lattice;
    const bool hex = lattice == scene::LatticeKind::kD2Q7;
    const double dy = hex ? D2Q7::row_spacing : 1.0;
    EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kXLow), hex ? -0.25 : -0.5);
    EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kXHigh), hex ? 9.75 : 9.5);
    EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kYLow), -0.5 * dy);
    EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kYHigh), 5.5 * dy);
    if (lattice == scene::LatticeKind::kD3Q19) {
      EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kZLow), -0.5);
      EXPECT_DOUBLE_EQ(scene::wall_position(s, fluid::kZHigh), 3.5);
    }
  }
}

// Contact and placement follow: a D2Q7 sheet sent at an x wall stops before -1/4 (with the walls
// at -1/2 its leftmost column reached -0.48 before the contact), and a body reaching x = -0.3 is
// refused where it was accepted before.
TEST(D2Q7XWalls, ContactAndPlacementUseTheZigZagWall) {
  scene::Scene s;
  s.lattice = scene::LatticeKind::kD2Q7;
  s.with_fluid = false;
  s.fluid.nx = 12;
  s.fluid.ny = 8;
  s.fluid.sides[fluid::kXLow].kind = s.fluid.sides[fluid::kXHigh].kind = WallKind::kBounceBack;
  solid::BodySpec sheet;
  sheet.size = {3, 3, 1};
  sheet.centre = {4, 4, 0};           // leftmost column at x = 3
  sheet.velocity = {-0.29, 0.0, 0};  // at 3 - 0.29 n: 0.10, -0.19, then -0.48 would cross -1/4
  s.bodies.push_back(sheet);
  ASSERT_TRUE(scene::validate_scene(s).empty());
  auto sim = scene::build_simulation(s);
  const double low = scene::wall_position(s, fluid::kXLow), high = scene::wall_position(s, fluid::kXHigh);
  double lowest = HUGE_VAL, highest = -HUGE_VAL, fastest_right = 0;
  for (int step = 0; step < 120; ++step) {
    sim->step();
    fastest_right = std::max(fastest_right, sim->body_state(0).velocity[0]);
    for (int p = 0; p < sim->solid()->particle_count(); ++p) {
      lowest = std::min(lowest, sim->solid()->position(p)[0]);
      highest = std::max(highest, sim->solid()->position(p)[0]);
    }
  }
  std::printf("[ figure   ] D2Q7 sheet between x walls at %.2f and %.2f: x from %.4f to %.4f\n", low, high, lowest,
              highest);
  EXPECT_GT(lowest, -0.25);
  EXPECT_LT(lowest, 0.0);  // it did come within reach of the wall
  EXPECT_LT(highest, s.fluid.nx - 0.25);
  EXPECT_GT(fastest_right, 0.1);  // and bounced

  s.bodies[0].velocity = {0, 0, 0};
  s.bodies[0].centre = {0.7, 4, 0};  // leftmost column at x = -0.3: beyond -1/4
  const auto errors = scene::validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind("bodies[0].centre: particle at (-0.3, 3) lies on or beyond the x_low wall (at -0.25", 0), 0u)
      << errors[0];
}

}  // namespace
}  // namespace lbsolid::testing
