// Anchored particles (issue 18, MODEL.md section 5): held where they are placed (infinite mass),
// still exchanging momentum with the fluid; the momentum they absorb each step is the force on them.
//
// 1. Static elasticity, no fluid: a chain of N particles along x, anchored at its first particle,
//    every particle loaded by the same transverse F. The model's rules alone fix its equilibrium
//    (derived here from eqs. 6, 7 and 11, not from the code). At rest r does not move, so eq. 7
//    gives Psi_l = -F/2 for every free particle and eq. 6 then sends each arriving vector back
//    negated: f_+(l+1) = -f_-(l). With a_l = f_+(l) (arrived from l - 1) and b_l = f_-(l) (from
//    l + 1): interior a_l + b_l = -F/2 and a_{l+1} = -b_l, so a_{l+1} = a_l + F/2; the free end
//    (one link, M = 1/2) has a_{N-1} = -F/2. Hence a_l = -(N - l) F / 2, b_{l-1} = (N - l) F / 2,
//    and eq. 11, r_l - r_{l-1} = Delta0 - a_l + b_{l-1}, deforms link l by (N - l) F: each link by
//    the load it carries (the particles beyond it), a vector spring of stiffness 1. The tip moves
//    by F N (N - 1) / 2, and the anchor (Psi_0 = b_0 = (N - 1) F / 2) absorbs 2 Psi_0 + F = N F.
//    Checked two ways: started in that state, nothing moves (to round-off) over 2000 steps; started
//    at rest and unloaded shape, the undamped chain oscillates about it (its time average over many
//    periods is that state).
//    A sheet anchored along one edge: every row holds the chain's equilibrium (below).
// 2. In a fluid: an anchored disk in a periodic D2Q9 box driven by a body force g. Total momentum
//    (fluid + solid) changes each step by exactly what enters (g per node) minus what the anchors
//    absorb: checked to round-off over every step. At steady state the anchors hold the whole
//    driving force, g times the number of nodes, within the convergence of the run.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

constexpr int kLinks2D = 4;  // +x, +y, -x, -y (MODEL.md section 2)

Scene anchored_chain(int n, double load) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.with_fluid = false;
  s.fluid.nx = s.fluid.ny = 4 * n;
  s.contact.enabled = false;
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = n;
  chain.axis = 0;
  chain.centre = {2.0 * n, 1.0 * n, 0};
  chain.load = {0, load, 0};
  chain.anchor_labels = {{0, 0, 0}};
  s.bodies.push_back(chain);
  return s;
}

// The equilibrium derived above: position of particle l relative to particle 0, and its vectors.
struct ChainEquilibrium {
  std::vector<double> deflection;  // y_l - y_0 = F sum_{j=1..l} (N - j)
  solid::SolidState state;
};

ChainEquilibrium chain_equilibrium(const Simulation& sim, int n, double load) {
  ChainEquilibrium eq;
  eq.state = sim.save_state().solid;
  const solid::SolidSystem& solid = *sim.solid();
  const solid::Vec3 r0 = solid.position(0);
  double y = 0;
  for (int l = 0; l < n; ++l) {
    if (l > 0) y += (n - l) * load;
    eq.deflection.push_back(y);
    eq.state.positions[l] = {r0[0] + l, r0[1] + y, 0};
    eq.state.incoming[l * kLinks2D + 0] = {0, l > 0 ? -(n - l) * load / 2 : 0.0, 0};         // a_l
    eq.state.incoming[l * kLinks2D + 2] = {0, l < n - 1 ? (n - l - 1) * load / 2 : 0.0, 0};  // b_l
    eq.state.momentum[l] = {0, eq.state.incoming[l * kLinks2D][1] + eq.state.incoming[l * kLinks2D + 2][1], 0};
  }
  return eq;
}

