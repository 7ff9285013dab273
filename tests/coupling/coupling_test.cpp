// The solid-fluid coupling (MODEL.md section 3): nearest nodes on each lattice's geometry, the
// common-velocity exchange, and conservation of fluid plus solid momentum in a periodic box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cstdint>
#include <cmath>
#include <iterator>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling/momentum_exchange.h"
#include "coupling/node_locator.h"
#include "fluid/kernel_isa.h"
#include "fluid/fluid_test_support.h"
#include "lattice/d2q7.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"
#include "parallel/thread_pool.h"
#include "scene/simulation.h"

namespace lbsolid::coupling {
namespace {

using testing::report;
using fluid::Vec3;

fluid::FluidConfig box(int nx, int ny, int nz, bool walls) {
  fluid::FluidConfig c;
  c.nx = nx;
  c.ny = ny;
  c.nz = nz;
  if (walls) c.sides[fluid::kYLow].kind = c.sides[fluid::kYHigh].kind = fluid::WallKind::kBounceBack;
  return c;
}

// The nearest node found must be at least as near as every node of the grid (brute force), both
// by nearest() and by the vectorised nearest_cells(), which must also break ties alike (the runs
// would otherwise change). Walled axes are sampled inside the box, where "nearest" is the
// geometric question; beyond a wall both clamp (NearestIsANodeForAnyDouble).
template <class L>
void check_nearest(const fluid::FluidConfig& c) {
  NodeLocator<L> locator(c);
  std::mt19937_64 rng(7);
  const int n[3] = {c.nx, c.ny, c.nz};
  const double spacing[3] = {1.0, L::row_spacing, 1.0};
  bool periodic[3];
  for (int a = 0; a < 3; ++a) periodic[a] = c.sides[2 * a].kind == fluid::WallKind::kPeriodic;
  constexpr long kTrials = 2000;
  std::vector<double> positions;
  for (long trial = 0; trial < kTrials; ++trial)
    for (int a = 0; a < L::D; ++a) {
      const double width = n[a] * spacing[a];
      double v = std::uniform_real_distribution<double>(-3, width + 3)(rng);
      if (!periodic[a]) v = std::clamp(v, 0.0, (n[a] - 1) * spacing[a]);
      positions.push_back(v);
    }
  std::vector<std::uint32_t> cells(kTrials);
  const long split = 777;  // two ranges: the second starts mid-array
  locator.nearest_cells(positions.data(), 0, split, cells.data());
  locator.nearest_cells(positions.data(), split, kTrials, cells.data());
  for (long trial = 0; trial < kTrials; ++trial) {
    const double* p = &positions[L::D * trial];
    const Vec3 r{p[0], p[1], L::D == 3 ? p[2] : 0.0};
    auto distance2 = [&](int x, int y, int z) {
      const Vec3 q = fluid::FluidLattice<L, double>::position(x, y, z);
      double d2 = 0;
      for (int a = 0; a < L::D; ++a) {
        const double d = periodic[a] ? std::remainder(q[a] - r[a], n[a] * spacing[a]) : q[a] - r[a];
        d2 += d * d;
      }
      return d2;
    };
    double best = INFINITY;
    for (int z = 0; z < c.nz; ++z)
      for (int y = 0; y < c.ny; ++y)
        for (int x = 0; x < c.nx; ++x) best = std::min(best, distance2(x, y, z));
    const std::string at = "position " + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " + std::to_string(r[2]);
    const Node found = locator.nearest(r);
    ASSERT_NEAR(distance2(found[0], found[1], found[2]), best, 1e-12) << at;
    const long cell = cells[trial];
    const int x = static_cast<int>(cell % c.nx), y = static_cast<int>(cell / c.nx % c.ny),
              z = static_cast<int>(cell / (static_cast<long>(c.nx) * c.ny));
    ASSERT_LT(z, c.nz) << at;
    ASSERT_NEAR(distance2(x, y, z), best, 1e-12) << "nearest_cells, " << at;
    ASSERT_EQ(cell, locator.cell(found)) << "nearest_cells breaks a tie unlike nearest(), " << at;
  }
}

fluid::FluidConfig walled_box(int nx, int ny, int nz, int dimension) {
  fluid::FluidConfig c = box(nx, ny, nz, false);
  for (int side = 0; side < 2 * dimension; ++side) c.sides[side].kind = fluid::WallKind::kBounceBack;
  return c;
}

// nearest_cells() runs the best instruction set the CPU has (fluid/kernel_isa.h), as the fluid
// kernels do: each check runs on every path this CPU has, the best restored after.
template <class Check>
void on_every_kernel_isa(const Check& check) {
  struct Restore {
    ~Restore() { fluid::limit_kernel_isa(fluid::KernelIsa::kAvx512); }
  } restore;
  for (auto isa : {fluid::KernelIsa::kBaseline, fluid::KernelIsa::kAvx2, fluid::KernelIsa::kAvx512}) {
    fluid::limit_kernel_isa(isa);
    SCOPED_TRACE(fluid::kernel_isa_name(fluid::kernel_isa()));
    check();
  }
}

TEST(NodeLocator, NearestNodeOnSquareAndTriangularGrids) {
  on_every_kernel_isa([] {
    check_nearest<lattice::D2Q9>(box(10, 8, 1, false));
    check_nearest<lattice::D2Q9>(walled_box(9, 7, 1, 2));
    check_nearest<lattice::D2Q7>(box(10, 8, 1, false));
    check_nearest<lattice::D2Q7>(box(9, 7, 1, true));
    check_nearest<lattice::D2Q7>(walled_box(9, 7, 1, 2));
  });
}

TEST(NodeLocator, NearestNodeOnCubicGrids) {
  on_every_kernel_isa([] {
    check_nearest<lattice::D3Q19>(box(6, 5, 4, false));
    check_nearest<lattice::D3Q19>(box(6, 5, 4, true));
    check_nearest<lattice::D3Q19>(walled_box(6, 5, 4, 3));
  });
}

// Between two monitor checks a diverging particle can reach NaN or 1e300, and the exchange still
// asks for its node: nearest() must give a node of the grid for any double (casting such a value to
// long is undefined). A NaN coordinate is read as 0; on a walled axis a huge or infinite one gives
// the first or last node, as any position beyond the wall does.
template <class L>
void check_any_double(const fluid::FluidConfig& c) {
  const NodeLocator<L> locator(c);
  const double values[] = {NAN, -NAN, INFINITY, -INFINITY, 1e300, -1e300, 1e18, -1e18, DBL_MAX, -DBL_MAX, 0.3};
  const int n[3] = {c.nx, c.ny, c.nz};
  const bool periodic[3] = {c.sides[fluid::kXLow].kind == fluid::WallKind::kPeriodic,
                            c.sides[fluid::kYLow].kind == fluid::WallKind::kPeriodic,
                            c.sides[fluid::kZLow].kind == fluid::WallKind::kPeriodic};
  const int count = std::size(values);
  // nearest_cells() over all the combinations at once (its vectorised loop, not only its tail).
  std::vector<double> positions;
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      for (int k = 0; k < (L::D == 3 ? count : 1); ++k) {
        positions.insert(positions.end(), {values[i], values[j]});
        if (L::D == 3) positions.push_back(values[k]);
      }
  std::vector<std::uint32_t> cells(positions.size() / L::D);
  locator.nearest_cells(positions.data(), 0, static_cast<long>(cells.size()), cells.data());
  long index = 0;
  for (int i = 0; i < count; ++i)
    for (int j = 0; j < count; ++j)
      for (int k = 0; k < (L::D == 3 ? count : 1); ++k, ++index) {
        const Vec3 r{values[i], values[j], L::D == 3 ? values[k] : 0.0};
        const Node found = locator.nearest(r);
        const std::string at = "at (" + std::to_string(r[0]) + ", " + std::to_string(r[1]) + ", " +
                               std::to_string(r[2]) + ")";
        for (int a = 0; a < 3; ++a) {
          ASSERT_GE(found[a], 0) << at;
          ASSERT_LT(found[a], a < L::D ? n[a] : 1) << at;
          if (a >= L::D || periodic[a] || std::isnan(r[a]) || std::abs(r[a]) < 1e18) continue;
          EXPECT_EQ(found[a], r[a] > 0 ? n[a] - 1 : 0) << "axis " << a << " " << at;
        }
        const Vec3 nan_as_zero{std::isnan(r[0]) ? 0 : r[0], std::isnan(r[1]) ? 0 : r[1], std::isnan(r[2]) ? 0 : r[2]};
        EXPECT_EQ(found, locator.nearest(nan_as_zero)) << at;
        EXPECT_EQ(cells[index], locator.cell(found)) << "nearest_cells " << at;
      }
}

TEST(NodeLocator, NearestIsANodeForAnyDouble) {
  on_every_kernel_isa([] {
    check_any_double<lattice::D2Q9>(box(10, 8, 1, false));
    check_any_double<lattice::D2Q9>(walled_box(10, 8, 1, 2));
    check_any_double<lattice::D2Q7>(box(10, 8, 1, false));
    check_any_double<lattice::D2Q7>(walled_box(9, 7, 1, 2));
    check_any_double<lattice::D3Q19>(box(6, 5, 4, false));
    check_any_double<lattice::D3Q19>(walled_box(6, 5, 4, 3));
  });
}

// A fluid at one state everywhere, answering the exchange's batched read.
struct UniformFluid {
  fluid::Moments state;
  void gather_momenta(const fluid::NodeIndex*, long count, fluid::DensityMomentum* out) const {
    for (long k = 0; k < count; ++k)
      out[k] = {state.rho, {state.rho * state.u[0], state.rho * state.u[1], state.rho * state.u[2]}};
  }
};

// Vectors laid out as a 3D solid stores them (particle_vectors.h).
std::vector<double> flattened(const std::vector<Vec3>& v) {
  std::vector<double> flat;
  for (const Vec3& x : v) flat.insert(flat.end(), x.begin(), x.end());
  return flat;
}

// One exchange leaves a lone particle and its node at the same velocity, with dP = Z (u_s - u_f),
// 1/Z = 1/rho + 1/M (eq. 14).
TEST(MomentumExchange, LoneParticleAndItsNodeReachOneVelocity) {
  MomentumExchange exchange({4, 1, 1}, ExchangeRule::kCommonVelocity);
  const fluid::Moments fluid_state{1.07, {0.01, -0.02, 0.003}};
  const double mass = 1.5;
  const Vec3 psi{0.09, 0.012, -0.03};
  exchange.locate(1, [](long) { return CellIndex{1}; });
  exchange.compute({mass}, {psi.data(), 3}, UniformFluid{fluid_state});
  const std::vector<Vec3> dp{exchange.particle_dp<3>(0, psi, mass)};
  const auto nodes = exchange.exchanged();
  ASSERT_EQ(nodes.size(), 1);
  const double z = 1.0 / (1.0 / fluid_state.rho + 1.0 / mass);
  double worst = 0;
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(dp[0][a], z * (psi[a] / mass - fluid_state.u[a]), 1e-16);
    const double u_fluid = (fluid_state.rho * fluid_state.u[a] + nodes.gained[0][a]) / fluid_state.rho;
    const double u_solid = (psi[a] - dp[0][a]) / mass;
    worst = std::max(worst, std::abs(u_fluid - u_solid));
  }
  report("|u_s - u_f| after one exchange", worst, 1e-15);
  EXPECT_LT(worst, 1e-15);
}

// Several particles on one node: the common-velocity rule leaves all of them and the fluid at one
// velocity; eq. 14 applied to each particle against the same fluid overshoots that velocity.
TEST(MomentumExchange, SeveralParticlesOnOneNodeShareOneVelocity) {
  const fluid::Moments fluid_state{1.0, {0, 0, 0}};
  const std::vector<double> mass{2, 2, 2, 2};
  const std::vector<Vec3> psi{{0.2, 0, 0}, {0.2, 0, 0}, {0.2, 0, 0}, {0.2, 0, 0}};  // u_s = 0.1
  const std::vector<double> psi_stored = flattened(psi);
  const solid::ParticleVectors momenta{psi_stored.data(), 3};
  const auto on_one_node = [](long) { return CellIndex{0}; };
  MomentumExchange common({1, 1, 1}, ExchangeRule::kCommonVelocity);
  common.locate(4, on_one_node);
  common.compute(mass, momenta, UniformFluid{fluid_state});
  const double gained = common.exchanged().gained[0][0];
  const double u_star = 0.8 / 9.0;
  EXPECT_NEAR(gained / fluid_state.rho, u_star, 1e-16);
  for (int p = 0; p < 4; ++p)
    EXPECT_NEAR((psi[p][0] - common.particle_dp<3>(p, psi[p], mass[p])[0]) / mass[p], u_star, 1e-16);
  MomentumExchange pairwise({1, 1, 1}, ExchangeRule::kPairwise);
  pairwise.locate(4, on_one_node);
  pairwise.compute(mass, momenta, UniformFluid{fluid_state});
  const double overshoot = pairwise.exchanged().gained[0][0];
  report("pairwise fluid velocity / particle velocity before exchange", overshoot / 0.1, 1.0);
  EXPECT_GT(overshoot / fluid_state.rho, 0.1);  // the fluid ends faster than the particles were
}

// A fluid whose every node differs, so that a particle given another node's velocity shows.
struct NodeDependentFluid {
  static fluid::DensityMomentum at(const fluid::NodeIndex& n) {
    return {1.0 + 0.001 * n[0] + 0.01 * n[1], {0.002 * n[0] - 0.05, 0.01 * n[1] - 0.003 * (n[0] % 7), 0.0}};
  }
  void gather_momenta(const fluid::NodeIndex* nodes, long count, fluid::DensityMomentum* out) const {
    for (long k = 0; k < count; ++k) out[k] = at(nodes[k]);
  }
};

// One exchange of particles on `cells` of an nx-wide 2D grid, with random masses and momenta,
// checked against what is worked out here: the nodes listed are the distinct cells, and each
// particle gets dP = M (u - u*) with u* from its own node's fluid and particles.
void expect_each_particle_meets_its_own_node(MomentumExchange& exchange, int nx, const std::vector<CellIndex>& cells,
                                             int parts, parallel::ThreadPool* pool, std::mt19937& random,
                                             const std::string& context) {
  std::vector<double> mass, momentum;
  std::uniform_real_distribution<double> uniform(0.5, 1.5);
  for (std::size_t p = 0; p < cells.size(); ++p) {
    mass.push_back(uniform(random));
    momentum.push_back(0.1 * (uniform(random) - 1));
    momentum.push_back(0.1 * (uniform(random) - 1));
  }
  exchange.locate(static_cast<long>(cells.size()), [&](long p) { return cells[p]; }, pool, parts);
  exchange.compute(mass, {momentum.data(), 2}, NodeDependentFluid{}, pool, parts);
  std::vector<CellIndex> distinct = cells;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  EXPECT_EQ(exchange.exchanged().size(), static_cast<long>(distinct.size())) << context;
  std::map<CellIndex, fluid::DensityMomentum> node_sums;  // each node's fluid plus its particles
  for (std::size_t p = 0; p < cells.size(); ++p) {
    const fluid::NodeIndex node{static_cast<int>(cells[p] % nx), static_cast<int>(cells[p] / nx), 0};
    auto [at, added] = node_sums.try_emplace(cells[p], NodeDependentFluid::at(node));
    at->second.rho += mass[p];
    for (int a = 0; a < 2; ++a) at->second.momentum[a] += momentum[2 * p + a];
  }
  double worst = 0;
  for (std::size_t p = 0; p < cells.size(); ++p) {
    const fluid::DensityMomentum& sum = node_sums.at(cells[p]);
    const Vec3 psi{momentum[2 * p], momentum[2 * p + 1], 0};
    const Vec3 dp = exchange.particle_dp<2>(static_cast<long>(p), psi, mass[p]);
    for (int a = 0; a < 2; ++a) worst = std::max(worst, std::abs(dp[a] - (psi[a] - mass[p] * sum.momentum[a] / sum.rho)));
  }
  // The same sums in another order: dP (about 0.1) differs by a few units in its last place
  // (1.4e-17 each). A neighbouring node's u* differs by about 1e-3, so any wrong slot fails.
  EXPECT_LT(worst, 1e-15) << context;
}

// The exchange finds a particle's node by counting the marked cells of a 64-cell word before its
// own (on every instruction-set path: popcnt or a count in registers). Particles in random order
// on random cells of a 200 x 3 grid (ten words, the last one short; the first and last cells of
// words included), several on some cells. Twice, on other cells, to show no mark outlives its
// exchange; in 1, 3 and 12 parts (12: more than the grid's ten blocks, so some get no cells).
TEST(MomentumExchange, EachParticleMeetsItsOwnNode) {
  const int nx = 200, ny = 3;
  std::mt19937 random(7);
  const auto check = [&](int parts, parallel::ThreadPool* pool) {
    MomentumExchange exchange({nx, ny, 1}, ExchangeRule::kCommonVelocity);
    for (int round = 0; round < 2; ++round) {
      std::vector<CellIndex> cells{0, 63, 64, 127, 128, 191, 599, 599};
      std::uniform_int_distribution<int> any_cell(0, nx * ny - 1);
      while (cells.size() < 150) cells.push_back(static_cast<CellIndex>(any_cell(random)));
      std::shuffle(cells.begin(), cells.end(), random);
      expect_each_particle_meets_its_own_node(exchange, nx, cells, parts, pool, random,
                                              "round " + std::to_string(round) + ", " + std::to_string(parts) + " parts");
    }
  };
  parallel::ThreadPool pool(3);
  on_every_kernel_isa([&] {
    check(1, nullptr);
    check(3, &pool);
    check(12, &pool);
  });
}

// Most particles in the grid's last, short block of cells (200 x 3: cells 576-599): from the
// second exchange on, the cut that balances the parts gives the first part every cell and leaves
// the others empty at the grid's end, inside that block's word. An empty part must touch no word:
// it once listed the first part's marks of that word as its own and cleared them while the first
// part, busy with its 20,000 particles on another thread, still needed them (wrong dP, and
// writes past the slots; seen in most runs of this test). With 9 parts, 8 are left empty.
TEST(MomentumExchange, PartsLeftEmptyAtTheGridsEndTouchNoMark) {
  const int nx = 200, ny = 3;
  std::mt19937 random(11);
  parallel::ThreadPool pool(3);
  for (int parts : {2, 3, 9}) {
    MomentumExchange exchange({nx, ny, 1}, ExchangeRule::kCommonVelocity);
    for (int round = 0; round < 3; ++round) {
      std::vector<CellIndex> cells{5, 130};
      std::uniform_int_distribution<int> last_block(576, 599);
      while (cells.size() < 20000) cells.push_back(static_cast<CellIndex>(last_block(random)));
      std::shuffle(cells.begin(), cells.end(), random);
      expect_each_particle_meets_its_own_node(exchange, nx, cells, parts, &pool, random,
                                              "round " + std::to_string(round) + ", " + std::to_string(parts) + " parts");
    }
  }
}

// A fluid that records what add_momenta gives each node (summed; parts call it from several
// threads), and reads as NodeDependentFluid.
struct RecordingFluid : NodeDependentFluid {
  static constexpr int D = 2;
  std::map<CellIndex, std::array<double, 2>> gained;
  int nx = 0;
  std::mutex recording;
  void add_momenta(const fluid::NodeIndex* nodes, const double* dp, long count) {
    std::lock_guard lock(recording);
    for (long k = 0; k < count; ++k) {
      auto& g = gained[static_cast<CellIndex>(nodes[k][0] + nx * nodes[k][1])];
      g[0] += dp[2 * k];
      g[1] += dp[2 * k + 1];
    }
  }
};

// The listing kept between exchanges (particles moving to listed nodes, to nodes not listed yet,
// leaving nodes empty; anchors among them) gives every particle and every node exactly what a
// fresh exchange, which lists its nodes anew, gives them. 2,000 particles random-walk on a 100 x 40
// grid, 1% of them stepping to a neighbouring cell each exchange, for 60 exchanges, in 1, 3 and 12
// parts (several parts walk their particles sorted by part, sorted again when one moves to
// another part's cells). Some exchanges must have kept the listing and some listed afresh, or the
// comparison would test nothing.
TEST(MomentumExchange, KeptListingGivesWhatAFreshOneGives) {
  const int nx = 100, ny = 40;
  std::mt19937 random(5);
  parallel::ThreadPool pool(3);
  for (int parts : {1, 3, 12}) {
    std::uniform_int_distribution<int> any_cell(0, nx * ny - 1), step(-1, 1);
    std::uniform_real_distribution<double> uniform(0.5, 1.5);
    std::vector<CellIndex> cells;
    std::vector<double> mass, momentum;
    std::vector<char> anchored;
    for (int p = 0; p < 2000; ++p) {
      cells.push_back(static_cast<CellIndex>(any_cell(random)));
      mass.push_back(uniform(random));
      momentum.push_back(0.1 * (uniform(random) - 1));
      momentum.push_back(0.1 * (uniform(random) - 1));
      anchored.push_back(p % 97 == 0);
    }
    parallel::ThreadPool* on = parts > 1 ? &pool : nullptr;
    MomentumExchange kept({nx, ny, 1}, ExchangeRule::kCommonVelocity);
    int kept_count = 0, relisted_count = 0;
    for (int exchange = 0; exchange < 60; ++exchange) {
      for (std::size_t p = 0; p < cells.size(); ++p) {
        if (random() % 100 != 0) continue;
        const int x = (static_cast<int>(cells[p] % nx) + step(random) + nx) % nx;
        const int y = (static_cast<int>(cells[p] / nx) + step(random) + ny) % ny;
        cells[p] = static_cast<CellIndex>(x + nx * y);
      }
      MomentumExchange fresh({nx, ny, 1}, ExchangeRule::kCommonVelocity);
      RecordingFluid kept_fluid, fresh_fluid;
      kept_fluid.nx = fresh_fluid.nx = nx;
      const auto cell_of = [&](long p) { return cells[p]; };
      for (MomentumExchange* e : {&kept, &fresh}) {
        e->locate(static_cast<long>(cells.size()), cell_of, on, parts);
        e->compute(mass, {momentum.data(), 2}, NodeDependentFluid{}, on, parts, &anchored);
      }
      (kept.relisted() ? relisted_count : kept_count) += 1;
      kept.inject(kept_fluid, on);
      fresh.inject(fresh_fluid, on);
      const std::string context = std::to_string(parts) + " parts, exchange " + std::to_string(exchange);
      for (std::size_t p = 0; p < cells.size(); ++p) {
        const Vec3 psi{momentum[2 * p], momentum[2 * p + 1], 0};
        const long i = static_cast<long>(p);
        ASSERT_EQ(kept.particle_dp<2>(i, psi, mass[p]), fresh.particle_dp<2>(i, psi, mass[p])) << context << ", " << p;
        if (anchored[p]) {
          ASSERT_EQ(kept.anchor_dp(i), fresh.anchor_dp(i)) << context << ", " << p;
        }
      }
      const ExchangedNodes kept_nodes = kept.exchanged(), fresh_nodes = fresh.exchanged();
      ASSERT_EQ(kept_nodes.nodes, fresh_nodes.nodes) << context;
      ASSERT_EQ(kept_nodes.gained, fresh_nodes.gained) << context;
      // Every node the fresh exchange gives momentum gets the same from the kept one; a node only
      // the kept one still lists (left empty) gets exactly nothing.
      for (const auto& [cell, g] : fresh_fluid.gained) {
        const auto at = kept_fluid.gained.find(cell);
        ASSERT_TRUE(at != kept_fluid.gained.end()) << context << ", cell " << cell;
        ASSERT_EQ(at->second, g) << context << ", cell " << cell;
      }
      for (const auto& [cell, g] : kept_fluid.gained) {
        if (!fresh_fluid.gained.contains(cell)) {
          ASSERT_EQ(g, (std::array<double, 2>{0, 0})) << context << ", cell " << cell;
        }
      }
    }
    EXPECT_GT(kept_count, 30) << parts << " parts";
    EXPECT_GT(relisted_count, 1) << parts << " parts";
  }
}

// Locating a block at a time inside another pass over the particles (begin_locate and a
// RangeLocator a range, as the solid's step does) against locate_ranges over the same cells: the
// same listing kept or made afresh at each exchange, and the same dP for every particle bit for
// bit. The ranges' blocks are of odd sizes (unlike locate's chunks), some exchanges move 1% of
// the particles (a listing kept) and every tenth a tenth of them (more than a kept listing
// allows: the ranges stop noting and the next exchange lists afresh).
TEST(MomentumExchange, LocatingInBlocksGivesWhatLocatingInRangesGives) {
  const int nx = 90, ny = 50;
  std::mt19937 random(11);
  std::uniform_int_distribution<int> any_cell(0, nx * ny - 1), step(-1, 1);
  std::uniform_real_distribution<double> uniform(0.5, 1.5);
  std::vector<CellIndex> cells;
  std::vector<double> mass, momentum;
  for (int p = 0; p < 3000; ++p) {
    cells.push_back(static_cast<CellIndex>(any_cell(random)));
    mass.push_back(uniform(random));
    momentum.push_back(0.1 * (uniform(random) - 1));
    momentum.push_back(0.1 * (uniform(random) - 1));
  }
  const long n = static_cast<long>(cells.size());
  const auto fill = [&](long first, long end, CellIndex* out) { std::copy(&cells[first], &cells[end], out + first); };
  parallel::ThreadPool pool(3);
  for (int parts : {1, 3}) {
    parallel::ThreadPool* on = parts > 1 ? &pool : nullptr;
    MomentumExchange in_ranges({nx, ny, 1}, ExchangeRule::kCommonVelocity);
    MomentumExchange in_blocks({nx, ny, 1}, ExchangeRule::kCommonVelocity);
    int kept = 0, relisted = 0;
    for (int exchange = 0; exchange < 60; ++exchange) {
      const unsigned moving = exchange % 10 == 9 ? 10 : 100;  // one particle in this many moves
      for (CellIndex& c : cells) {
        if (random() % moving != 0) continue;
        const int x = (static_cast<int>(c % nx) + step(random) + nx) % nx;
        const int y = (static_cast<int>(c / nx) + step(random) + ny) % ny;
        c = static_cast<CellIndex>(x + nx * y);
      }
      in_ranges.locate_ranges(n, fill, on, parts);
      in_blocks.begin_locate(n);
      // Ranges cut as a pool would (their order is no matter), their blocks 1 to 97 particles.
      for (int r = 0; r < parts; ++r) {
        MomentumExchange::RangeLocator range(in_blocks);
        for (long first = n * r / parts, end = n * (r + 1) / parts, block; first < end; first += block) {
          block = std::min<long>(end - first, 1 + random() % 97);
          range(first, first + block, fill);
        }
        range.finish();
      }
      for (MomentumExchange* e : {&in_ranges, &in_blocks}) e->compute(mass, {momentum.data(), 2}, NodeDependentFluid{}, on, parts);
      const std::string context = std::to_string(parts) + " parts, exchange " + std::to_string(exchange);
      ASSERT_EQ(in_blocks.relisted(), in_ranges.relisted()) << context;
      (in_ranges.relisted() ? relisted : kept) += 1;
      for (long p = 0; p < n; ++p) {
        const Vec3 psi{momentum[2 * p], momentum[2 * p + 1], 0};
        ASSERT_EQ(in_blocks.particle_dp<2>(p, psi, mass[p]), in_ranges.particle_dp<2>(p, psi, mass[p])) << context;
      }
    }
    // Both ways were exercised: listings kept, and made afresh beyond the first.
    EXPECT_GT(kept, 20) << parts << " parts";
    EXPECT_GT(relisted, 3) << parts << " parts";
  }
}

// The exchange inside the fluid's step (compute_sums, step_fluid) against the exchange around it
// (compute, step, inject), on a real fluid: 600 particles random-walk over a D2Q7 box with walls
// (and 500 over a periodic D3Q19 box), a few to a node, some anchored (or none: inside the step
// each node's u* is then written over its sums and its gain is not kept), 2% moving a step (so
// that listings are kept, with nodes listed since, and made afresh), for 30 steps in 1 and 3
// parts. Inside the step, a kept listing gives what a fresh one gives, bit for bit (a third fluid,
// exchanged each step by a new exchange that keeps its gains: the same values, stored apart).
// Around and inside the step, each particle's dP, each anchor's share, each node's gain and
// every population agree to round-off; the bound is
// the one of tests/fluid/in_step_exchange_test.cpp (the fluid read after the collision instead of
// before it: a few 1e-15 here, where the momenta compared are 1e-3 and the populations 1e-2).
template <class L>
void expect_in_step_exchange_alike(const fluid::FluidConfig& config, long particles, bool anchors) {
  constexpr int D = L::D;
  const int nx = config.nx, ny = config.ny, nz = config.nz;
  parallel::ThreadPool pool(3);
  for (int parts : {1, 3}) {
    std::mt19937 random(11);
    std::uniform_int_distribution<long> any_cell(0, static_cast<long>(nx) * ny * nz - 1);
    std::uniform_real_distribution<double> uniform(0.5, 1.5);
    std::vector<CellIndex> cells;
    std::vector<double> mass, momentum;
    std::vector<char> anchored;
    for (long p = 0; p < particles; ++p) {
      cells.push_back(static_cast<CellIndex>(any_cell(random) / 3 * 3));  // about three a node
      mass.push_back(uniform(random));
      for (int a = 0; a < D; ++a) momentum.push_back(0.01 * (uniform(random) - 1));
      anchored.push_back(anchors && p % 53 == 0);
    }
    fluid::FluidConfig c = config;
    c.threads = parts;
    c.layout = fluid::PopulationLayout::kArrays;  // the same on every host (blocks need AVX-512)
    fluid::FluidLattice<L, double> around(c, nullptr), inside(c, nullptr), inside_fresh(c, nullptr);
    ASSERT_TRUE(inside.can_exchange_in_step());
    const auto density = [](int x, int y, int z) { return 1.0 + 0.01 * std::sin(0.7 * x + 1.3 * y + 0.4 * z); };
    const auto velocity = [](int x, int y, int) { return Vec3{0.02 * std::cos(0.5 * y), 0.01 * std::sin(0.3 * x), 0}; };
    for (auto* f : {&around, &inside, &inside_fresh}) f->initialize(density, velocity);
    MomentumExchange apart({nx, ny, nz}, ExchangeRule::kCommonVelocity), in_step({nx, ny, nz}, ExchangeRule::kCommonVelocity);
    parallel::ThreadPool* on = parts > 1 ? &pool : nullptr;
    int kept = 0, relisted = 0;
    for (int step = 0; step < 30; ++step) {
      for (auto& cell : cells)
        if (random() % 50 == 0) cell = static_cast<CellIndex>(any_cell(random));
      const auto cell_of = [&](long p) { return cells[p]; };
      apart.locate(particles, cell_of, on, parts);
      in_step.locate(particles, cell_of, on, parts);
      const std::vector<char>* anchors_if_any = anchors ? &anchored : nullptr;
      apart.compute(mass, {momentum.data(), D}, around, on, parts, anchors_if_any);
      around.step();
      apart.inject(around, on);
      in_step.compute_sums(mass, {momentum.data(), D}, on, parts, anchors_if_any);
      in_step.step_fluid(inside);
      (in_step.relisted() ? relisted : kept) += 1;
      MomentumExchange fresh({nx, ny, nz}, ExchangeRule::kCommonVelocity);
      fresh.keep_gains(true);
      fresh.locate(particles, cell_of, on, parts);
      fresh.compute_sums(mass, {momentum.data(), D}, on, parts, anchors_if_any);
      fresh.step_fluid(inside_fresh);
      const std::string context = std::string(L::name) + ", " + std::to_string(parts) + " parts, step " + std::to_string(step);
      for (long p = 0; p < particles; ++p) {
        Vec3 psi{0, 0, 0};
        for (int a = 0; a < D; ++a) psi[a] = momentum[D * p + a];
        const Vec3 a = apart.particle_dp<D>(p, psi, mass[p]), b = in_step.particle_dp<D>(p, psi, mass[p]);
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(a[k], b[k], 1e-13) << context << ", particle " << p;
        ASSERT_EQ(b, fresh.particle_dp<D>(p, psi, mass[p])) << context << ", particle " << p;
        if (anchored[p]) {
          const Vec3 sa = apart.anchor_dp(p), sb = in_step.anchor_dp(p);
          for (int k = 0; k < 3; ++k) ASSERT_NEAR(sa[k], sb[k], 1e-13) << context << ", anchor " << p;
        }
      }
      if (!anchors) {
        ASSERT_THROW(in_step.exchanged(), std::logic_error) << context;
      }
      const ExchangedNodes nodes_apart = apart.exchanged(), nodes_in_step = (anchors ? in_step : fresh).exchanged();
      ASSERT_EQ(nodes_apart.nodes, nodes_in_step.nodes) << context;
      for (long n = 0; n < nodes_apart.size(); ++n)
        for (int k = 0; k < 3; ++k)
          ASSERT_NEAR(nodes_apart.gained[n][k], nodes_in_step.gained[n][k], 1e-13) << context << ", node " << n;
      const std::vector<double> fa = around.raw_state().populations, fb = inside.raw_state().populations;
      for (std::size_t i = 0; i < fa.size(); ++i) ASSERT_NEAR(fa[i], fb[i], 1e-13) << context << ", value " << i;
      ASSERT_EQ(fb, inside_fresh.raw_state().populations) << context;
    }
    EXPECT_GT(kept, 5) << parts << " parts";
    EXPECT_GT(relisted, 0) << parts << " parts";
  }
}

TEST(MomentumExchange, InsideTheStepAgreesWithAroundIt) {
  for (bool anchors : {true, false}) {
    expect_in_step_exchange_alike<lattice::D2Q7>(box(24, 14, 1, true), 600, anchors);
    expect_in_step_exchange_alike<lattice::D3Q19>(box(32, 10, 6, false), 500, anchors);
  }
}

// The pairwise rule reads the node's density for each particle after the fluid's read: not inside
// the step.
TEST(MomentumExchange, PairwiseRuleIsNotDoneInsideTheStep) {
  fluid::FluidLattice<lattice::D2Q9, double> fluid(box(8, 8, 1, false));
  MomentumExchange pairwise({8, 8, 1}, ExchangeRule::kPairwise);
  const std::vector<double> mass{1.0};
  std::vector<double> momentum{0.01, 0.0};
  pairwise.locate(1, [](long) { return CellIndex{9}; });
  pairwise.compute_sums(mass, {momentum.data(), 2});
  EXPECT_THROW(pairwise.step_fluid(fluid), std::logic_error);
}


// Periodic box, no walls, no loads: fluid plus solid momentum is conserved to round-off.
void check_coupled_momentum(scene::LatticeKind lattice) {
  scene::Scene s;
  s.lattice = lattice;
  const bool three_d = lattice == scene::LatticeKind::kD3Q19;
  s.fluid = box(16, 12, three_d ? 8 : 1, false);
  s.fluid.omega = 1.2;
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 2.5;
  disk.centre = {6.2, 5.1, three_d ? 3.7 : 0.0};
  disk.velocity = {0.04, -0.02, three_d ? 0.01 : 0.0};
  disk.spacing = 0.7;  // some nodes carry several particles
  s.bodies.push_back(disk);
  solid::BodySpec chain;
  chain.shape = solid::BodyShape::kChain;
  chain.length = 6;
  chain.axis = 1;
  chain.centre = {12.3, 6.0, three_d ? 2.0 : 0.0};
  chain.velocity = {-0.03, 0, 0};
  s.bodies.push_back(chain);
  auto sim = scene::build_simulation(s);
  EXPECT_EQ(sim->stages(), (std::vector<std::string>{"exchange", "fluid", "solid"}));
  const Vec3 p0 = sim->totals().momentum();
  double worst = 0, moved = 0;
  for (int step = 0; step < 1000; ++step) {
    sim->step();
    if (step % 50 != 49) continue;
    const auto t = sim->totals();
    const Vec3 p = t.momentum();
    for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(p[a] - p0[a]));
    moved = std::max(moved, std::abs(t.fluid_momentum[0]));
  }
  report(std::string("coupled momentum drift over 1000 steps, ") + scene::lattice_kind_name(lattice), worst, 1e-12);
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(moved, 0.05) << "the solid must have given the fluid momentum for the check to mean anything";
}

