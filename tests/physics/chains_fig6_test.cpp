// The paper's Fig. 6 (section 4.2) at small size: chains in a stress-driven shear flow.
//   - free fluid: the steady gradient is the analytic du_x/dy = sigma / (rho nu), within 1%;
//   - chains perpendicular to the flow raise the apparent viscosity (free gradient over chain
//     gradient) well above 1, and the flattened profile is still a straight line (the paper: 45x
//     with 2000 chains; "the flat profile is in fact still a linear shear flow profile");
//   - the same chains turned parallel to the flow leave the steady gradient within 2% of the free
//     fluid's ("the stationary velocity gradient is identical to the case of the free fluid").
// Set-up and why:
//   - D2Q7 with omega = 1 (nu = 1/8), the paper's choice; a channel of 128 x 40 nodes, periodic in
//     x, between two free-slip walls. Traction +sigma on the upper wall and -sigma on the lower one:
//     zero net force, so the steady free profile is the straight line through zero. On D2Q7 a node
//     covers 1 x sqrt(3)/2, so the mass per unit area is rho / (sqrt(3)/2).
//   - sigma = 2.5e-4: free gradient 0.0017, wall speeds below 0.02, and a chain Reynolds number
//     G a^2 / nu of 0.1 to 0.2 (a the chain's half-length, below): the Stokes regime in which the
//     paper's fluid stays Newtonian and the estimate below holds. Inertia is not negligible much
//     above that: while the fluid spins up the chains lag it, and the lift a lagging body feels in
//     a shear (toward the faster fluid, growing faster than linearly with sigma, independent of its
//     sign) moves parallel chains off their layer; at sigma = 1e-3 many end up straddling two
//     layers, whose nearest nodes they then tie together.
//   - 60 chains of 8 particles with rest spacing sqrt(3)/2: a perpendicular chain puts one particle
//     on each of 8 successive fluid layers, so it couples 8 layers ("extend over several fluid
//     layers"). Centres evenly spread in y over the band where a chain fits between the walls,
//     at random x (fixed seed): a statistically uniform suspension, and no crystal of chains that
//     would shear into and out of aligned columns. Parallel chains are the same chains turned,
//     their centres moved onto the nearest layer, so each stays on one layer of fluid (a chain
//     between two layers would couple them through its nearest nodes and is not parallel to them).
//   - The gradient is the slope of a line fitted to rows 7..32 only, against their heights
//     y sqrt(3)/2: away from the two forced wall layers, and only where every height is crossed by
//     the same density of perpendicular chains (a chain's centre cannot come closer to a wall than
//     half its length, so coverage thins over one chain length next to each wall).
//   - The chains move at different speeds in different layers and pass one another, so the profile
//     flickers by several percent: the gradient is read off the profile averaged over 30000 steps
//     (a shear strain of about 25 with chains) after 10000 steps (about 10 times the slowest
//     viscous decay time H^2 / (pi^2 nu) of the channel) to reach the steady state.
// Expected perpendicular ratio, from the physics. The model's springs keep a fixed orientation, so a
// chain across a shear u = G y is a plate that cannot turn. The fluid would turn a free plate at
// rate G as a material line, so the fixed plate's disturbance is that of a plate of half-length a
// turning at G in fluid at rest: in 2D Stokes flow a line of Stokeslets with density ~ y/sqrt(a^2-y^2)
// on the plate gives the torque T = 2 pi mu a^2 G. That torque is shear stress the chains carry
// between the layers they span, n_c T for n_c chains per unit area, so dilute chains give
//   mu_apparent / mu = 1 + 2 pi n_c a^2 = 1 + 2 phi,  phi = n_c pi a^2,
// with a = 8 particles x sqrt(3)/2 / 2 (each particle stands for one layer). Here phi = 0.63, so
// the estimate is 2.26. The test asks for 1 + phi, half the estimated rise: the LB chain is not a
// continuous no-slip plate but 8 point couplings that each pull one node per step toward a common
// velocity (eq. 14), so fluid slips through it and it carries less than the full plate torque; at
// this concentration the chains also interact, which raises the viscosity further. A chain that
// carried less than half the plate's torque would be one that barely holds the layers together.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "fluid/fluid_test_support.h"
#include "lattice/d2q7.h"
#include "observe/fits.h"
#include "physics/paper_channel.h"
#include "scene/simulation.h"

