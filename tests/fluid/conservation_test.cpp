// Mass and momentum: conserved to round-off in a periodic box; with a body force the momentum
// grows by exactly F per node per step (the forcing scheme's defining property).
#include <gtest/gtest.h>

#include <random>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

template <class L>
FluidConfig periodic_box() {
  FluidConfig c;
  c.nx = L::D == 3 ? 12 : 32;
  c.ny = L::D == 3 ? 12 : 32;
  c.nz = L::D == 3 ? 12 : 1;
  c.omega = 1.2;
  return c;
}

// Random velocities with |u| < 0.05 and a density within 1% of 1.
template <class F>
void randomize(F& fluid, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto& c = fluid.config();
  const int D = F::Lattice::D;
  std::vector<Vec3> u(fluid.cells());
  std::vector<double> rho(fluid.cells());
  for (long k = 0; k < fluid.cells(); ++k) {
    Vec3 v{0, 0, 0};
    do {
      for (int a = 0; a < D; ++a) v[a] = 0.05 * unit(rng);
    } while (std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) >= 0.05);
    u[k] = v;
    rho[k] = 1.0 + 0.01 * unit(rng);
  }
  auto index = [&](int x, int y, int z) { return x + static_cast<long>(c.nx) * (y + static_cast<long>(c.ny) * z); };
  fluid.initialize([&](int x, int y, int z) { return rho[index(x, y, z)]; },
                   [&](int x, int y, int z) { return u[index(x, y, z)]; });
}

template <class L>
class ConservationTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(ConservationTest, Lattices);

TYPED_TEST(ConservationTest, MassAndMomentumConservedOverTenThousandSteps) {
  FluidLattice<TypeParam, double> fluid(periodic_box<TypeParam>());
  randomize(fluid, 7);
  const double mass0 = fluid.total_mass();
  const Vec3 p0 = fluid.total_momentum();
  ASSERT_GT(std::abs(p0[0]) + std::abs(p0[1]), 1e-3) << "the random state should carry momentum";
  fluid.run(10000);
  const double drift = std::abs(fluid.total_mass() - mass0) / mass0;
  report(std::string(TypeParam::name) + " relative mass drift, 1e4 steps", drift, 1e-12);
  EXPECT_LT(drift, 1e-12);
  const Vec3 p = fluid.total_momentum();
  // Momentum is compared per unit mass (lattice units), the scale of one node moving at speed 1.
  double worst = 0;
  for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(p[a] - p0[a]) / mass0);
  report(std::string(TypeParam::name) + " momentum drift per unit mass, 1e4 steps", worst, 1e-12);
  EXPECT_LT(worst, 1e-12);
}

TYPED_TEST(ConservationTest, MomentumGrowsByExactlyTheBodyForcePerStep) {
  FluidConfig c = periodic_box<TypeParam>();
  c.body_force = {2e-6, -1e-6, TypeParam::D == 3 ? 3e-6 : 0.0};
  FluidLattice<TypeParam, double> fluid(c);
  randomize(fluid, 11);
  const double mass0 = fluid.total_mass();
  const Vec3 p0 = fluid.total_momentum();
  const long steps = 1000;
  fluid.run(steps);
  const Vec3 p = fluid.total_momentum();
  double worst = 0;
  for (int a = 0; a < 3; ++a) {
    const double expected = steps * static_cast<double>(fluid.cells()) * c.body_force[a];
    worst = std::max(worst, std::abs((p[a] - p0[a]) - expected) / mass0);
  }
  report(std::string(TypeParam::name) + " momentum gain minus N F t, per unit mass", worst, 1e-12);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(std::abs(fluid.total_mass() - mass0) / mass0, 1e-12);
}

}  // namespace
}  // namespace lbsolid::testing