TEST(CoupledMomentum, ConservedInPeriodicBoxD2Q9) { check_coupled_momentum(scene::LatticeKind::kD2Q9); }
TEST(CoupledMomentum, ConservedInPeriodicBoxD2Q7) { check_coupled_momentum(scene::LatticeKind::kD2Q7); }
TEST(CoupledMomentum, ConservedInPeriodicBoxD3Q19) { check_coupled_momentum(scene::LatticeKind::kD3Q19); }

// The fluid kernel splits rows over threads, and so do the per-particle stages (nearest node,
// forces, the solid's update), the exchange (by node) and the injection into the fluid. A coupled
// run must not depend on the thread count at all: every population, position, link vector and
// momentum (and the density and velocity fields, read in parts as well) is compared, after an
// even number of steps and an odd one (the in-place scheme stores
// populations differently on the two), on D2Q7 with walls (contact), on D2Q9 with four particles
// a node (spacing 1/2: nodes with several particles), on D3Q19, and with rotating bodies.
void expect_same_run_with_threads(scene::Scene s) {
  struct Run {
    scene::SimulationState state;
    scene::FluidFields fields;     // read in parts too
    std::vector<Vec3> torques;     // recorded in parts (scenes with a rotating body)
  };
  auto run = [&](int threads, long steps) {
    s.fluid.threads = threads;
    auto sim = scene::build_simulation(s);
    sim->run(steps);
    std::vector<Vec3> torques;
    for (int b = 0; b < sim->solid()->body_count(); ++b) torques.push_back(sim->body_state(b).torque);
    return Run{sim->save_state(), sim->fluid_fields(), torques};
  };
  for (long steps : {300L, 301L}) {
    const auto one_run = run(1, steps), three_run = run(3, steps);
    const auto &one = one_run.state, &three = three_run.state;
    EXPECT_EQ(one_run.fields.density, three_run.fields.density) << steps;
    EXPECT_EQ(one_run.fields.velocity, three_run.fields.velocity) << steps;
    EXPECT_EQ(one.fluid.populations, three.fluid.populations) << steps;
    ASSERT_EQ(one.solid.positions.size(), three.solid.positions.size());
    EXPECT_EQ(one.solid.positions, three.solid.positions) << steps;
    EXPECT_EQ(one.solid.incoming, three.solid.incoming) << steps;
    EXPECT_EQ(one.solid.momentum, three.solid.momentum) << steps;
    EXPECT_EQ(one_run.torques, three_run.torques) << steps;
    EXPECT_GT(one.solid.positions.size(), 20u);  // enough particles for three parts to differ
  }
}

