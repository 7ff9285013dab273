// The exchange done inside the fluid's step (FluidLattice::step_exchanging, in_step_exchange.h)
// against the same exchange around the step (gather_momenta before step(), add_momenta after).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fluid/fluid_test_support.h"
#include "fluid/in_step_exchange.h"

namespace lbsolid::testing {
namespace {

using fluid::CollisionModel;
using fluid::DensityMomentum;
using fluid::MarkWord;
using fluid::NodeIndex;

// Nodes with made-up particle sums (mass M, momentum P a node), exchanged by the common-velocity
// rule: u* = (j + P) / (rho + M), the fluid gains P - M u*. Most nodes are marked; every seventh,
// but inside a run, is an "other" node (one listed late, out of cell order, in MomentumExchange's
// terms).
template <int D>
class TestExchange final : public fluid::InStepExchange {
 public:
  TestExchange(const std::vector<NodeIndex>& nodes, int nx, int ny, long cells) {
    std::vector<long> cells_of_nodes, marked, later;
    for (const NodeIndex& n : nodes) cells_of_nodes.push_back(n[0] + nx * (n[1] + static_cast<long>(ny) * n[2]));
    std::vector<long> sorted_cells = cells_of_nodes;
    std::sort(sorted_cells.begin(), sorted_cells.end());
    const auto is_node = [&](long c) { return std::binary_search(sorted_cells.begin(), sorted_cells.end(), c); };
    for (std::size_t k = 0; k < cells_of_nodes.size(); ++k) {
      const long c = cells_of_nodes[k];
      // Runs stay whole (a node with both row neighbours stays marked): the step takes their
      // inner nodes in blocks of 8.
      const bool inside_run = is_node(c - 1) && is_node(c + 1);
      (k % 7 == 3 && !inside_run ? later : marked).push_back(c);
    }
    std::sort(marked.begin(), marked.end());
    words_.assign(static_cast<std::size_t>((cells + 63) / 64), {});
    others_.assign(words_.size(), 0);
    for (long c : marked) {
      MarkWord& word = words_[static_cast<std::size_t>(c >> 6)];
      if (word.cells == 0) word.first_slot = static_cast<std::uint32_t>(cell_.size());
      word.cells |= std::uint64_t{1} << (c & 63);
      cell_.push_back(c);
    }
    for (long c : later) {
      others_[static_cast<std::size_t>(c >> 6)] |= std::uint64_t{1} << (c & 63);
      cell_.push_back(c);
    }
    for (std::size_t s = 0; s < cell_.size(); ++s) {
      mass_.push_back(0.5 + 0.1 * static_cast<double>(s % 5));
      for (int a = 0; a < D; ++a) momentum_.push_back(0.01 * std::sin(1.0 + static_cast<double>(3 * s + a)));
    }
    read_.assign(cell_.size(), {});
    gain_.assign(D * cell_.size(), 0.0);
    marks = words_.data();
    other_marks = others_.data();
    nx_ = nx;
    ny_ = ny;
  }

  TestExchange(const TestExchange&) = delete;  // marks point at its own vectors
  TestExchange& operator=(const TestExchange&) = delete;

  std::uint32_t other_slot(long cell) const override {
    for (std::size_t s = 0; s < cell_.size(); ++s)
      if (cell_[s] == cell && (others_[static_cast<std::size_t>(cell >> 6)] >> (cell & 63) & 1)) return static_cast<std::uint32_t>(s);
    throw std::logic_error("no such other node");
  }
  // The gains kept (gain()) and written into the step's own, axis by axis.
  void exchange(std::uint32_t first_slot, long count, const fluid::NodesFluid& fluid, fluid::NodesGain& gained) override {
    for (long k = 0; k < count; ++k) {
      compare(first_slot + k, fluid.node(k));
      for (int a = 0; a < D; ++a) gained.momentum[a][k] = gain_[D * (first_slot + k) + a];
    }
  }

