// The LB solid's exact properties (MODEL.md section 2, the paper's eqs. 8, 10 and 11), checked
// per particle under random loads for every link count a body can have: chain ends (1 link),
// chain interiors and sheet corners (2), sheet edges (3), sheet interiors (4), box interiors (6).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "fluid/fluid_test_support.h"
#include "solid/body_shape.h"
#include "solid/solid_system.h"

namespace lbsolid::solid {
namespace {

using testing::report;

SolidSystem make_solid(int dimension, std::mt19937_64& rng) {
  SolidSystem solid(dimension);
  std::uniform_real_distribution<double> v(-0.05, 0.05);
  BodySpec sheet;
  sheet.size = {4, 3, dimension == 3 ? 3 : 1};
  const Vec3 vel{v(rng), v(rng), dimension == 3 ? v(rng) : 0.0};
  solid.add_body("sheet", body_labels(sheet, dimension), 1.0, {5, 5, dimension == 3 ? 5.0 : 0.0}, vel, {0, 0, 0});
  BodySpec chain;
  chain.shape = BodyShape::kChain;
  chain.length = 5;
  chain.axis = 1;
  solid.add_body("chain", body_labels(chain, dimension), 0.8, {20, 5, 0}, {0, 0, 0}, {0, 0, 0});
  return solid;
}

struct Before {
  Vec3 psi;
  double energy;
  Vec3 position;
};

void check_invariants(int dimension) {
  std::mt19937_64 rng(2024 + dimension);
  std::uniform_real_distribution<double> load(-0.02, 0.02);
  SolidSystem solid = make_solid(dimension, rng);
  const int n = solid.particle_count();
  const int links = solid.topology().links();
  std::vector<int> seen_links(links + 1, 0);
  for (int p = 0; p < n; ++p) seen_links[static_cast<int>(2 * solid.mass(p))]++;
  for (int k = 1; k <= links; ++k)
    EXPECT_GT(seen_links[k], 0) << "no particle with " << k << " links";

  double worst_momentum = 0, worst_energy = 0, worst_deformation = 0;
  std::vector<Vec3> force(n);
  for (int step = 0; step < 200; ++step) {
    std::vector<Before> before(n);
    for (int p = 0; p < n; ++p) {
      before[p] = {solid.momentum(p), solid.energy(p), solid.position(p)};
      for (int a = 0; a < dimension; ++a) force[p][a] = load(rng);
    }
    solid.step(force);
    for (int p = 0; p < n; ++p) {
      // What p sent out now sits at its neighbours: f_k(p + c_k).
      Vec3 out{0, 0, 0};
      double energy_out = 0;
      for (int k = 0; k < links; ++k) {
        const int q = solid.neighbour(p, k);
        if (q < 0) continue;
        const Vec3& f = solid.incoming(q, k);
        for (int a = 0; a < 3; ++a) {
          out[a] += f[a];
          energy_out += f[a] * f[a];
        }
      }
      double work = 0;
      for (int a = 0; a < 3; ++a) {
        worst_momentum = std::max(worst_momentum, std::abs(out[a] - (before[p].psi[a] + force[p][a])));
        work += (solid.position(p)[a] - before[p].position[a]) * force[p][a];
      }
      worst_energy = std::max(worst_energy, std::abs(energy_out - (before[p].energy + work)));
      for (int k = 0; k < links; ++k) {
        const int q = solid.neighbour(p, k);
        if (q < 0) continue;
        const Vec3& forward = solid.incoming(q, k);
        const Vec3& back = solid.incoming(p, solid.topology().opposite(k));
        for (int a = 0; a < 3; ++a) {
          const double delta = solid.position(q)[a] - solid.position(p)[a] + forward[a] - back[a];
          worst_deformation = std::max(worst_deformation, std::abs(delta - solid.rest_separation(p, k)[a]));
        }
      }
    }
  }
  report("eq. 8 momentum out - (Psi + F), worst", worst_momentum, 1e-12);
  report("eq. 10 energy out - (E + dr.F), worst", worst_energy, 1e-12);
  report("eq. 11 deformation invariant drift, worst", worst_deformation, 1e-12);
  EXPECT_LT(worst_momentum, 1e-12);
  EXPECT_LT(worst_energy, 1e-12);
  EXPECT_LT(worst_deformation, 1e-12);
}

TEST(SolidInvariants, Eqs8To11HoldUnderRandomLoads2D) { check_invariants(2); }
TEST(SolidInvariants, Eqs8To11HoldUnderRandomLoads3D) { check_invariants(3); }

TEST(SolidInvariants, MassIsHalfTheLinkCount) {
  SolidSystem solid(2);
  BodySpec sheet;
  sheet.size = {3, 3, 1};
  solid.add_body("s", body_labels(sheet, 2), 1.0, {0, 0, 0}, {0, 0, 0}, {0, 0, 0});
  // Labels x fastest: corners (2 links), edges (3), the centre (4).
  const double expected[9] = {1, 1.5, 1, 1.5, 2, 1.5, 1, 1.5, 1};
  for (int p = 0; p < 9; ++p) EXPECT_EQ(solid.mass(p), expected[p]) << "particle " << p;
}

TEST(SolidInvariants, RigidStartCarriesMomentumMassTimesVelocity) {
  SolidSystem solid(3);
  BodySpec ball;
  ball.shape = BodyShape::kDisk;
  ball.radius = 2.5;
  const Vec3 v{0.01, -0.02, 0.03};
  solid.add_body("ball", body_labels(ball, 3), 1.0, {0, 0, 0}, v, {0, 0, 0});
  for (int p = 0; p < solid.particle_count(); ++p)
    for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(solid.momentum(p)[a], solid.mass(p) * v[a]);
}

// Without walls or loads a body's centre of mass moves in a straight line at constant velocity,
// however the body deforms (here: started with a velocity gradient across it).
TEST(SolidInvariants, LoneSolidCentreOfMassMovesStraight) {
  for (int dimension : {2, 3}) {
    SolidSystem solid(dimension);
    BodySpec sheet;
    sheet.size = {6, 4, dimension == 3 ? 3 : 1};
    solid.add_body("a", body_labels(sheet, dimension), 1.0, {0, 0, 0}, {0.02, 0.01, 0}, {0, 0, 0});
    solid.add_body("b", body_labels(sheet, dimension), 1.0, {0, 10, 0}, {-0.03, 0.0, 0.01 * (dimension == 3)},
                   {0, 0, 0});
    auto com = [&] {
      Vec3 c{0, 0, 0};
      double m = 0;
      for (int p = 0; p < solid.particle_count(); ++p) {
        m += solid.mass(p);
        for (int a = 0; a < 3; ++a) c[a] += solid.mass(p) * solid.position(p)[a];
      }
      for (int a = 0; a < 3; ++a) c[a] /= m;
      return c;
    };
    double total_mass = 0;
    for (int p = 0; p < solid.particle_count(); ++p) total_mass += solid.mass(p);
    const Vec3 start = com();
    const Vec3 velocity = solid.total_momentum();
    std::vector<Vec3> no_force(solid.particle_count(), Vec3{0, 0, 0});
    double worst = 0;
    for (int step = 1; step <= 1000; ++step) {
      solid.step(no_force);
      const Vec3 c = com();
      for (int a = 0; a < 3; ++a)
        worst = std::max(worst, std::abs(c[a] - (start[a] + step * velocity[a] / total_mass)));
    }
    report("centre of mass off the straight line, worst (" + std::to_string(dimension) + "D)", worst, 1e-12);
    EXPECT_LT(worst, 1e-12);
  }
}

// A 2D solid stores no z components (solid/particle_vectors.h): it refuses one rather than drop it,
// at placement and on restore, and restores its own state exactly.
TEST(SolidInvariants, A2DSolidRefusesZComponents) {
  SolidSystem solid(2);
  BodySpec sheet;
  sheet.size = {3, 2, 1};
  const auto labels = body_labels(sheet, 2);
  EXPECT_THROW(solid.add_body("s", labels, 1.0, {0, 0, 1}, {0, 0, 0}, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(solid.add_body("s", labels, 1.0, {0, 0, 0}, {0, 0, 0.1}, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(solid.add_body("s", labels, 1.0, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0.1, 0, 0}), std::invalid_argument);
  EXPECT_EQ(solid.particle_count(), 0);
  solid.add_body("s", labels, 1.0, {0, 0, 0}, {0.01, 0.02, 0}, {0, 0, 0});
  std::vector<Vec3> force(solid.particle_count(), Vec3{0.001, -0.002, 0});
  solid.step(force);
  const SolidState saved = solid.state();
  for (auto vectors : {&SolidState::positions, &SolidState::incoming, &SolidState::momentum}) {
    SolidState bad = saved;
    (bad.*vectors).back()[2] = 1e-3;
    try {
      solid.restore(bad);
      ADD_FAILURE() << "a z component was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("z component"), std::string::npos) << e.what();
    }
  }
  SolidSystem copy(2);
  copy.add_body("s", labels, 1.0, {0, 0, 0}, {0, 0, 0}, {0, 0, 0});
  copy.restore(saved);
  solid.step(force);
  copy.step(force);
  EXPECT_EQ(copy.state().positions, solid.state().positions);
  EXPECT_EQ(copy.state().incoming, solid.state().incoming);
  EXPECT_EQ(copy.state().momentum, solid.state().momentum);
}

TEST(BodyShape, ShapesAndValidation) {
  BodySpec disk;
  disk.shape = BodyShape::kDisk;
  disk.radius = 2;
  EXPECT_EQ(body_labels(disk, 2).size(), 13u);  // |l| <= 2: 1 + 4 + 4 + 4
  EXPECT_EQ(body_labels(disk, 3).size(), 33u);
  BodySpec chain;
  chain.shape = BodyShape::kChain;
  chain.length = 4;
  chain.axis = 2;
  EXPECT_EQ(body_labels(chain, 3)[3], (Label{0, 0, 3}));
  const auto errors = validate_body_spec(chain, 2, "bodies[0]");
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].axis: must be 0 (x), 1 (y)");
  BodySpec lone;
  lone.shape = BodyShape::kLabels;
  lone.labels = {{0, 0, 0}, {2, 0, 0}};
  const auto lone_errors = validate_body_spec(lone, 2, "bodies[1]");
  ASSERT_EQ(lone_errors.size(), 1u);
  EXPECT_NE(lone_errors[0].find("bodies[1].labels: label (0, 0, 0) has no neighbour"), std::string::npos);
  BodySpec dup = lone;
  dup.labels = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  EXPECT_NE(validate_body_spec(dup, 2, "b")[0].find("appears twice"), std::string::npos);
  BodySpec bad;
  bad.spacing = -1;
  bad.size = {1, 1, 1};
  const auto bad_errors = validate_body_spec(bad, 2, "b");
  ASSERT_EQ(bad_errors.size(), 2u);
  EXPECT_NE(bad_errors[0].find("b.size: a body needs at least 2 particles"), std::string::npos);
  EXPECT_NE(bad_errors[1].find("b.spacing"), std::string::npos);
}

}  // namespace
}  // namespace lbsolid::solid
