// In-place (AA) and two-buffer streaming compute the same collision on the same pulled values, so
// they must agree bit for bit, through walls, corners, traction and body force, at odd and even
// step counts, with any number of threads.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

using fluid::StreamingScheme;

template <class L>
class StreamingSchemeTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(StreamingSchemeTest, Lattices);

template <class L>
FluidConfig walled_box() {
  FluidConfig c = channel_config<L>(12, WallKind::kFreeSlip, WallKind::kBounceBack);
  c.nx = 9;
  c.sides[fluid::kXLow].kind = WallKind::kBounceBack;  // corners with the y walls
  c.sides[fluid::kXHigh].kind = WallKind::kBounceBack;
  c.sides[fluid::kYLow].traction = {2e-4, 0, 0};
  c.body_force = {1e-5, -2e-5, L::D == 3 ? 1e-5 : 0.0};
  return c;
}

template <class L>
void expect_same_populations(const FluidLattice<L, double>& a, const FluidLattice<L, double>& b,
                             double tolerance) {
  const auto& c = a.config();
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        const auto fa = a.populations(x, y, z), fb = b.populations(x, y, z);
        for (int i = 0; i < L::Q; ++i) {
          if (tolerance == 0) {
            ASSERT_EQ(fa[i], fb[i]) << "node " << x << "," << y << "," << z << " dir " << i;
          } else {
            ASSERT_NEAR(fa[i], fb[i], tolerance) << "node " << x << "," << y << "," << z << " dir " << i;
          }
        }
      }
}

// Walled, and periodic on every side: there the local step sweeps each thread's rows as one run,
// whose start (9-cell rows, 3 parts) falls anywhere in a cache line.
TYPED_TEST(StreamingSchemeTest, InPlaceEqualsTwoBufferBitForBit) {
  using L = TypeParam;
  for (bool walled : {true, false}) {
    SCOPED_TRACE(walled ? "walled box" : "periodic box");
    FluidConfig c = walled_box<L>();
    if (!walled)
      for (auto& side : c.sides) side = fluid::SideBoundary{};
    c.streaming = StreamingScheme::kTwoBuffer;
    FluidLattice<L, double> two_buffer(c);
    c.streaming = StreamingScheme::kInPlace;
    c.threads = 3;
    FluidLattice<L, double> in_place(c);
    auto u = [](int x, int y, int) { return Vec3{0.01 * std::sin(0.7 * x), 0.02 * std::cos(0.3 * y), 0}; };
    auto rho = [](int x, int y, int z) { return 1.0 + 0.001 * (x - y + z); };
    two_buffer.initialize(rho, u);
    in_place.initialize(rho, u);
    // One population buffer instead of two, plus the nodes of each row for an exchange inside the
    // step, which only the in-place step takes (sized when the lattice is built).
    const std::size_t row_counts = static_cast<std::size_t>(c.ny) * c.nz * sizeof(std::uint32_t);
    EXPECT_EQ((in_place.bytes_allocated() - row_counts) * 2, two_buffer.bytes_allocated());
    for (long steps : {1L, 1L, 6L, 29L}) {  // odd and even totals: 1, 2, 8, 37
      two_buffer.run(steps);
      in_place.run(steps);
      expect_same_populations(two_buffer, in_place, 0.0);
    }
  }
}

// initialize_uniform writes one equilibrium per row (the body force is a row's) a population's row
// at a time, and in place skips the second pass that puts each population where the next step
// pulls it (it is where the first pass put it): every stored value of both buffers must be what
// the general initialize() stores, before and after steps, through the walls, corners, traction
// and body force of walled_box().
TYPED_TEST(StreamingSchemeTest, UniformInitializationStoresWhatTheGeneralOneStores) {
  using L = TypeParam;
  for (const auto scheme : {StreamingScheme::kTwoBuffer, StreamingScheme::kInPlace}) {
    SCOPED_TRACE(scheme == StreamingScheme::kInPlace ? "in place" : "two buffers");
    FluidConfig c = walled_box<L>();
    c.streaming = scheme;
    FluidLattice<L, double> uniform(c), general(c);
    const Vec3 u{0.02, -0.01, L::D == 3 ? 0.005 : 0.0};
    uniform.run(3);  // a state for initialization to replace (the same in both)
    general.run(3);
    uniform.initialize_uniform(1.03, u);
    general.initialize([](int, int, int) { return 1.03; }, [&](int, int, int) { return u; });
    for (long steps : {0L, 1L, 2L}) {
      uniform.run(steps);
      general.run(steps);
      const auto a = uniform.raw_state(), b = general.raw_state();
      ASSERT_EQ(a.populations.size(), b.populations.size());
      for (std::size_t k = 0; k < a.populations.size(); ++k)
        ASSERT_EQ(a.populations[k], b.populations[k]) << "value " << k << " after " << uniform.step_count() << " steps";
    }
  }
}

TYPED_TEST(StreamingSchemeTest, InPlaceMatchesTwoBufferWithAMovingWall) {
  using L = TypeParam;
  FluidConfig c = channel_config<L>(10, WallKind::kMovingWall, WallKind::kBounceBack);
  c.sides[fluid::kYLow].wall_velocity = {0.05, 0, 0};
  c.streaming = StreamingScheme::kTwoBuffer;
  FluidLattice<L, double> two_buffer(c);
  c.streaming = StreamingScheme::kInPlace;
  FluidLattice<L, double> in_place(c);
  two_buffer.run(101);
  in_place.run(101);
  // Not bit for bit: the two-buffer start stores f_eq - correction at the wall, which is f_eq
  // again only to the last bit; everything after the first step is the same arithmetic.
  expect_same_populations(two_buffer, in_place, 1e-15);
}

