// Fracture (issue 18, MODEL.md section 5): a link breaks when the force it carries passes the
// body's threshold. The force a link carries is its extension e (eq. 11: a vector spring of
// stiffness 1, tests/physics/anchored_test.cpp checks that law in equilibrium). No fluid here: the
// predictions come from the solid's own wave rule.
//
// 1. A chain pulled apart by opposite loads +-F at its ends, suddenly applied. In 1D the LB wave
//    rule (eq. 6) moves vectors one link per step without dispersion, so it is d'Alembert's
//    solution: a tension front F runs in from each end, and where the two meet (the middle link,
//    after N/2 steps) the tension doubles to 2F, and never exceeds it. So with threshold T: for
//    T/2 < F < T the middle link breaks at step N/2 and no other; for F < T/2 nothing ever breaks;
//    for F > T the front itself breaks every link it reaches.
// 2. A chain hitting a wall (contact, e = 1) at speed v: the front particle stops, and each step
//    the compression front stops one more particle (M = 1) moving at v, so the link behind the
//    front carries a force v: it breaks for v > T and not below.
//    The stretch criterion (|r_q - r_p| / spacing - 1) reads the same extension over the spacing,
//    and never breaks a link in compression.
// 3. A notched sheet pulled apart breaks from the notch's tip, across to the other edge, at a load
//    the same sheet without a notch carries.
// 4. Breaking keeps linear momentum exact (each removed vector goes back to its own particle as an
//    impulse of that step) and leaves every particle with M = K/2 of the links it still has.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

// A free chain of n particles along x, loaded by -F at its first and +F at its last particle.
Scene pulled_chain(int n, double pull, double threshold) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.with_fluid = false;
  s.fluid.nx = s.fluid.ny = 8 * n;
  s.contact.enabled = false;
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = n;
  chain.centre = {4.0 * n, 4.0 * n, 0};
  chain.point_loads = {{{0, 0, 0}, {-pull, 0, 0}}, {{n - 1, 0, 0}, {pull, 0, 0}}};
  chain.fracture.max_force = threshold;
  s.bodies.push_back(chain);
  return s;
}

constexpr int kChain = 20;       // the middle link joins particles 9 and 10
constexpr double kThreshold = 1e-3;

TEST(ChainPulledApart, JustAboveHalfTheThresholdTheMiddleLinkBreaksWhenTheFrontsMeet) {
  auto sim = build_simulation(pulled_chain(kChain, 0.51 * kThreshold, kThreshold));
  EXPECT_EQ(sim->stages(), (std::vector<std::string>{"fracture", "loads", "solid"}));
  sim->run(4000);  // 100 round trips of the fronts
  const auto& broken = sim->solid()->broken_links();
  ASSERT_EQ(broken.size(), 1u);
  EXPECT_EQ(broken[0].particle, kChain / 2 - 1);
  EXPECT_EQ(broken[0].link, 0);  // +x
  // The fronts, one link a step, meet after N/2 steps; the next step's test finds the link past T.
  EXPECT_EQ(broken[0].step, kChain / 2 + 1);
  EXPECT_DOUBLE_EQ(broken[0].position[0], 4.0 * kChain);  // the chain's middle
}

TEST(ChainPulledApart, JustBelowHalfTheThresholdNothingBreaks) {
  auto sim = build_simulation(pulled_chain(kChain, 0.49 * kThreshold, kThreshold));
  sim->run(4000);
  EXPECT_TRUE(sim->solid()->broken_links().empty());
}