TEST(AnchoredChain, HeldInTheEquilibriumTheLinkLawPredictsNothingMoves) {
  constexpr int n = 12;
  constexpr double load = 1e-4;
  auto sim = build_simulation(anchored_chain(n, load));
  ASSERT_TRUE(sim->solid()->anchored(0));
  ASSERT_FALSE(sim->solid()->anchored(1));
  const ChainEquilibrium eq = chain_equilibrium(*sim, n, load);
  SimulationState start = sim->save_state();
  start.solid = eq.state;
  sim->load_state(start);
  sim->run(2000);
  // Round-off: positions of order n, vectors of order n F; 2000 steps of additions.
  for (int l = 0; l < n; ++l) {
    const solid::Vec3 r = sim->solid()->position(l);
    EXPECT_NEAR(r[0], eq.state.positions[l][0], 1e-12) << "particle " << l;
    EXPECT_NEAR(r[1], eq.state.positions[l][1], 1e-12) << "particle " << l;
  }
  // The tip: F N (N - 1) / 2 against what the positions show.
  EXPECT_NEAR(sim->solid()->position(n - 1)[1] - sim->solid()->position(0)[1], load * n * (n - 1) / 2, 1e-12);
  // The anchor holds the whole load: N F along y, nothing along x.
  const BodyState body = sim->body_state(0);
  EXPECT_NEAR(body.anchor_force[1], n * load, 1e-15);
  EXPECT_NEAR(body.anchor_force[0], 0, 1e-18);
}

TEST(AnchoredChain, StartedAtRestItOscillatesAboutThatEquilibrium) {
  constexpr int n = 8;
  constexpr double load = 1e-4;
  auto sim = build_simulation(anchored_chain(n, load));
  const ChainEquilibrium eq = chain_equilibrium(*sim, n, load);
  const double y0 = sim->solid()->position(0)[1];
  // No damping: the chain swings about its equilibrium for ever, and the time average of each
  // deflection converges to it like (amplitude) / (steps x lowest frequency). The lowest mode of
  // an anchored chain of 8 has a period of about 4 N = 32 steps; the swing is the deflection itself
  // (it starts undeflected), so over 64000 steps (2000 periods) the average should be within about
  // 1e-3 of the deflection (measured: 7-8e-5 at every particle); 1e-3 is the bound.
  std::vector<double> sum(n, 0.0);
  constexpr long kSteps = 64000;
  for (long t = 0; t < kSteps; ++t) {
    sim->step();
    for (int l = 0; l < n; ++l) sum[l] += sim->solid()->position(l)[1] - y0;
  }
  EXPECT_DOUBLE_EQ(sim->solid()->position(0)[1], y0);  // the anchor never moved
  for (int l = 1; l < n; ++l)
    EXPECT_NEAR(sum[l] / kSteps, eq.deflection[l], 1e-3 * eq.deflection[l]) << "particle " << l;
}

// A W x H sheet anchored along its left column (labels (0, j)), the same load F on every particle.
// Eqs. 6-7 at rest need Psi = -F/2 at every free particle whatever its mass (edge particles have
// fewer links) and send each link's arriving vector back negated, so every row can hold the
// chain's equilibrium with N = W while the y links carry nothing: rows deflect alike, columns stay
// straight (eq. 11 with zero y-link vectors), each row's anchor holds W F, the body W H F.
TEST(AnchoredSheet, HeldAlongOneEdgeEachRowIsTheChainsEquilibrium) {
  constexpr int w = 6, h = 4;
  constexpr double load = 1e-4;
  Scene s = anchored_chain(2, load);
  s.bodies[0].shape = solid::BodyShape::kRectangle;
  s.bodies[0].size = {w, h, 1};
  s.bodies[0].anchor_labels.clear();
  for (int j = 0; j < h; ++j) s.bodies[0].anchor_labels.push_back({0, j, 0});
  auto sim = build_simulation(s);
  const solid::SolidSystem& solid = *sim->solid();
  SimulationState start = sim->save_state();
  std::vector<solid::Vec3> expected(solid.particle_count());
  for (int p = 0; p < solid.particle_count(); ++p) {
    const solid::Label l = solid.label(p);
    ASSERT_EQ(solid.anchored(p), l[0] == 0);
    double y = 0;
    for (int m = 1; m <= l[0]; ++m) y += (w - m) * load;
    const solid::Vec3 r = solid.position(p);
    expected[p] = {r[0], r[1] + y, 0};
    start.solid.positions[p] = expected[p];
    const int i = l[0];
    start.solid.incoming[p * kLinks2D + 0] = {0, i > 0 ? -(w - i) * load / 2 : 0.0, 0};
    start.solid.incoming[p * kLinks2D + 1] = {0, 0, 0};
    start.solid.incoming[p * kLinks2D + 2] = {0, i < w - 1 ? (w - i - 1) * load / 2 : 0.0, 0};
    start.solid.incoming[p * kLinks2D + 3] = {0, 0, 0};
    start.solid.momentum[p] = {0, start.solid.incoming[p * kLinks2D][1] + start.solid.incoming[p * kLinks2D + 2][1], 0};
  }
  sim->load_state(start);
  sim->run(2000);
  for (int p = 0; p < solid.particle_count(); ++p) {
    EXPECT_NEAR(solid.position(p)[0], expected[p][0], 1e-12) << "particle " << p;
    EXPECT_NEAR(solid.position(p)[1], expected[p][1], 1e-12) << "particle " << p;
  }
  EXPECT_NEAR(sim->body_state(0).anchor_force[1], w * h * load, 1e-15);
}