// walled_box() (or the same box periodic on every side) in `scheme`, with a density and velocity
// that vary from node to node: the observers' tests read it back node by node and row by row.
template <class L, class T = double>
std::unique_ptr<FluidLattice<L, T>> varied_box(bool walled, StreamingScheme scheme, int nx = 9) {
  FluidConfig c = walled_box<L>();
  c.nx = nx;
  if (!walled)
    for (auto& side : c.sides) side = fluid::SideBoundary{};  // periodic
  c.streaming = scheme;
  auto fluid = std::make_unique<FluidLattice<L, T>>(c);
  fluid->initialize([](int x, int y, int z) { return 1.0 + 0.001 * (x - y + z); },
                    [](int x, int y, int) { return Vec3{0.01 * std::sin(0.7 * x), 0.02 * std::cos(0.3 * y), 0}; });
  return fluid;
}

// check(fluid, walled, scheme) on varied_box() walled and periodic, in both schemes, after 0, 1, 2
// and 8 steps (odd and even counts: the in-place scheme stores populations differently after each).
template <class L, class T = double, class Check>
void for_each_varied_state(const Check& check, int nx = 9) {
  for (const bool walled : {true, false})
    for (const auto scheme : {StreamingScheme::kTwoBuffer, StreamingScheme::kInPlace}) {
      auto fluid = varied_box<L, T>(walled, scheme, nx);
      for (long steps : {0L, 1L, 1L, 6L}) {
        fluid->run(steps);
        check(*fluid, walled, scheme);
      }
    }
}

// The velocity profile streamed to clients takes each row's populations through one set of
// sources for the interior nodes (add_row_velocity_x); it must give the very values that
// velocity(x, y, z), which resolves every node through its own sources, gives: in both schemes,
// after odd and even step counts (the in-place scheme reads differently after each), through the
// walls, corners and the periodic x sides of walled_box() and a periodic box. It sums the interior
// in blocks of 8 nodes: rows of 9 (one short block) and 150 (18 whole blocks and a short one), in
// both precisions.
template <class L, class T>
void expect_row_velocity_sums_equal_per_node_velocities(int nx) {
  for_each_varied_state<L, T>(
      [nx](const FluidLattice<L, T>& fluid, bool walled, StreamingScheme scheme) {
        const FluidConfig& c = fluid.config();
        for (int z = 0; z < c.nz; ++z)
          for (int y = 0; y < c.ny; ++y) {
            double fast = 0, per_node = 0;
            fluid.add_row_velocity_x(y, z, fast);
            for (int x = 0; x < c.nx; ++x) per_node += fluid.velocity(x, y, z)[0];
            ASSERT_EQ(fast, per_node) << "nx " << nx << ", row " << y << ", layer " << z << ", walled " << walled
                                      << ", scheme " << static_cast<int>(scheme) << ", step " << fluid.step_count();
          }
      },
      nx);
}

TYPED_TEST(StreamingSchemeTest, RowVelocitySumsEqualPerNodeVelocitiesBitForBit) {
  expect_row_velocity_sums_equal_per_node_velocities<TypeParam, double>(9);
  expect_row_velocity_sums_equal_per_node_velocities<TypeParam, double>(150);
  expect_row_velocity_sums_equal_per_node_velocities<TypeParam, float>(150);
}

// Field reads (GetField, field snapshots) take whole rows through row_moments: every node's
// density and velocity must be those moments(x, y, z) gives, bit for bit, for any segment of a row
// (a read in chunks starts and ends mid-row), in both schemes, after odd and even step counts,
// with walls and without. The interior goes in blocks of 8 nodes: rows of 9 and 150 nodes, and
// segments that start and end inside a block, in both precisions.
template <class L, class T>
void expect_row_moments_equal_per_node_moments(int nx) {
  for_each_varied_state<L, T>(
      [](const FluidLattice<L, T>& fluid, bool, StreamingScheme) {
        const FluidConfig& c = fluid.config();
        for (int z = 0; z < c.nz; ++z)
          for (int y = 0; y < c.ny; ++y)
            for (const auto& [first, count] : {std::pair{0, c.nx}, std::pair{1, c.nx - 2}, std::pair{c.nx - 1, 1},
                                               std::pair{0, 1}, std::pair{3, c.nx - 5}, std::pair{2, c.nx - 2}}) {
              std::vector<double> density(count), velocity(3 * count);
              fluid.row_moments(y, z, first, count, density.data(), velocity.data());
              for (int k = 0; k < count; ++k) {
                const auto m = fluid.moments(first + k, y, z);
                ASSERT_EQ(density[k], m.rho) << "nx " << c.nx << ", node " << first + k << ", row " << y << ", step "
                                             << fluid.step_count();
                for (int a = 0; a < 3; ++a)
                  ASSERT_EQ(velocity[3 * k + a], m.u[a]) << "nx " << c.nx << ", node " << first + k << ", row " << y
                                                         << ", axis " << a;
              }
            }
      },
      nx);
}

TYPED_TEST(StreamingSchemeTest, RowMomentsEqualPerNodeMomentsBitForBit) {
  expect_row_moments_equal_per_node_moments<TypeParam, double>(9);
  expect_row_moments_equal_per_node_moments<TypeParam, double>(150);
  expect_row_moments_equal_per_node_moments<TypeParam, float>(150);
}

}  // namespace
}  // namespace lbsolid::testing
