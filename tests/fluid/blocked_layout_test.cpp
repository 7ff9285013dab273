// Populations in blocks (fluid/population_storage.h, fluid/blocked_kernel.h) are a second
// layout with kernels of their own for D3Q19 in place, BGK, every side periodic. The arrays'
// kernels are an independent implementation of the same arithmetic, so every observable must
// agree bit for bit: the populations after each step (local and pulling), with and without a
// body force, on one thread and several (the pulling step's parts meet at rows whose join slots
// both touch), on each instruction-set path; the observers, the coupling's batched calls and
// checkpoints, which convert between the layouts.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "fluid/fluid_test_support.h"
#include "fluid/kernel_isa.h"

namespace lbsolid::testing {
namespace {

using fluid::CollisionModel;
using fluid::KernelIsa;
using fluid::PopulationLayout;
using fluid::StreamingScheme;

template <class T>
constexpr int kW = fluid::PopulationStorage<T>::kBlockCells;

FluidConfig periodic_box(int nx, int ny, int nz, PopulationLayout layout, int threads = 1, bool force = false) {
  FluidConfig c;
  c.nx = nx;
  c.ny = ny;
  c.nz = nz;
  c.omega = 1.3;
  c.threads = threads;
  c.layout = layout;
  if (force) c.body_force = {1e-5, -2e-5, 3e-5};
  return c;
}

// A flow with structure along every axis, so that every direction carries distinct values.
template <class T>
void start(FluidLattice<D3Q19, T>& fluid) {
  fluid.initialize([](int x, int y, int z) { return 1.0 + 0.003 * std::sin(0.9 * x + 0.4 * y - 0.7 * z); },
                   [](int x, int y, int z) {
                     return Vec3{0.03 * std::cos(0.5 * y + 0.2 * z), 0.01 * std::sin(0.7 * x), 0.02 * std::cos(0.3 * x + z)};
                   });
}

// Steps both layouts side by side and compares every population after every step.
template <class T>
void expect_steps_alike(int nx, int ny, int nz, int threads, bool force, int steps) {
  FluidLattice<D3Q19, T> arrays(periodic_box(nx, ny, nz, PopulationLayout::kArrays, 1, force));
  FluidLattice<D3Q19, T> blocks(periodic_box(nx, ny, nz, PopulationLayout::kBlocks, threads, force));
  ASSERT_EQ(blocks.layout(), PopulationLayout::kBlocks);
  start(arrays);
  start(blocks);
  for (int s = 0; s <= steps; ++s) {
    const std::vector<double> a = every_population(arrays), b = every_population(blocks);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k)
      ASSERT_EQ(a[k], b[k]) << nx << "x" << ny << "x" << nz << ", " << threads << " thread(s), force " << force
                            << ", after " << s << " steps: population " << k % 19 << " of cell " << k / 19;
    arrays.step();
    blocks.step();
  }
}

template <class T>
void expect_boxes_alike() {
  const int w = kW<T>;
  // A box of several blocks a row; one block a row; rows of one plane (ny = 1, nz = 1); y and z
  // sides of two rows (every row an edge row); odd sizes elsewhere.
  expect_steps_alike<T>(3 * w, 7, 5, 1, false, 5);
  expect_steps_alike<T>(3 * w, 7, 5, 1, true, 4);
  expect_steps_alike<T>(w, 5, 3, 1, false, 3);
  expect_steps_alike<T>(2 * w, 1, 1, 1, false, 3);
  expect_steps_alike<T>(2 * w, 2, 2, 1, true, 3);
  expect_steps_alike<T>(w, 3, 1, 1, false, 3);
}

TEST(BlockedLayout, StepsGiveTheArraysPopulationsBitForBit) {
  expect_boxes_alike<double>();
  expect_boxes_alike<float>();
}

// The pulling step's parts are ranges of planes, each leaving 2 planes at each end to a second
// pass on one thread: parts with planes for both passes (2 and 3 threads on 24 planes), parts
// too thin for the first (7), more parts than planes (40), a box too thin for any.
TEST(BlockedLayout, ThreadsGiveTheArraysPopulationsBitForBit) {
  for (int threads : {2, 3, 7, 40}) {
    expect_steps_alike<double>(2 * kW<double>, 3, 24, threads, false, 3);
    expect_steps_alike<float>(kW<float>, 4, 24, threads, true, 3);
    expect_steps_alike<double>(kW<double>, 6, 3, threads, true, 2);
  }
}

TEST(BlockedLayout, EveryPathGivesTheArraysPopulations) {
  const KernelIsa best = fluid::kernel_isa();
  for (KernelIsa isa : {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512}) {
    if (isa > best) continue;  // a path this CPU cannot run
    KernelIsaLimit limit(isa);
    SCOPED_TRACE(fluid::kernel_isa_name(isa));
    expect_steps_alike<double>(2 * kW<double>, 5, 12, 2, true, 3);
    expect_steps_alike<float>(2 * kW<float>, 5, 12, 2, false, 3);
  }
}

// The observers, the coupling's batched calls and a checkpoint, after a local and after a
// pulling step, read the same values in both layouts; momentum injected into both, and a state
// carried from one layout into the other, keep the runs alike.
template <class T>
void expect_readers_alike() {
  const int nx = 2 * kW<T>, ny = 4, nz = 3;
  FluidLattice<D3Q19, T> arrays(periodic_box(nx, ny, nz, PopulationLayout::kArrays, 1, true));
  FluidLattice<D3Q19, T> blocks(periodic_box(nx, ny, nz, PopulationLayout::kBlocks, 2, true));
  start(arrays);
  start(blocks);
  std::vector<fluid::NodeIndex> nodes;
  std::vector<double> dp;
  for (int k = 0; k < 12; ++k) {
    nodes.push_back({(5 * k) % nx, (3 * k) % ny, k % nz});
    for (int a = 0; a < 3; ++a) dp.push_back(1e-4 * (k + 1) * (a == 1 ? -1 : 1));
  }
  for (int s = 0; s < 4; ++s) {
    arrays.step();
    blocks.step();
    SCOPED_TRACE("after step " + std::to_string(s + 1));
    EXPECT_EQ(arrays.total_mass(), blocks.total_mass());
    EXPECT_EQ(arrays.total_momentum(), blocks.total_momentum());
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y) {
        double sum_a = 0, sum_b = 0;
        arrays.add_row_velocity_x(y, z, sum_a);
        blocks.add_row_velocity_x(y, z, sum_b);
        EXPECT_EQ(sum_a, sum_b);
        std::vector<double> rho_a(nx), rho_b(nx), u_a(3 * nx), u_b(3 * nx);
        arrays.row_moments(y, z, 0, nx, rho_a.data(), u_a.data());
        blocks.row_moments(y, z, 0, nx, rho_b.data(), u_b.data());
        EXPECT_EQ(rho_a, rho_b);
        EXPECT_EQ(u_a, u_b);
        for (int x = 0; x < nx; ++x) EXPECT_EQ(arrays.velocity(x, y, z), blocks.velocity(x, y, z));
      }
    std::vector<fluid::DensityMomentum> got_a(nodes.size()), got_b(nodes.size());
    arrays.gather_momenta(nodes.data(), static_cast<long>(nodes.size()), got_a.data());
    blocks.gather_momenta(nodes.data(), static_cast<long>(nodes.size()), got_b.data());
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      EXPECT_EQ(got_a[k].rho, got_b[k].rho);
      EXPECT_EQ(got_a[k].momentum, got_b[k].momentum);
    }
    arrays.add_momenta(nodes.data(), dp.data(), static_cast<long>(nodes.size()));
    blocks.add_momenta(nodes.data(), dp.data(), static_cast<long>(nodes.size()));
    const fluid::FluidRawState state_a = arrays.raw_state(), state_b = blocks.raw_state();
    EXPECT_EQ(state_a.populations, state_b.populations);
    EXPECT_EQ(state_a.pulled, state_b.pulled);
  }
  // A checkpoint of the blocks restored into arrays and the other way round: each continues as
  // the run it came from.
  FluidLattice<D3Q19, T> arrays_from_blocks(periodic_box(nx, ny, nz, PopulationLayout::kArrays, 1, true));
  FluidLattice<D3Q19, T> blocks_from_arrays(periodic_box(nx, ny, nz, PopulationLayout::kBlocks, 1, true));
  arrays_from_blocks.restore_raw_state(blocks.raw_state());
  blocks_from_arrays.restore_raw_state(arrays.raw_state());
  for (int s = 0; s < 3; ++s) {
    arrays.step();
    blocks.step();
    arrays_from_blocks.step();
    blocks_from_arrays.step();
  }
  const std::vector<double> expected = every_population(arrays);
  EXPECT_EQ(every_population(blocks), expected);
  EXPECT_EQ(every_population(arrays_from_blocks), expected);
  EXPECT_EQ(every_population(blocks_from_arrays), expected);
}