  // The slots' nodes, for the calls around the step.
  std::vector<NodeIndex> nodes() const {
    std::vector<NodeIndex> list;
    for (long c : cell_)
      list.push_back({static_cast<int>(c % nx_), static_cast<int>(c / nx_ % ny_), static_cast<int>(c / nx_ / ny_)});
    return list;
  }
  void compare(long s, const DensityMomentum& fluid) {
    read_[s] = fluid;
    const double inverse = 1.0 / (fluid.rho + mass_[s]);
    for (int a = 0; a < D; ++a)
      gain_[D * s + a] = momentum_[D * s + a] - mass_[s] * ((fluid.momentum[a] + momentum_[D * s + a]) * inverse);
  }
  const std::vector<DensityMomentum>& read() const { return read_; }
  const std::vector<double>& gain() const { return gain_; }

 private:
  std::vector<MarkWord> words_;
  std::vector<std::uint64_t> others_;
  std::vector<long> cell_;  // per slot
  std::vector<double> mass_, momentum_, gain_;
  std::vector<DensityMomentum> read_;
  int nx_ = 0, ny_ = 0;
};

// Some nodes of every kind a step treats apart: both edge cells of rows, the rows at the y walls,
// runs of neighbours (a body's row: 20 cells, two blocks of 8 and a remainder where no edge cuts
// it), lone nodes, and pairs of rows without nodes (y = 3 or 0 mod 4 but the wall rows) between
// rows with them, whose reports the step cuts short and whose cells a local step does at once.
std::vector<NodeIndex> some_nodes(int nx, int ny, int nz) {
  std::vector<NodeIndex> nodes;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const bool edge = (x == 0 || x == nx - 1) && (y + z) % 3 == 0;
        const bool wall_row = (y == 0 || y == ny - 1) && x % 5 == 1;
        const bool run = y % 4 == 2 && x >= nx / 3 && x < nx / 3 + 20;
        const bool lone = (x * 7 + y * 13 + z * 5) % 23 == 0;
        const bool empty_row = (y % 4 == 3 || y % 4 == 0) && y != 0 && y != ny - 1;
        if (wall_row || (!empty_row && (edge || run || lone))) nodes.push_back({x, y, z});
      }
  return nodes;
}

// Every population of both lattices, as stored.
std::vector<double> populations(const fluid::FluidRawState& state) { return state.populations; }

// Steps `steps` times both ways from the same non-uniform state and compares: the fluid each node
// reads (the step's from after the collision, the batched call's from before it) and, after each
// step, every population.
//
// The bound: the collision keeps mass and momentum exactly in exact arithmetic, so the two reads
// differ by the rounding of the Q post-collision populations (stored less w_i rho0, each from
// about ten operations on values of order 1, ulp 2.2e-16) and of their sums: a few 1e-15. 1e-13
// leaves room for that and is far below what a wrong slot or a missed force term gives (the
// populations differ by 1e-3 from one cell to the next here, and the force is 1e-5).
template <class L>
void expect_alike(fluid::FluidConfig config, const std::string& context, int steps = 4) {
  constexpr int D = L::D;
  FluidLattice<L, double> around(config), inside(config);
  config.threads = 3;
  FluidLattice<L, double> inside_threads(config);
  ASSERT_TRUE(inside.can_exchange_in_step()) << context;
  const auto density = [](int x, int y, int z) { return 1.0 + 0.01 * std::sin(0.7 * x + 1.3 * y + 0.4 * z); };
  const auto velocity = [](int x, int y, int z) {
    return Vec3{0.02 * std::cos(0.5 * y + 0.2 * z), 0.01 * std::sin(0.3 * x), D == 3 ? 0.01 * std::cos(0.6 * x) : 0.0};
  };
  for (auto* f : {&around, &inside, &inside_threads}) f->initialize(density, velocity);
  const std::vector<NodeIndex> some = some_nodes(config.nx, config.ny, config.nz);
  TestExchange<D> apart(some, config.nx, config.ny, around.cells()), in_step(some, config.nx, config.ny, around.cells()),
      in_step_threads(some, config.nx, config.ny, around.cells());
  const std::vector<NodeIndex> nodes = apart.nodes();
  ASSERT_GT(nodes.size(), 20u) << context;
  std::vector<DensityMomentum> read(nodes.size());
  long compared = 0;
  for (int s = 0; s < steps; ++s) {
    around.gather_momenta(nodes.data(), static_cast<long>(nodes.size()), read.data());
    for (std::size_t k = 0; k < nodes.size(); ++k) apart.compare(static_cast<long>(k), read[k]);
    around.step();
    around.add_momenta(nodes.data(), apart.gain().data(), static_cast<long>(nodes.size()));
    inside.step_exchanging(in_step);
    inside_threads.step_exchanging(in_step_threads);
    const std::string at = context + ", step " + std::to_string(s);
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const DensityMomentum &a = apart.read()[k], &b = in_step.read()[k];
      ASSERT_NEAR(a.rho, b.rho, 1e-13) << at << ", node " << k;
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(a.momentum[c], b.momentum[c], 1e-13) << at << ", node " << k;
      // Threads change nothing, bit for bit.
      ASSERT_EQ(b.rho, in_step_threads.read()[k].rho) << at;
      ASSERT_EQ(b.momentum, in_step_threads.read()[k].momentum) << at;
    }
    const std::vector<double> pa = populations(around.raw_state()), pb = populations(inside.raw_state());
    ASSERT_EQ(pa.size(), pb.size());
    for (std::size_t i = 0; i < pa.size(); ++i) ASSERT_NEAR(pa[i], pb[i], 1e-13) << at << ", value " << i;
    ASSERT_EQ(pb, populations(inside_threads.raw_state())) << at;
    compared += static_cast<long>(nodes.size());
  }
  EXPECT_EQ(compared, steps * static_cast<long>(nodes.size()));
}

