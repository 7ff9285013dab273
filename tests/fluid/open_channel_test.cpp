// Open channels: a velocity inlet on x_low and a pressure outlet on x_high (pull_source.h), on
// every lattice and in both streaming schemes, against what holds independently of the code:
//   - Ladd's inlet rule adds exactly rho0 u per node and step (its corrections sum to that, for
//     any populations): a channel closed at x_high gains that mass each step, to round-off;
//   - at steady state what enters leaves: the mass stops changing;
//   - the flow that settles is plane Poiseuille flow: the parabola across the channel and the
//     pressure gradient dp/dx = -8 mu u_max / H^2 along it (p = c_s^2 rho);
//   - the outlet sets the pressure level: the pressure line ends at rho_out and moves with it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

using fluid::InflowProfile;
using fluid::StreamingScheme;

constexpr int kLength = 64, kWidth = 16;
constexpr double kPeak = 0.02;   // inlet's peak speed: Mach 0.035 on D2Q9
constexpr double kOmega = 1.6;   // nu = 0.042 on D2Q9: Re = u_max H / nu = 7.7

// A channel along x between bounce-back y walls (and periodic z in 3D), parabolic inflow at
// x_low, a pressure outlet at rho0 on x_high. TRT at Lambda 3/16 puts bounce-back walls exactly
// half-way for Poiseuille flow, so the profile is the parabola between them.
template <class L>
FluidConfig open_channel(StreamingScheme streaming, WallKind x_high = WallKind::kPressureOutlet) {
  FluidConfig c = channel_config<L>(kWidth, WallKind::kBounceBack, WallKind::kBounceBack, kOmega);
  c.nx = kLength;
  c.collision = fluid::CollisionModel::kTrt;
  c.streaming = streaming;
  c.sides[fluid::kXLow].kind = WallKind::kVelocityInlet;
  c.sides[fluid::kXLow].inflow_speed = kPeak;
  c.sides[fluid::kXLow].inflow_profile = InflowProfile::kParabolic;
  c.sides[fluid::kXHigh].kind = x_high;
  return c;
}

template <class L>
double trt_viscosity() {
  return (1.0 / kOmega - 0.5) * L::cs2;
}

// Mass entering per step by Ladd's rule: 2 w_i rho0 (c_i . u) / c_s^2 summed over the populations
// that come in through the inlet at each of its nodes, from the lattice's own weights (at a corner
// a y wall answers for the slanted ones).
template <class L>
double inflow_per_step(const FluidConfig& c) {
  double total = 0;
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int i = 0; i < L::Q; ++i) {
        const int parity = L::hexagonal ? (y & 1) : 0;
        const auto o = L::neighbour_offset(lattice::opposite<L>(i), parity);
        const int sy = y + o[1];
        if (o[0] >= 0 || sy < 0 || sy >= c.ny) continue;  // not from beyond x_low, or a y wall's
        total += 2.0 * L::w[i] * c.rho0 * L::c[i][0] * fluid::inflow_speed_at(c, fluid::kXLow, y, z) / L::cs2;
      }
  return total;
}

// The line the channel's mean density follows over the middle half of its length.
template <class L>
observe::LineFit pressure_line(const FluidLattice<L, double>& fluid) {
  std::vector<double> xs, rho;
  for (int x = kLength / 4; x < 3 * kLength / 4; ++x) {
    double sum = 0;
    for (int y = 0; y < kWidth; ++y) sum += fluid.density(x, y, 0);
    xs.push_back(fluid::FluidLattice<L, double>::position(x, 0, 0)[0]);
    rho.push_back(sum / kWidth);
  }
  return fit_line(xs, rho);
}

template <class L>
class OpenChannelTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(OpenChannelTest, Lattices);

TYPED_TEST(OpenChannelTest, InletAddsExactlyItsInflowEveryStep) {
  using L = TypeParam;
  for (StreamingScheme streaming : {StreamingScheme::kInPlace, StreamingScheme::kTwoBuffer}) {
    const FluidConfig c = open_channel<L>(streaming, WallKind::kBounceBack);
    FluidLattice<L, double> fluid(c);
    const double inflow = inflow_per_step<L>(c);
    double mass = fluid.total_mass(), worst = 0;
    for (int step = 0; step < 300; ++step) {
      fluid.step();
      const double now = fluid.total_mass();
      worst = std::max(worst, std::abs((now - mass) - inflow));
      mass = now;
    }
    // Round-off of a sum of kLength * kWidth * nz masses near 1: a few 1e-13.
    report(std::string(L::name) + " largest |gain - inflow| per step", worst, 1e-11);
    EXPECT_LT(worst, 1e-11) << "inflow per step " << inflow;
    EXPECT_GT(inflow, 0.9 * kPeak * c.rho0 * kWidth * c.nz * 2.0 / 3.0);  // the parabola's mean is 2/3 of its peak
  }
}