TEST(AnchoredDisk, MomentumBalancesToRoundOffAndTheAnchorsHoldTheDrivingForce) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.fluid.nx = 40;
  s.fluid.ny = 30;
  s.fluid.omega = 1.0;
  const double g = 2e-6;
  s.fluid.body_force = {g, 0, 0};
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 4;
  disk.centre = {20.2, 15.3, 0};
  disk.anchored = true;
  s.bodies.push_back(disk);
  auto sim = build_simulation(s);
  const double nodes = s.fluid.nx * s.fluid.ny;
  Vec3 absorbed_total{0, 0, 0};
  Totals before = sim->totals();
  double worst = 0;
  // The drive builds the flow up and the anchors take more and more of it; measured, they hold
  // 0.86 of it after 1000 steps, 0.9994 after 4000 and 0.99998 after 6000 (a settling time of
  // about 600 steps: the viscous time of the gaps between the disk's periodic images).
  constexpr int kSteps = 6000, kAveraged = 500;
  for (int t = 1; t <= kSteps; ++t) {
    sim->step();
    const Vec3 absorbed = sim->body_state(0).anchor_force;
    const Totals now = sim->totals();
    for (int a = 0; a < 2; ++a) {
      const double entered = (a == 0 ? g * nodes : 0.0) - absorbed[a];
      worst = std::max(worst, std::abs(now.momentum()[a] - before.momentum()[a] - entered));
    }
    before = now;
    if (t > kSteps - kAveraged)
      for (int a = 0; a < 3; ++a) absorbed_total[a] += absorbed[a] / kAveraged;
  }
  // Per step, the balance holds to round-off of momenta of order 1 (measured 1.5e-14).
  EXPECT_LT(worst, 1e-13);
  // Steady: the anchors take the whole drive, g per node, within 0.1% (measured 2e-5 short).
  EXPECT_NEAR(absorbed_total[0], g * nodes, 1e-3 * g * nodes);
  // No lift: the periodic array is mirror-symmetric about the flow line through the disk's centre
  // row (measured 1e-14 of the drag).
  EXPECT_NEAR(absorbed_total[1], 0, 1e-6 * g * nodes);
  // The disk's particles never moved.
  const auto& solid = *sim->solid();
  const auto placed = build_simulation(s);
  for (int p = 0; p < solid.particle_count(); ++p) {
    EXPECT_EQ(solid.position(p)[0], placed->solid()->position(p)[0]);
    EXPECT_EQ(solid.position(p)[1], placed->solid()->position(p)[1]);
  }
}

TEST(AnchoredBodies, ValidationNamesTheField) {
  Scene s = anchored_chain(4, 0);
  s.bodies[0].anchor_labels = {{7, 0, 0}};
  std::vector<std::string> errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].anchor_labels: label (7, 0, 0) is not a particle of this body");
  s.bodies[0].anchor_labels = {{0, 0, 0}};
  s.bodies[0].anchored = true;
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].anchor_labels: give either anchored (the whole body) or anchor_labels, not both");
  s.bodies[0].anchor_labels.clear();
  s.bodies[0].rotation = true;
  errors = validate_scene(s);
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0], "bodies[0].rotation: an anchored body cannot rotate (its springs' frame would turn about a fixed point)");
}

}  // namespace
}  // namespace lbsolid::scene