fluid::FluidConfig box(int nx, int ny, int nz, CollisionModel collision, bool walls, bool force) {
  fluid::FluidConfig c;
  c.nx = nx;
  c.ny = ny;
  c.nz = nz;
  c.omega = 1.3;
  c.collision = collision;
  c.layout = fluid::PopulationLayout::kArrays;
  if (walls) c.sides[fluid::kYLow].kind = c.sides[fluid::kYHigh].kind = WallKind::kBounceBack;
  if (force) c.body_force = {1e-5, -2e-5, nz > 1 ? 1e-5 : 0.0};
  return c;
}

std::string name(const std::string& lattice, CollisionModel collision, bool walls, bool force) {
  return lattice + ", " + fluid::collision_model_name(collision) + (walls ? ", walls" : ", periodic") +
         (force ? ", force" : "");
}

// Every lattice and collision, with and without walls and force. D3Q19 boxes 32 cells wide, so
// that the pulling step sweeps joined rows with their edge cells from the copies at the joins
// (rows reported as the sweep passes them) as well as the other ways.
TEST(InStepExchange, ReadsAndGivesWhatTheCallsAroundTheStepDo) {
  for (CollisionModel collision : {CollisionModel::kBgk, CollisionModel::kTrt, CollisionModel::kRegularized})
    for (bool walls : {false, true})
      for (bool force : {false, true}) {
        expect_alike<D2Q9>(box(40, 14, 1, collision, walls, force), name("D2Q9", collision, walls, force));
        expect_alike<D2Q7>(box(40, 14, 1, collision, walls, force), name("D2Q7", collision, walls, force));
        expect_alike<D3Q19>(box(32, 12, 6, collision, walls, force), name("D3Q19", collision, walls, force));
      }
}

// In blocks (D3Q19, BGK, every side periodic, nx a multiple of 8), against the calls around the
// step in blocks, with and without a force: 6 planes (3 threads then do the planes at the parts'
// boundaries one after another) and 30 (10 a part: those planes all at once).
TEST(InStepExchange, InBlocksReadsAndGivesWhatTheCallsAroundTheStepDo) {
  for (int nz : {6, 30})
    for (bool force : {false, true}) {
      fluid::FluidConfig config = box(32, 12, nz, CollisionModel::kBgk, false, force);
      config.layout = fluid::PopulationLayout::kBlocks;
      expect_alike<D3Q19>(config, name("D3Q19 in blocks", CollisionModel::kBgk, false, force) + ", nz " + std::to_string(nz));
    }
}