TYPED_TEST(OpenChannelTest, SettlesToPoiseuilleFlowWithWhatEntersLeaving) {
  using L = TypeParam;
  for (StreamingScheme streaming : {StreamingScheme::kInPlace, StreamingScheme::kTwoBuffer}) {
    const FluidConfig c = open_channel<L>(streaming);
    FluidLattice<L, double> fluid(c);
    run_to_steady_profile(fluid, 1e-10, 60000);
    const double inflow = inflow_per_step<L>(c);

    // In = out: over 1000 steps the mass changes by a tiny fraction of what flowed through.
    const double before = fluid.total_mass();
    fluid.run(1000);
    const double imbalance = std::abs(fluid.total_mass() - before) / (1000 * inflow);
    report(std::string(L::name) + " |dM/dt| / inflow at steady state", imbalance, 1e-6);
    EXPECT_LT(imbalance, 1e-6);

    // The pressure gradient of plane Poiseuille flow, fitted over the middle half of the channel.
    const double h = kWidth * L::row_spacing;
    const double nu = trt_viscosity<L>();
    const auto line = pressure_line(fluid);
    const double expected = -8.0 * nu * c.rho0 * kPeak / (L::cs2 * h * h);
    // Mass flux rho u is what the channel carries; the density falls by 0.5% over its length
    // (-expected * kLength), so u_max and with it the gradient vary by about as much: twice that.
    const double gradient_error = std::abs(line.slope / expected - 1);
    report(std::string(L::name) + " pressure gradient relative error", gradient_error, 0.01);
    EXPECT_LT(gradient_error, 0.01) << "slope " << line.slope << " expected " << expected;

    // The profile across the middle of the channel: the parabola whose mass flux entered, rho0 u
    // at the inlet, carried at the local density (rho u is conserved along the channel). The
    // density varies by 0.5% along the channel and the viscous stress with it: twice that.
    std::vector<double> profile, parabola;
    const int mid = kLength / 2;
    for (int y = 0; y < kWidth; ++y) {
      const auto m = fluid.moments(mid, y, 0);
      profile.push_back(m.u[0]);
      parabola.push_back(fluid::inflow_speed_at(c, fluid::kXLow, y, 0) * c.rho0 / m.rho);
    }
    const double shape_error = relative_l2(profile, parabola);
    report(std::string(L::name) + " mid-channel profile relative L2 error", shape_error, 0.01);
    EXPECT_LT(shape_error, 0.01);

  }
}

// The fully developed part of a steady open channel: the line its mean density follows.
template <class L>
observe::LineFit steady_pressure_line(double outflow_density) {
  FluidConfig c = open_channel<L>(StreamingScheme::kInPlace);
  c.sides[fluid::kXHigh].outflow_density = outflow_density;
  FluidLattice<L, double> fluid(c);
  run_to_steady_profile(fluid, 1e-12, 60000);
  return pressure_line(fluid);
}

// The outlet sets the pressure level: lowering rho_out lowers the whole line by as much. The
// inlet fixes the mass flux rho u, so the gradient 8 nu rho u / H^2 stays; u rises by drho/rho
// (2% here) and the O(u^2) parts of the density with it, a few 1e-6: 1% of drho allowed.
//
// Where the line meets the outlet (x = nx - 1/2) it is rho_out: the populations entering there
// are the equilibrium at rho_out and the velocity beside it (pull_source.h), so only where
// exactly between the last nodes that holds is open: up to a node of the gradient.
TYPED_TEST(OpenChannelTest, OutletSetsThePressureLevel) {
  using L = TypeParam;
  const auto at_rho0 = steady_pressure_line<L>(1.0), lowered = steady_pressure_line<L>(0.98);
  const double outlet_x = kLength - 0.5;
  auto level = [&](const observe::LineFit& line) { return line.intercept + line.slope * outlet_x; };
  const double shift = (level(at_rho0) - level(lowered)) / 0.02;
  report(std::string(L::name) + " line shift / outflow density change", shift, 1);
  EXPECT_NEAR(shift, 1.0, 0.01);
  const double offset = std::abs(level(at_rho0) - 1.0);
  const double bound = std::abs(at_rho0.slope);
  report(std::string(L::name) + " |line at the outlet - rho_out|", offset, bound);
  EXPECT_LT(offset, bound);
}

// Both streaming schemes read the same populations through the same rules (fluid_lattice.h):
// BGK gives the same fluid bit for bit, the outlet's equilibrium included.
TYPED_TEST(OpenChannelTest, StreamingSchemesAgreeBitForBit) {
  using L = TypeParam;
  FluidConfig in_place = open_channel<L>(StreamingScheme::kInPlace);
  in_place.collision = fluid::CollisionModel::kBgk;
  in_place.sides[fluid::kXHigh].outflow_density = 0.99;
  FluidConfig two_buffer = in_place;
  two_buffer.streaming = StreamingScheme::kTwoBuffer;
  FluidLattice<L, double> a(in_place), b(two_buffer);
  for (int steps : {1, 1, 40, 101}) {
    a.run(steps);
    b.run(steps);
    for (int z = 0; z < in_place.nz; ++z)
      for (int y = 0; y < kWidth; ++y)
        for (int x = 0; x < kLength; ++x) ASSERT_EQ(a.populations(x, y, z), b.populations(x, y, z)) << x << "," << y;
  }
}

// A restart continues exactly: the outlet's rule is a function of the stored populations
// (refreshed on restore), so a fluid restored from a raw state at an even or an odd step goes on
// bit for bit like the one it was taken from, in both schemes.
TYPED_TEST(OpenChannelTest, RestoredStateContinuesBitForBit) {
  using L = TypeParam;
  for (StreamingScheme streaming : {StreamingScheme::kInPlace, StreamingScheme::kTwoBuffer})
    for (int before : {300, 301}) {  // after the inflow has reached the outlet (110 steps)
      const FluidConfig c = open_channel<L>(streaming);
      FluidLattice<L, double> original(c), restored(c);
      original.run(before);
      restored.restore_raw_state(original.raw_state());
      original.run(25);
      restored.run(25);
      for (int z = 0; z < c.nz; ++z)
        for (int y = 0; y < kWidth; ++y)
          for (int x = 0; x < kLength; ++x)
            ASSERT_EQ(original.populations(x, y, z), restored.populations(x, y, z))
                << static_cast<int>(streaming) << " after " << before << " steps, at " << x << "," << y;
    }
}

}  // namespace
}  // namespace lbsolid::testing
