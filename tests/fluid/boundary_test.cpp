// Geometry and boundary rules: D2Q7 neighbours match the triangular grid, the initial state is
// exactly the requested equilibrium through every boundary, closed boxes keep their mass, and a
// multi-threaded step equals the single-threaded one bit for bit.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "fluid/fluid_test_support.h"
#include "lattice/lattice_traits.h"

namespace lbsolid::testing {
namespace {

TEST(HexagonalGeometryTest, NeighbourOffsetsMoveByTheLatticeVelocity) {
  for (int y = 0; y < 4; ++y) {
    for (int i = 0; i < D2Q7::Q; ++i) {
      const auto o = D2Q7::neighbour_offset(i, y & 1);
      const Vec3 from = FluidLattice<D2Q7, double>::position(5, y, 0);
      const Vec3 to = FluidLattice<D2Q7, double>::position(5 + o[0], y + o[1], 0);
      EXPECT_NEAR(to[0] - from[0], D2Q7::c[i][0], 1e-15) << "dir " << i << " row " << y;
      EXPECT_NEAR(to[1] - from[1], D2Q7::c[i][1], 1e-15) << "dir " << i << " row " << y;
      const int back = lattice::opposite<D2Q7>(i);
      const auto r = D2Q7::neighbour_offset(back, (y + o[1]) & 1);
      EXPECT_EQ(o[0] + r[0], 0);
      EXPECT_EQ(o[1] + r[1], 0);
    }
  }
}

template <class L>
double max_abs(const Vec3& v) {
  return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
}

template <class L>
class BoundaryTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(BoundaryTest, Lattices);

TYPED_TEST(BoundaryTest, InitialStateIsTheRequestedEquilibriumThroughEveryBoundary) {
  using L = TypeParam;
  FluidConfig c = channel_config<L>(6, WallKind::kBounceBack, WallKind::kMovingWall);
  c.sides[fluid::kYHigh].wall_velocity = {0.03, 0, 0};
  c.sides[fluid::kXLow].kind = WallKind::kBounceBack;
  c.sides[fluid::kXHigh].kind = WallKind::kBounceBack;
  c.nx = 5;
  FluidLattice<L, double> fluid(c);
  auto rho = [](int x, int y, int z) { return 1.0 + 0.01 * x - 0.005 * y + 0.002 * z; };
  auto u = [](int x, int y, int z) { return Vec3{0.01 * y, -0.02 + 0.003 * x, L::D == 3 ? 0.001 * z : 0.0}; };
  fluid.initialize(rho, u);
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        const auto m = fluid.moments(x, y, z);
        EXPECT_NEAR(m.rho, rho(x, y, z), 1e-14);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(m.u[a], u(x, y, z)[a], 1e-14);
      }
}

TYPED_TEST(BoundaryTest, ClosedBoxWithMovingLidKeepsItsMass) {
  using L = TypeParam;
  FluidConfig c;
  c.nx = 16;
  c.ny = 16;
  c.nz = L::D == 3 ? 8 : 1;
  for (int side = 0; side < 2 * L::D; ++side) c.sides[side].kind = WallKind::kBounceBack;
  c.sides[fluid::kYHigh].kind = WallKind::kMovingWall;
  c.sides[fluid::kYHigh].wall_velocity = {0.05, 0, 0};
  FluidLattice<L, double> fluid(c);
  const double mass0 = fluid.total_mass();
  fluid.run(2000);
  EXPECT_LT(std::abs(fluid.total_mass() - mass0) / mass0, 1e-12);
  // The lid set the fluid moving along x.
  EXPECT_GT(fluid.velocity(c.nx / 2, c.ny - 1, 0)[0], 0.01);
}

TYPED_TEST(BoundaryTest, ThreadedStepEqualsSingleThreadedStepBitForBit) {
  using L = TypeParam;
  FluidConfig c = channel_config<L>(24, WallKind::kFreeSlip, WallKind::kMovingWall);
  c.nx = 20;
  c.sides[fluid::kYLow].traction = {1e-4, 0, 0};
  c.sides[fluid::kYHigh].wall_velocity = {0.04, 0, 0};
  c.body_force = {1e-5, 0, 0};
  FluidLattice<L, double> serial(c);
  FluidLattice<L, double> threaded(c);
  threaded.set_threads(3);
  EXPECT_THROW(threaded.set_threads(0), std::invalid_argument);
  EXPECT_EQ(threaded.config().threads, 3);
  serial.run(50);
  threaded.run(50);
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        EXPECT_EQ(serial.populations(x, y, z), threaded.populations(x, y, z));
        EXPECT_EQ(serial.density(x, y, z), threaded.density(x, y, z));
      }
}

TEST(FreeSlipWallTest, UniformFlowAlongAFreeSlipChannelIsUndisturbed) {
  // No shear stress at a free-slip wall: a plug flow stays a plug flow, to round-off.
  FluidConfig c = channel_config<D2Q9>(10, WallKind::kFreeSlip, WallKind::kFreeSlip);
  FluidLattice<D2Q9, double> fluid(c);
  fluid.initialize_uniform(1.0, {0.04, 0, 0});
  fluid.run(500);
  for (int y = 0; y < c.ny; ++y) EXPECT_NEAR(fluid.velocity(1, y)[0], 0.04, 1e-14);
}

}  // namespace
}  // namespace lbsolid::testing