TEST(BlockedLayout, ObserversBatchedCallsAndCheckpointsReadAlike) {
  expect_readers_alike<double>();
  expect_readers_alike<float>();
}

// Mass and momentum are kept to round-off by the blocked steps themselves (not only by agreeing
// with the arrays): a periodic box without force over 40 steps. The populations are stored less
// w_i rho0, below 0.1 here (ulp 1.4e-17); each of 40 steps x 2,880 cells x 19 populations
// rounds at most a few times: 40 x 2,880 x 19 x 2 ulp = 6e-11 at worst, hence 1e-10.
TEST(BlockedLayout, ConservesMassAndMomentum) {
  FluidLattice<D3Q19, double> fluid(periodic_box(2 * kW<double>, 12, 15, PopulationLayout::kBlocks, 2));
  start(fluid);
  const double mass = fluid.total_mass();
  const Vec3 momentum = fluid.total_momentum();
  fluid.run(40);
  EXPECT_NEAR(fluid.total_mass(), mass, 1e-10);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(fluid.total_momentum()[a], momentum[a], 1e-10);
  EXPECT_GT(std::abs(momentum[0]) + std::abs(momentum[1]) + std::abs(momentum[2]), 1e-3);  // something to keep
}

// Blocks where they do not apply are refused, naming the field and the reason; left to the
// lattice, they are chosen only where they apply.
TEST(BlockedLayout, AskedForWhereTheyDoNotApplyIsAnError) {
  auto expect_refused = [](FluidConfig c, const std::string& reason) {
    c.layout = PopulationLayout::kBlocks;
    try {
      FluidLattice<D3Q19, double> fluid(c);
      FAIL() << "blocks accepted for " << reason;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("layout: blocks do not apply to"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  FluidConfig c = periodic_box(16, 4, 4, PopulationLayout::kBlocks);
  c.streaming = StreamingScheme::kTwoBuffer;
  expect_refused(c, "two-buffer");
  c = periodic_box(16, 4, 4, PopulationLayout::kBlocks);
  c.collision = CollisionModel::kTrt;
  expect_refused(c, "BGK only");
  c = periodic_box(16, 4, 4, PopulationLayout::kBlocks);
  c.sides[fluid::kYLow].kind = c.sides[fluid::kYHigh].kind = WallKind::kBounceBack;
  expect_refused(c, "not periodic");
  expect_refused(periodic_box(12, 4, 4, PopulationLayout::kBlocks), "nx = 12");
  FluidConfig plane;
  plane.nx = 16;
  plane.ny = 4;
  plane.layout = PopulationLayout::kBlocks;
  EXPECT_THROW(([&] { FluidLattice<D2Q9, double> fluid(plane); })(), std::invalid_argument);

  FluidConfig automatic = periodic_box(16, 4, 4, PopulationLayout::kArrays);
  automatic.layout.reset();
  const bool wide = fluid::kernel_isa() == KernelIsa::kAvx512;
  using Fluid = FluidLattice<D3Q19, double>;
  EXPECT_EQ(Fluid::chosen_layout(automatic), wide ? PopulationLayout::kBlocks : PopulationLayout::kArrays);
  automatic.nx = 12;
  EXPECT_EQ(Fluid::chosen_layout(automatic), PopulationLayout::kArrays);
}

}  // namespace
}  // namespace lbsolid::testing
