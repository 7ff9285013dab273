// Decaying shear wave u = A e^{-nu k^2 t} sin(k.r) t_hat: the viscosity fitted from the decay rate
// must match the BGK viscosity (1/omega - 1/2) c_s^2, and on D2Q7 it must not depend on direction.
#include <gtest/gtest.h>

#include "fluid/fluid_test_support.h"

namespace lbsolid::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Wave {
  Vec3 k;       // wave vector
  Vec3 t_hat;   // unit velocity direction, perpendicular to k
};

// Projection of the velocity field on sin(k.r) t_hat: the wave's current amplitude.
template <class F>
double amplitude(const F& fluid, const Wave& wave) {
  const auto& c = fluid.config();
  double sum = 0;
  for (int z = 0; z < c.nz; ++z)
    for (int y = 0; y < c.ny; ++y)
      for (int x = 0; x < c.nx; ++x) {
        const Vec3 r = F::position(x, y, z);
        const Vec3 u = fluid.velocity(x, y, z);
        const double phase = wave.k[0] * r[0] + wave.k[1] * r[1] + wave.k[2] * r[2];
        sum += (u[0] * wave.t_hat[0] + u[1] * wave.t_hat[1] + u[2] * wave.t_hat[2]) * std::sin(phase);
      }
  return 2.0 * sum / static_cast<double>(fluid.cells());
}

// Runs the wave for about one decay time and returns the viscosity fitted from ln A(t).
template <class L>
double fitted_viscosity(FluidConfig c, const Wave& wave) {
  FluidLattice<L, double> fluid(c);
  const double a0 = 1e-3;
  fluid.initialize([](int, int, int) { return 1.0; },
                   [&](int x, int y, int z) {
                     const Vec3 r = FluidLattice<L, double>::position(x, y, z);
                     const double s = a0 * std::sin(wave.k[0] * r[0] + wave.k[1] * r[1] + wave.k[2] * r[2]);
                     return Vec3{s * wave.t_hat[0], s * wave.t_hat[1], s * wave.t_hat[2]};
                   });
  const double k2 = wave.k[0] * wave.k[0] + wave.k[1] * wave.k[1] + wave.k[2] * wave.k[2];
  const long decay_steps = static_cast<long>(1.0 / (bgk_viscosity<L>(c.omega) * k2));
  // Skip the first steps: the equilibrium start lacks the non-equilibrium part of a shear flow.
  const long skip = 50;
  const long samples = 20;
  fluid.run(skip);
  std::vector<double> t, log_a;
  for (long s = 0; s <= samples; ++s) {
    t.push_back(static_cast<double>(fluid.step_count()));
    log_a.push_back(std::log(amplitude(fluid, wave)));
    fluid.run(decay_steps / samples + 1);
  }
  return -fit_line(t, log_a).slope / k2;
}

template <class L>
class ShearWaveTest : public ::testing::Test {};
using Lattices = ::testing::Types<D2Q9, D2Q7, D3Q19>;
TYPED_TEST_SUITE(ShearWaveTest, Lattices);

TYPED_TEST(ShearWaveTest, ViscosityFromDecayRateMatchesBgk) {
  using L = TypeParam;
  FluidConfig c;
  c.nx = 64;
  c.ny = 2;  // even, so D2Q7 can be periodic in y
  c.nz = L::D == 3 ? 2 : 1;
  const Wave wave{{2 * kPi / c.nx, 0, 0}, {0, 1, 0}};
  for (double omega : {0.6, 1.0, 1.6}) {
    c.omega = omega;
    const double ratio = fitted_viscosity<L>(c, wave) / bgk_viscosity<L>(omega);
    report(std::string(L::name) + " shear-wave viscosity error, omega " + std::to_string(omega),
           std::abs(ratio - 1), 0.01);
    EXPECT_NEAR(ratio, 1.0, 0.01) << "omega " << omega;
  }
}

TEST(HexagonalIsotropyTest, ShearWavesAtZeroAndSixtyDegreesDecayAlike) {
  // Box 96 x 64 rows: both waves below are periodic on it with |k| = 4 pi / 96.
  FluidConfig c;
  c.nx = 96;
  c.ny = 64;
  const double k = 4 * kPi / 96;
  const double s = D2Q7::half_sqrt3;
  for (double omega : {0.6, 1.0, 1.6}) {
    c.omega = omega;
    const double along_0 = fitted_viscosity<D2Q7>(c, {{k, 0, 0}, {0, 1, 0}});
    const double along_60 = fitted_viscosity<D2Q7>(c, {{0.5 * k, s * k, 0}, {-s, 0.5, 0}});
    report("D2Q7 0 vs 60 degree decay mismatch, omega " + std::to_string(omega),
           std::abs(along_60 / along_0 - 1), 0.01);
    EXPECT_NEAR(along_60 / along_0, 1.0, 0.01) << "omega " << omega;
    EXPECT_NEAR(along_0 / bgk_viscosity<D2Q7>(omega), 1.0, 0.01) << "omega " << omega;
  }
}

}  // namespace
}  // namespace lbsolid::testing