TEST(ChainPulledApart, AboveTheThresholdTheFrontsBreakEveryLinkAndShedEveryParticle) {
  auto sim = build_simulation(pulled_chain(kChain, 1.01 * kThreshold, kThreshold));
  sim->run(kChain);
  const auto& solid = *sim->solid();
  const auto& broken = solid.broken_links();
  ASSERT_EQ(broken.size(), static_cast<std::size_t>(kChain - 1));
  // The end links first (in step 2, the first that starts with a stretched link), then one link a
  // step from each end inwards.
  for (std::size_t i = 0; i < broken.size(); ++i) {
    const int from_end = static_cast<int>(i) / 2;
    const int expected = i % 2 == 0 ? from_end : kChain - 2 - from_end;
    EXPECT_EQ(broken[i].particle, expected) << "break " << i;
    EXPECT_EQ(broken[i].step, from_end + 2) << "break " << i;
  }
  for (int p = 0; p < kChain; ++p) EXPECT_TRUE(solid.shed(p)) << "particle " << p;
  // Every particle shed with what it held: all the momentum is booked there; the loads on the
  // ends were opposite, so it sums to zero.
  EXPECT_NEAR(sim->totals().momentum()[0], 0, 1e-17);
  EXPECT_EQ(solid.total_momentum()[0], 0.0);  // nothing is left stepped
}

// The same in 3D (cubic topology, six links), along z: the link from particle 9 along +z (link 2).
TEST(ChainPulledApart, InThreeDimensionsAlongZTheMiddleLinkBreaksAlike) {
  Scene s = pulled_chain(kChain, 0.51 * kThreshold, kThreshold);
  s.lattice = LatticeKind::kD3Q19;
  s.fluid.nz = 8 * kChain;
  auto& chain = s.bodies[0];
  chain.axis = 2;
  chain.centre = {4.0 * kChain, 4.0 * kChain, 4.0 * kChain};
  chain.point_loads = {{{0, 0, 0}, {0, 0, -0.51 * kThreshold}}, {{0, 0, kChain - 1}, {0, 0, 0.51 * kThreshold}}};
  auto sim = build_simulation(s);
  sim->run(400);
  const auto& broken = sim->solid()->broken_links();
  ASSERT_EQ(broken.size(), 1u);
  EXPECT_EQ(broken[0].particle, kChain / 2 - 1);
  EXPECT_EQ(broken[0].link, 2);  // +z
  EXPECT_EQ(broken[0].step, kChain / 2 + 1);
  EXPECT_DOUBLE_EQ(broken[0].position[2], 4.0 * kChain);
  EXPECT_EQ(sim->solid()->mass(kChain / 2 - 1), 0.5);  // an end now: one link
}

// The stretch criterion: the middle link's extension 2F (stiffness 1) over the spacing s. At s = 2
// it breaks past F = max_stretch, not below; the force criterion's prediction (2F > T) would say
// otherwise, so the spacing is really divided out.
TEST(ChainPulledApart, AStretchThresholdReadsTheExtensionPerSpacing) {
  constexpr double kStretch = 1e-3;
  for (const double ratio : {0.98, 1.02}) {
    Scene s = pulled_chain(kChain, ratio * kStretch, 0);
    s.fluid.nx = s.fluid.ny = 16 * kChain;
    s.bodies[0].spacing = 2;
    s.bodies[0].centre = {8.0 * kChain, 8.0 * kChain, 0};
    s.bodies[0].fracture.max_stretch = kStretch;
    auto sim = build_simulation(s);
    sim->run(4000);
    const auto& broken = sim->solid()->broken_links();
    if (ratio < 1) {
      EXPECT_TRUE(broken.empty()) << "F / max_stretch = " << ratio;
    } else {
      ASSERT_EQ(broken.size(), 1u) << "F / max_stretch = " << ratio;
      EXPECT_EQ(broken[0].particle, kChain / 2 - 1);
      EXPECT_EQ(broken[0].step, kChain / 2 + 1);
    }
  }
}

// A chain moving at -v along x toward the x_low wall, with contact.
Scene chain_hitting_a_wall(int n, double speed, double threshold) {
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.with_fluid = false;
  s.fluid.nx = 4 * n;
  s.fluid.ny = 8;
  for (int side = 0; side < 4; ++side) s.fluid.sides[side].kind = fluid::WallKind::kBounceBack;
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = n;
  chain.centre = {n / 2.0 + 0.5, 4, 0};  // its first particle at x = 1, half a unit off the wall at -1/2
  chain.velocity = {-speed, 0, 0};
  chain.fracture.max_force = threshold;
  s.bodies.push_back(chain);
  return s;
}