TEST(CoupledMomentum, ThreadCountDoesNotChangeACoupledRun) {
  scene::Scene s;
  s.lattice = scene::LatticeKind::kD2Q7;
  s.fluid = box(24, 16, 1, true);
  solid::BodySpec disk;
  disk.shape = solid::BodyShape::kDisk;
  disk.radius = 3;
  disk.centre = {8, 6.5, 0};
  disk.load = {1e-4, 2e-5, 0};
  s.bodies.push_back(disk);
  expect_same_run_with_threads(s);

  scene::Scene dense;
  dense.fluid = box(16, 12, 1, false);
  solid::BodySpec sheet;
  sheet.size = {8, 6, 1};
  sheet.spacing = 0.5;
  sheet.centre = {6.5, 5.5, 0};
  sheet.velocity = {0.02, 0.01, 0};
  dense.bodies.push_back(sheet);
  expect_same_run_with_threads(dense);

  scene::Scene ball;
  ball.lattice = scene::LatticeKind::kD3Q19;
  ball.fluid = box(12, 12, 12, false);
  solid::BodySpec sphere;
  sphere.shape = solid::BodyShape::kDisk;  // a ball in 3D
  sphere.radius = 2;
  sphere.centre = {5, 5, 5};
  sphere.load = {1e-4, 0, 2e-5};
  ball.bodies.push_back(sphere);
  expect_same_run_with_threads(ball);

  // Rotating bodies: their frames turn, and their node momenta are worked out, body by body in
  // parts. Three chains and a disk, spinning, in the D2Q7 box with walls.
  scene::Scene turning;
  turning.lattice = scene::LatticeKind::kD2Q7;
  turning.fluid = box(24, 16, 1, true);
  for (int c = 0; c < 3; ++c) {
    solid::BodySpec chain;
    chain.shape = solid::BodyShape::kChain;
    chain.length = 5;
    chain.centre = {5.0 + 6 * c, 10.5, 0};
    chain.angular_velocity = {0, 0, 0.01 * (c + 1)};
    chain.rotation = true;
    turning.bodies.push_back(chain);
  }
  disk.rotation = true;
  disk.angular_velocity = {0, 0, -0.01};
  turning.bodies.push_back(disk);
  expect_same_run_with_threads(turning);
}