// The blocks' kernels give the arrays' populations bit for bit, and the exchange inside the step
// reads and adds the same terms in the same order in either layout (step_nodes.h): the fluid, and
// what each node reads, are the arrays' bit for bit, with 1 thread and with 3.
TEST(InStepExchange, InBlocksTheSameBitForBitAsInArrays) {
  for (bool force : {false, true}) {
    fluid::FluidConfig config = box(32, 12, 30, CollisionModel::kBgk, false, force);
    FluidLattice<D3Q19, double> arrays(config);
    config.layout = fluid::PopulationLayout::kBlocks;
    FluidLattice<D3Q19, double> blocks(config);
    config.threads = 3;
    FluidLattice<D3Q19, double> blocks_threads(config);
    const auto density = [](int x, int y, int z) { return 1.0 + 0.01 * std::sin(0.7 * x + 1.3 * y + 0.4 * z); };
    const auto velocity = [](int x, int y, int z) {
      return Vec3{0.02 * std::cos(0.5 * y + 0.2 * z), 0.01 * std::sin(0.3 * x), 0.01 * std::cos(0.6 * x)};
    };
    for (auto* f : {&arrays, &blocks, &blocks_threads}) f->initialize(density, velocity);
    const std::vector<NodeIndex> some = some_nodes(config.nx, config.ny, config.nz);
    TestExchange<3> in_arrays(some, config.nx, config.ny, arrays.cells()), in_blocks(some, config.nx, config.ny, arrays.cells()),
        in_blocks_threads(some, config.nx, config.ny, arrays.cells());
    for (int s = 0; s < 4; ++s) {  // two local steps and two pulling steps
      arrays.step_exchanging(in_arrays);
      blocks.step_exchanging(in_blocks);
      blocks_threads.step_exchanging(in_blocks_threads);
      const std::string at = std::string(force ? "force" : "no force") + ", step " + std::to_string(s);
      for (std::size_t k = 0; k < in_arrays.read().size(); ++k) {
        ASSERT_EQ(in_arrays.read()[k].rho, in_blocks.read()[k].rho) << at << ", node " << k;
        ASSERT_EQ(in_arrays.read()[k].momentum, in_blocks.read()[k].momentum) << at << ", node " << k;
        ASSERT_EQ(in_arrays.read()[k].rho, in_blocks_threads.read()[k].rho) << at << ", node " << k;
        ASSERT_EQ(in_arrays.read()[k].momentum, in_blocks_threads.read()[k].momentum) << at << ", node " << k;
      }
      const std::vector<double> expected = populations(arrays.raw_state());
      ASSERT_EQ(expected, populations(blocks.raw_state())) << at;
      ASSERT_EQ(expected, populations(blocks_threads.raw_state())) << at;
    }
  }
}

// Where the step stores a population through a wall rule with a scale or a correction (a moving
// wall, a pressure outlet), or between two buffers, it cannot read a node's fluid from what it
// stored: it says so, and refuses.
TEST(InStepExchange, OnlyWhereEveryPopulationIsStoredAsItIs) {
  struct Case {
    std::string what;
    fluid::FluidConfig config;
  };
  std::vector<Case> refused;
  fluid::FluidConfig moving = box(16, 8, 1, CollisionModel::kBgk, true, false);
  moving.sides[fluid::kYHigh].kind = WallKind::kMovingWall;
  moving.sides[fluid::kYHigh].wall_velocity = {0.01, 0, 0};
  refused.push_back({"a moving wall", moving});
  fluid::FluidConfig two_buffers = box(16, 8, 1, CollisionModel::kBgk, true, false);
  two_buffers.streaming = fluid::StreamingScheme::kTwoBuffer;
  refused.push_back({"two buffers", two_buffers});
  for (const Case& c : refused) {
    FluidLattice<D2Q9, double> fluid(c.config);
    EXPECT_FALSE(fluid.can_exchange_in_step()) << c.what;
    TestExchange<2> exchange(some_nodes(16, 8, 1), 16, 8, fluid.cells());
    EXPECT_THROW(fluid.step_exchanging(exchange), std::logic_error) << c.what;
  }
  // Stationary walls and periodic sides store every population as it is, in either layout.
  EXPECT_TRUE((FluidLattice<D2Q7, double>(box(16, 8, 1, CollisionModel::kBgk, true, true)).can_exchange_in_step()));
  fluid::FluidConfig blocks = box(32, 8, 8, CollisionModel::kBgk, false, false);
  blocks.layout = fluid::PopulationLayout::kBlocks;
  EXPECT_TRUE((FluidLattice<D3Q19, double>(blocks).can_exchange_in_step()));
}

}  // namespace
}  // namespace lbsolid::testing