TEST(ChainHittingAWall, BreaksJustAboveTheImpactSpeedThatMatchesTheThresholdAndNotBelow) {
  constexpr int n = 10;
  constexpr double threshold = 1e-2;
  // It reaches the wall after about 1.5 / v = 150 steps; 20 n more covers the contact and the
  // rebound (the compression front's round trip is 2 n steps).
  for (const double ratio : {0.98, 1.02}) {
    auto sim = build_simulation(chain_hitting_a_wall(n, ratio * threshold, threshold));
    sim->run(150 + 20 * n);
    const auto& broken = sim->solid()->broken_links();
    if (ratio < 1) {
      EXPECT_TRUE(broken.empty()) << "v / T = " << ratio;
      EXPECT_GT(sim->body_state(0).velocity[0], 0) << "it bounced back whole";
    } else {
      ASSERT_FALSE(broken.empty()) << "v / T = " << ratio;
      EXPECT_EQ(broken[0].particle, 0) << "the link behind the front particle breaks first";
    }
  }
}

// Stretch only breaks in tension: a chain hitting a wall at 20 times its stretch threshold (as a
// speed) is compressed, and rebounds whole, never stretched (measured: 2.2e-14 at most, round-off).
TEST(ChainHittingAWall, AStretchThresholdDoesNotBreakItInCompression) {
  Scene s = chain_hitting_a_wall(10, 0.02, 0);
  s.bodies[0].fracture.max_stretch = 1e-3;
  auto sim = build_simulation(s);
  sim->run(600);
  EXPECT_TRUE(sim->solid()->broken_links().empty());
  EXPECT_NEAR(sim->body_state(0).velocity[0], 0.02, 1e-12) << "it bounced back whole, elastically";
}

// A w x h sheet pulled along x by +-F on every particle of its left and right columns, with a
// notch `depth` rows deep cut from its top edge at the middle column.
Scene notched_sheet(double pull, int depth) {
  constexpr int w = 21, h = 10;
  Scene s;
  s.lattice = LatticeKind::kD2Q9;
  s.with_fluid = false;
  s.fluid.nx = 4 * w;
  s.fluid.ny = 4 * h;
  s.contact.enabled = false;
  solid::BodySpec sheet;
  sheet.shape = solid::BodyShape::kLabels;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      if (!(i == w / 2 && j >= h - depth)) sheet.labels.push_back({i, j, 0});
  for (int j = 0; j < h; ++j) {
    sheet.point_loads.push_back({{0, j, 0}, {-pull, 0, 0}});
    sheet.point_loads.push_back({{w - 1, j, 0}, {pull, 0, 0}});
  }
  sheet.centre = {2.0 * w, 2.0 * h, 0};
  sheet.fracture.max_force = 1e-2;
  s.bodies.push_back(sheet);
  return s;
}

TEST(NotchedSheet, BreaksFromTheNotchTipAcrossToTheOtherEdge) {
  // Measured: with a notch 4 rows deep the sheet breaks at F = 0.2 T (not at 0.15 T); without a
  // notch it carries 0.3 T for 2000 steps and breaks at 0.4 T.
  auto sim = build_simulation(notched_sheet(0.2e-2, 4));
  sim->run(400);
  const auto& solid = *sim->solid();
  const auto& broken = solid.broken_links();
  ASSERT_FALSE(broken.empty());
  // The notch's tip is particle (10, 5): its two x links break first, together.
  ASSERT_GE(broken.size(), 2u);
  EXPECT_EQ(solid.label(broken[0].particle), (solid::Label{9, 5, 0}));
  EXPECT_EQ(solid.label(broken[1].particle), (solid::Label{10, 5, 0}));
  EXPECT_EQ(broken[0].step, broken[1].step);
  // The crack runs down the notch's line: every row below the tip loses its links there, and no
  // link away from it breaks.
  std::vector<bool> row_cut(6, false);
  for (const auto& link : broken) {
    const solid::Label l = solid.label(link.particle);
    EXPECT_TRUE(l[0] >= 9 && l[0] <= 11) << "a link broke at (" << l[0] << ", " << l[1] << ")";
    if (link.link == 0 && l[1] <= 5) row_cut[l[1]] = true;
  }
  for (int j = 0; j <= 5; ++j) EXPECT_TRUE(row_cut[j]) << "row " << j << " was not cut";

  for (const double pull : {0.2e-2, 0.3e-2}) {
    auto whole = build_simulation(notched_sheet(pull, 0));
    whole->run(2000);
    EXPECT_TRUE(whole->solid()->broken_links().empty()) << "without a notch, F = " << pull;
  }
}

