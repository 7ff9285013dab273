// The two ways a cell update can run (fluid/cell_update.h): all Q populations collided together,
// or read again and relaxed a pair of opposite directions at a time (what D3Q19 BGK runs). The
// second must compute what the first does, with and without force and wall corrections, and in
// place where each cell writes into the slots it read (out[i] = in[opp(i)]): a pair must read
// both its slots before writing either. The source arithmetic is the same, but GCC contracts
// a * b + c into one fused multiply-add where it sees fit, and may choose differently in the two
// loops (it does for D2Q9 with force and corrections here). So the bound: every quantity is of
// order 1 at most (rho ~ 1, populations ~ 0.02 here), and a different fusing changes a handful
// of roundings of at most 2^-52 each; 2e-15 allows about ten. A slot read after its pair wrote
// it, or a wrong term, would be off by the size of a population (~1e-2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "fluid/cell_update.h"
#include "lattice/d2q9.h"
#include "lattice/d3q19.h"

namespace lbsolid::fluid {
namespace {

template <class L, bool kForce, bool kCorrections>
void expect_pairs_equal_together(bool in_place) {
  constexpr int Q = L::Q;
  constexpr long kCells = 37;  // not a multiple of any vector width: the loop tails run too
  constexpr auto opp = lattice::opposite_table<L>();
  std::mt19937_64 random(7 + Q + 2 * kForce + kCorrections + 4 * in_place);
  std::uniform_real_distribution<double> deviation(-0.02, 0.02);
  std::vector<double> source(Q * kCells);
  for (double& v : source) v = deviation(random);
  // Walls shift populations, and scale them (cell_update.h: WallMap; 0 at a pressure outlet).
  auto in_map = WallMap<double, Q>::identity(), out_map = WallMap<double, Q>::identity();
  for (int i = 0; kCorrections && i < Q; ++i) {
    in_map.shift[i] = deviation(random);
    out_map.shift[i] = deviation(random);
    in_map.scale[i] = i % 3 == 1 ? 0.0 : 1.0;
    out_map.scale[i] = i % 4 == 2 ? 0.0 : 1.0;
  }
  const double force[3] = {kForce ? 1e-3 : 0.0, kForce ? -2e-3 : 0.0, kForce && L::D == 3 ? 5e-4 : 0.0};
  const double omega = 1.3, rho0 = 1.0;

  auto run = [&](bool by_pairs) {
    std::vector<double> a = source, b(Q * kCells, 0.0);
    const double* in[Q];
    double* out[Q];
    for (int i = 0; i < Q; ++i) {
      in[i] = a.data() + i * kCells;
      out[i] = in_place ? a.data() + opp[i] * kCells : b.data() + i * kCells;
    }
    using Bgk = BgkCollision<L, double>;
    if (by_pairs)
      update_cells_by_pairs<L, double, Bgk, kForce, kCorrections>(in, in_map, out, out_map, force, omega,
                                                                  rho0, 0, kCells);
    else
      update_cells_together<L, double, Bgk, kForce, kCorrections>(in, in_map, out, out_map, force, omega,
                                                                  rho0, 0, kCells);
    return in_place ? a : b;
  };
  const std::vector<double> together = run(false), pairs = run(true);
  ASSERT_NE(together, source) << "the update changed nothing";
  double worst = 0;
  for (std::size_t k = 0; k < together.size(); ++k) worst = std::max(worst, std::abs(together[k] - pairs[k]));
  EXPECT_LE(worst, 2e-15) << L::name << " force " << kForce << " corrections " << kCorrections << " in place "
                          << in_place;
}

template <class L>
void expect_all_variants() {
  for (bool in_place : {false, true}) {
    expect_pairs_equal_together<L, false, false>(in_place);
    expect_pairs_equal_together<L, true, false>(in_place);
    expect_pairs_equal_together<L, false, true>(in_place);
    expect_pairs_equal_together<L, true, true>(in_place);
  }
}

TEST(CellUpdate, ByPairsComputesTheJointUpdate) {
  expect_all_variants<lattice::D3Q19>();
  expect_all_variants<lattice::D2Q9>();
}

}  // namespace
}  // namespace lbsolid::fluid
