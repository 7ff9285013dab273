// FluidLattice::add_momentum (MODEL.md eq. 12): adding w_i (c_i . dp)/c_s^2 to a node's
// post-collision populations gives the fluid exactly dp of momentum and no mass, and lands on the
// same populations whichever streaming scheme stored them (the in-place scheme stores them in
// different slots on even and odd steps, and through walls).
#include <gtest/gtest.h>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

using fluid::StreamingScheme;

template <class L>
class MomentumInjectionTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(MomentumInjectionTest, Lattices);

template <class L>
FluidConfig periodic_box() {
  FluidConfig c;
  c.nx = 8;
  c.ny = 6;
  c.nz = L::D == 3 ? 4 : 1;
  c.omega = 1.3;
  return c;
}

TYPED_TEST(MomentumInjectionTest, MomentumGrowsByExactlyDpAndMassIsUnchanged) {
  using L = TypeParam;
  for (auto scheme : {StreamingScheme::kInPlace, StreamingScheme::kTwoBuffer}) {
    FluidConfig c = periodic_box<L>();
    c.streaming = scheme;
    FluidLattice<L, double> fluid(c);
    fluid.initialize([](int x, int, int) { return 1.0 + 0.01 * x; },
                     [](int, int y, int z) { return Vec3{0.02 * y, -0.01, 0.005 * z}; });
    const Vec3 dp{0.013, -0.007, L::D == 3 ? 0.004 : 0.0};
    for (int step = 0; step < 6; ++step) {  // even and odd in-place steps
      const double mass = fluid.total_mass();
      const Vec3 p = fluid.total_momentum();
      fluid.step();
      fluid.add_momentum(3, step % c.ny, 0, dp);
      fluid.add_momentum(0, 0, c.nz - 1, dp);  // a node whose populations wrap around
      const Vec3 q = fluid.total_momentum();
      // The totals sum Q * cells populations (3648 on D3Q19) of order 0.05: their round-off,
      // not the injection, sets the 1e-13 bound (the injection itself adds exact multiples).
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(q[a] - p[a], 2 * dp[a], 1e-13) << "axis " << a;
      EXPECT_NEAR(fluid.total_mass(), mass, 1e-12);
    }
  }
}

TYPED_TEST(MomentumInjectionTest, BothStreamingSchemesAgreeBitForBitThroughWalls) {
  using L = TypeParam;
  FluidConfig c = channel_config<L>(7, WallKind::kBounceBack, WallKind::kMovingWall);
  c.nx = 6;
  c.sides[fluid::kYHigh].wall_velocity = {0.02, 0, 0};
  c.streaming = StreamingScheme::kTwoBuffer;
  FluidLattice<L, double> two(c);
  c.streaming = StreamingScheme::kInPlace;
  FluidLattice<L, double> in_place(c);
  for (int step = 0; step < 7; ++step) {
    for (auto* f : {&two, &in_place}) {
      f->step();
      f->add_momentum(step % c.nx, 0, 0, {0.01, 0.003 * step, 0});  // next to the bounce-back wall
      f->add_momentum(1, c.ny - 1, c.nz - 1, {-0.002, 0.004, 0});  // next to the moving wall
    }
  }
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        const auto a = two.populations(x, y, z), b = in_place.populations(x, y, z);
        for (int i = 0; i < L::Q; ++i) ASSERT_EQ(a[i], b[i]) << x << "," << y << "," << z << " dir " << i;
      }
}

TEST(MomentumInjection, RefusedBeforeAnyStep) {
  FluidLattice<D2Q9, double> fluid(periodic_box<D2Q9>());
  EXPECT_THROW(fluid.add_momentum(0, 0, 0, {0.1, 0, 0}), std::logic_error);
}

}  // namespace
}  // namespace lbsolid::testing