// A chain in rigid motion with a uniform load along x and a pull against it at its first
// particle, strong enough to break links and shed particles: asymmetric, so that no mirror image
// cancels an error.
Scene breaking_chain_with_loads() {
  Scene s = pulled_chain(16, 0, 1e-3);
  auto& chain = s.bodies[0];
  chain.velocity = {0.003, -0.001, 0};
  chain.load = {2e-4, 1e-4, 0};
  chain.point_loads = {{{0, 0, 0}, {-1.5e-3, 0.7e-3, 0}}, {{15, 0, 0}, {1.2e-3, 0, 0}}};
  return s;
}

TEST(FractureConservation, MomentumChangesByExactlyTheLoadsOnParticlesStillStepped) {
  auto sim = build_simulation(breaking_chain_with_loads());
  const auto& solid = *sim->solid();
  const auto& body = sim->scene().bodies[0];
  const Vec3 load = body.load, first = body.point_loads[0].force, last = body.point_loads[1].force;
  Vec3 before = sim->totals().momentum();
  for (int t = 0; t < 200; ++t) {
    sim->step();
    // Breaks happen first in a step, so the particles unshed now are those the step moved.
    Vec3 expected = before;
    for (int p = 0; p < solid.particle_count(); ++p) {
      if (solid.shed(p)) continue;
      for (int a = 0; a < 2; ++a) expected[a] += load[a] + (p == 0 ? first[a] : p == 15 ? last[a] : 0);
    }
    const Vec3 now = sim->totals().momentum();
    // Round-off: momenta of order 0.05, a few dozen additions a step.
    for (int a = 0; a < 2; ++a) ASSERT_NEAR(now[a], expected[a], 1e-15) << "step " << t + 1 << " axis " << a;
    before = now;
  }
  ASSERT_GT(solid.broken_links().size(), 2u) << "the test needs breaks";
  int shed = 0;
  for (int p = 0; p < solid.particle_count(); ++p) shed += solid.shed(p);
  ASSERT_GT(shed, 0) << "the test needs a shed particle";
}

TEST(FractureConservation, EveryMassIsHalfTheLinksLeftAndEveryMomentumTheSumOfWhatArrives) {
  auto sim = build_simulation(notched_sheet(0.3e-2, 4));
  sim->run(60);
  const auto& solid = *sim->solid();
  ASSERT_GT(solid.broken_links().size(), 4u);
  // K from the labels alone (the links the shape has), less the broken links each particle ends.
  std::map<solid::Label, int> index;
  for (int p = 0; p < solid.particle_count(); ++p) index[solid.label(p)] = p;
  std::vector<int> links(solid.particle_count(), 0);
  for (int p = 0; p < solid.particle_count(); ++p)
    for (int k = 0; k < 4; ++k) {
      const solid::Label c = solid.topology().link(k), l = solid.label(p);
      links[p] += index.count({l[0] + c[0], l[1] + c[1], 0});
    }
  for (const auto& link : solid.broken_links()) {
    const solid::Label c = solid.topology().link(link.link), l = solid.label(link.particle);
    --links[link.particle];
    --links[index.at({l[0] + c[0], l[1] + c[1], 0})];
  }
  double total = 0, placed = 0;
  for (int p = 0; p < solid.particle_count(); ++p) {
    EXPECT_EQ(solid.mass(p), links[p] / 2.0) << "particle " << p;
    total += solid.mass(p);
    Vec3 arrived{0, 0, 0};
    for (int k = 0; k < 4; ++k)
      for (int a = 0; a < 2; ++a) arrived[a] += solid.incoming(p, k)[a];
    for (int a = 0; a < 2; ++a) EXPECT_EQ(solid.momentum(p)[a], arrived[a]) << "particle " << p;
  }
  auto fresh = build_simulation(notched_sheet(0.3e-2, 4));
  for (int p = 0; p < fresh->solid()->particle_count(); ++p) placed += fresh->solid()->mass(p);
  EXPECT_EQ(total, placed - static_cast<double>(solid.broken_links().size()));  // 1/2 from each end
}