namespace lbsolid::scene {
namespace {

using lbsolid::testing::report;

constexpr double kRowSpacing = lattice::D2Q7::row_spacing;  // sqrt(3)/2
constexpr int kChannelLength = 128;  // nodes along x (periodic)
constexpr int kChannelRows = 40;     // D2Q7 rows across
constexpr double kOmega = 1.0;       // the paper's choice
constexpr double kRho = 1.0;
constexpr double kSigma = 2.5e-4;  // traction: force per unit wall length on the wall layer
constexpr int kChainLength = 8;  // particles
constexpr int kChainCount = 60;
constexpr double kChainSpacing = kRowSpacing;  // one fluid layer per particle when perpendicular
constexpr double kClearance = 0.25;  // how far a chain's end starts from a wall (must be > 0)
constexpr long kWarmupSteps = 10000;
constexpr long kAveragingSteps = 30000;
constexpr long kSampleEvery = 10;

// D2Q7 BGK viscosity (MODEL.md section 1): c_s^2 = 1/4.
double kinematic_viscosity() { return (1.0 / kOmega - 0.5) / 4.0; }
// Mass per unit area: one D2Q7 node covers 1 x sqrt(3)/2.
double density_per_area() { return kRho / kRowSpacing; }
double analytic_gradient() { return kSigma / (density_per_area() * kinematic_viscosity()); }

double wall_low() { return -0.5 * kRowSpacing; }
double wall_high() { return (kChannelRows - 0.5) * kRowSpacing; }
// End particle to end particle.
double chain_extent() { return (kChainLength - 1) * kChainSpacing; }
// The hydrodynamic half-length: each particle stands for one spacing (one fluid layer).
double chain_half_length() { return 0.5 * kChainLength * kChainSpacing; }
// The band of heights the chains' centres are spread over: a perpendicular chain fits between the walls.
double centre_band_low() { return wall_low() + 0.5 * chain_extent() + kClearance; }
double centre_band_high() { return wall_high() - 0.5 * chain_extent() - kClearance; }

// Rows whose height is crossed by the full density of perpendicular chains (half a chain length
// inside the centre band); these rows also keep well away from the two forced wall layers.
int first_fit_row() { return static_cast<int>(std::ceil((centre_band_low() + 0.5 * chain_extent()) / kRowSpacing)); }
int last_fit_row() { return static_cast<int>(std::floor((centre_band_high() - 0.5 * chain_extent()) / kRowSpacing)); }

// Chain centres per unit area in the band they occupy, and phi = n_c pi a^2.
double chain_area_fraction() {
  const double per_area = kChainCount / (kChannelLength * (centre_band_high() - centre_band_low()));
  return per_area * std::numbers::pi * chain_half_length() * chain_half_length();
}

Scene sheared_channel() {
  Scene s = testing::paper_channel(kChannelLength, kChannelRows, fluid::WallKind::kFreeSlip, kOmega, kRho);
  s.fluid.sides[fluid::kYLow].traction = {-kSigma, 0, 0};
  s.fluid.sides[fluid::kYHigh].traction = {kSigma, 0, 0};
  return s;
}

double nearest_layer_height(double y) { return std::round(y / kRowSpacing) * kRowSpacing; }

// Chains along `axis` (1: across the flow, 0: along it), centres evenly spread over the band in y
// and at random x.
void add_chains(Scene& s, int axis) {
  std::mt19937 rng;  // default seed: its output is fixed by the standard, so every platform places alike
  const double band = centre_band_high() - centre_band_low();
  for (int k = 0; k < kChainCount; ++k) {
    solid::BodySpec chain;
    chain.shape = solid::BodyShape::kChain;
    chain.length = kChainLength;
    chain.axis = axis;
    chain.spacing = kChainSpacing;
    const double x = kChannelLength * (rng() / 4294967296.0);
    const double y = centre_band_low() + (k + 0.5) * band / kChainCount;
    chain.centre = {x, axis == 0 ? nearest_layer_height(y) : y, 0};
    s.bodies.push_back(chain);
  }
}

// u_x(y) averaged along x and over the averaging window, after the warm-up.
std::vector<double> steady_mean_profile(Simulation& sim) {
  sim.run(kWarmupSteps);
  std::vector<double> mean(kChannelRows, 0.0);
  const long samples = kAveragingSteps / kSampleEvery;
  for (long k = 0; k < samples; ++k) {
    sim.run(kSampleEvery);
    const std::vector<double> profile = sim.velocity_profile();
    for (int y = 0; y < kChannelRows; ++y) mean[y] += profile[y] / samples;
  }
  return mean;
}

// The line through the fit rows, against their heights y sqrt(3)/2 (not their row numbers).
observe::LineFit bulk_fit(const std::vector<double>& profile) {
  std::vector<double> heights, velocities;
  for (int y = first_fit_row(); y <= last_fit_row(); ++y) {
    heights.push_back(y * kRowSpacing);
    velocities.push_back(profile[y]);
  }
  return observe::fit_line(heights, velocities);
}

observe::LineFit measure(const Scene& s) {
  auto sim = build_simulation(s);
  return bulk_fit(steady_mean_profile(*sim));
}

// The free fluid is the reference of both chain tests: run once.
const observe::LineFit& free_fluid_fit() {
  static const observe::LineFit fit = measure(sheared_channel());
  return fit;
}

void print_set_up(const char* orientation) {
  std::printf("[ set-up   ] D2Q7 %d x %d, omega %.1f, sigma %.1e; %d %s chains of %d particles (%d particles, "
              "%.3f per fluid node); fit rows %d..%d\n",
              kChannelLength, kChannelRows, kOmega, kSigma, kChainCount, orientation, kChainLength,
              kChainCount * kChainLength, static_cast<double>(kChainCount * kChainLength) / (kChannelLength * kChannelRows),
              first_fit_row(), last_fit_row());
}

// Both the free gradient and the parallel chains' deviation are held by what is left of the
// start-up transient in the 10k-40k-step time average: tau/T e^(-10000/tau), with
// tau = H^2/(pi^2 nu) = 973 steps, is about 1.1e-6 (measured 1.27e-6 free); parallel chains relax
// more slowly (tau x 1.08, their added mass, Fig. 7), which predicts about -1.5e-6 (measured
// -1.25e-6). Bound: 2x the measured values.
constexpr double kTransientBound = 2.5e-6;

TEST(ChainsFig6, FreeFluidGradientIsSigmaOverRhoNu) {
  const double error = free_fluid_fit().slope / analytic_gradient() - 1.0;
  std::printf("[ figure   ] free gradient %.6e, analytic sigma/(rho nu) %.6e\n", free_fluid_fit().slope,
              analytic_gradient());
  report("free gradient relative error", std::abs(error), kTransientBound);
  EXPECT_NEAR(error, 0.0, kTransientBound);
}

TEST(ChainsFig6, PerpendicularChainsRaiseTheApparentViscosity) {
  Scene s = sheared_channel();
  add_chains(s, /*axis=*/1);
  print_set_up("perpendicular");
  const observe::LineFit chains = measure(s);
  const double ratio = free_fluid_fit().slope / chains.slope;
  const double phi = chain_area_fraction();
  std::printf("[ figure   ] gradient free %.4e, with perpendicular chains %.4e; phi = %.3f, dilute plate "
              "estimate 1 + 2 phi = %.3f\n",
              free_fluid_fit().slope, chains.slope, phi, 1.0 + 2.0 * phi);
  report("apparent viscosity ratio, free / perpendicular gradient (bound: 1 + phi)", ratio, 1.0 + phi);
  EXPECT_GT(ratio, 1.0 + phi);
  report("perpendicular profile line fit R^2", chains.r2, 0.99);
  EXPECT_GT(chains.r2, 0.99) << "the flattened profile should still be a straight shear profile";
}

TEST(ChainsFig6, ParallelChainsLeaveTheGradientUnchanged) {
  Scene s = sheared_channel();
  add_chains(s, /*axis=*/0);
  print_set_up("parallel");
  const observe::LineFit chains = measure(s);
  const double deviation = chains.slope / free_fluid_fit().slope - 1.0;
  std::printf("[ figure   ] gradient free %.6e, with parallel chains %.6e\n", free_fluid_fit().slope, chains.slope);
  report("parallel-chain gradient relative deviation from free", std::abs(deviation), kTransientBound);
  EXPECT_NEAR(deviation, 0.0, kTransientBound);
}

}  // namespace
}  // namespace lbsolid::scene