// Dense packing, 4 particles per node: the common-velocity exchange stays bounded (it only ever
// averages velocities), while eq. 14 applied pair by pair over-corrects and grows without bound.
TEST(CoupledMomentum, DensePackingBoundedOnlyWithCommonVelocity) {
  auto run = [](ExchangeRule rule) {
    scene::Scene s;
    s.fluid = box(12, 12, 1, false);
    solid::BodySpec sheet;
    sheet.size = {8, 8, 1};
    sheet.spacing = 0.5;  // particles at node +- 1/4: four per node
    sheet.centre = {5.5, 5.5, 0};
    sheet.velocity = {0.05, 0.02, 0};
    s.bodies.push_back(sheet);
    s.exchange = rule;
    auto sim = scene::build_simulation(s);
    double peak = 0;
    for (int step = 0; step < 200; ++step) {
      sim->step();
      for (int p = 0; p < sim->solid()->particle_count(); ++p) {
        const Vec3 u = sim->particle_velocity(p);
        const double speed = std::hypot(u[0], u[1]);
        peak = std::isfinite(speed) ? std::max(peak, speed) : INFINITY;
      }
      if (!std::isfinite(peak)) break;
    }
    return peak;
  };
  const double common = run(ExchangeRule::kCommonVelocity), pairwise = run(ExchangeRule::kPairwise);
  const double start = std::hypot(0.05, 0.02);
  report("common velocity: peak particle speed / initial", common / start, 1.0 + 1e-12);
  report("pairwise eq. 14: peak particle speed / initial", pairwise / start, 10.0);
  EXPECT_LE(common, start * (1 + 1e-12));
  EXPECT_GT(pairwise, 10 * start);
}

}  // namespace
}  // namespace lbsolid::coupling