TEST(FractureRestore, ARestoredRunBreaksTheSameLinksBitForBit) {
  const Scene scene = notched_sheet(0.3e-2, 4);
  auto sim = build_simulation(scene);
  sim->run(22);  // mid-crack
  const SimulationState middle = sim->save_state();
  ASSERT_FALSE(middle.solid.broken.empty());
  sim->run(40);
  const SimulationState end = sim->save_state();
  ASSERT_GT(end.solid.broken.size(), middle.solid.broken.size());
  // Into a fresh simulation, and back into this one (which must mend the links broken since).
  auto fresh = build_simulation(scene);
  fresh->load_state(middle);
  sim->load_state(middle);
  for (auto* run : {fresh.get(), sim.get()}) {
    run->run(40);
    const SimulationState again = run->save_state();
    EXPECT_EQ(again.solid.broken, end.solid.broken);
    EXPECT_EQ(again.solid.positions, end.solid.positions);
    EXPECT_EQ(again.solid.incoming, end.solid.incoming);
    EXPECT_EQ(again.solid.shed_momentum, end.solid.shed_momentum);
  }
}

TEST(FractureRestore, AStateWhoseBrokenLinksDoNotFitIsRefused) {
  auto sim = build_simulation(notched_sheet(0.3e-2, 4));
  sim->run(30);
  const SimulationState good = sim->save_state();
  SimulationState bad = good;
  bad.solid.broken.push_back(bad.solid.broken.front());  // broken twice
  EXPECT_THROW(sim->load_state(bad), std::invalid_argument);
  bad = good;
  bad.solid.broken.front().link = 2;  // links are named from their lower end: 0 or 1 in 2D
  EXPECT_THROW(sim->load_state(bad), std::invalid_argument);
  bad = good;
  bad.solid.broken.pop_back();  // a link restored whole, yet its vectors were cleared: fine;
  sim->load_state(bad);         // but a broken link that still carries a vector is not
  bad = good;
  const auto& link = bad.solid.broken.front();
  bad.solid.incoming[static_cast<std::size_t>(link.particle) * 4 + 2] = {1e-3, 0, 0};
  EXPECT_THROW(sim->load_state(bad), std::invalid_argument);
  sim->load_state(good);
  EXPECT_EQ(sim->save_state().solid.broken, good.solid.broken);
}

TEST(FractureSpec, BadThresholdsAndPointLoadsAreRefusedNamingTheField) {
  Scene s = pulled_chain(6, 1e-3, 1e-3);
  s.bodies[0].fracture.max_force = -1;
  auto errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].fracture.max_force: must be a finite number >= 0 (0: off)");
  s.bodies[0].fracture.max_force = 1e-3;
  s.bodies[0].fracture.max_stretch = NAN;
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].fracture.max_stretch: must be a finite number >= 0 (0: off)");
  s.bodies[0].fracture.max_stretch = 0;
  s.bodies[0].rotation = true;
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].rotation: a body that can break cannot rotate (its best-fit frame would span "
                       "the broken pieces)");
  s.bodies[0].rotation = false;
  s.bodies[0].point_loads[1].label = {6, 0, 0};
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].point_loads.label: label (6, 0, 0) is not a particle of this body");
  s.bodies[0].point_loads[1].label = {0, 0, 0};
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].point_loads.label: label (0, 0, 0) appears twice");
  s.bodies[0].point_loads[1] = {{5, 0, 0}, {0, 0, 1e-3}};
  errors = validate_scene(s);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0], "bodies[0].point_loads.force: a 2D body has zero z components");
}

}  // namespace
}  // namespace lbsolid::scene
